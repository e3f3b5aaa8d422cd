#include "gearnvh/solver/event_locator.h"

#include <cmath>
#include <limits>

#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

EventLocator::EventLocator(const SegmentTables& tables, const SolverOptions& options)
    : t_(tables),
      gap_tolerance_(1e-12 * tables.half_backlash),
      grazing_rate_tolerance_(options.grazing_rate_tolerance) {}

int EventLocator::Outside(const SegmentSystem& sys, ContactState state, const Eigen::VectorXd& z,
                          bool with_tolerance) const {
  GapWall walls[kMaxWalls];
  const int count = ActiveWalls(sys, state, walls);
  for (int i = 0; i < count; ++i) {
    const double gap = walls[i].sign * walls[i].row->dot(z);
    if (with_tolerance ? BeyondTolerance(gap, *walls[i].row, z) : gap > 0.0) return i;
  }
  return -1;
}

bool EventLocator::SwitchIfOutsideAtStart(int segment, double start, LocatorState& state,
                                          EventHandler& handler) const {
  // At most two switches: free -> contact, and a contact state can never be outside its own wall
  // right after entering it.
  for (int guard = 0; guard < 2; ++guard) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state.contact)];
    const int outside = Outside(sys, state.contact, state.z, true);
    if (outside < 0) return true;
    GapWall walls[kMaxWalls];
    ActiveWalls(sys, state.contact, walls);
    if (!handler.Switch(segment, sys, walls[outside], start, /*state_triggered=*/false)) {
      return false;
    }
  }
  return true;
}

SubstepLocator::SubstepLocator(const SegmentTables& tables, const SolverOptions& options)
    : EventLocator(tables, options), z1_(tables.m) {}

std::unique_ptr<EventLocator> MakeEventLocator(const SegmentTables& tables,
                                               const SolverOptions& options) {
  switch (options.events) {
    case EventMethod::kDyadic:
      return std::make_unique<DyadicLocator>(tables, options);
    case EventMethod::kTaylor:
      return std::make_unique<TaylorLocator>(tables, options);
    case EventMethod::kSpectral:
      break;
  }
  return std::make_unique<SpectralLocator>(tables, options);
}

}  // namespace gearnvh
