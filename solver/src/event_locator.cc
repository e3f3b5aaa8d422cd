#include "gearnvh/solver/event_locator.h"

#include <cmath>
#include <limits>

#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

int ActiveWalls(const SegmentSystem& sys, ContactState state, GapWall out[kMaxWalls]) {
  switch (state) {
    case ContactState::kFree:
      out[0] = {&sys.gap_drive, &sys.gap_drive_rate, 1.0, ContactState::kDrive, 0};
      out[1] = {&sys.gap_back, &sys.gap_back_rate, -1.0, ContactState::kBack, 1};
      return 2;
    case ContactState::kDrive:
      out[0] = {&sys.gap_drive, &sys.gap_drive_rate, -1.0, ContactState::kFree, 0};
      return 1;
    case ContactState::kBack:
      out[0] = {&sys.gap_back, &sys.gap_back_rate, 1.0, ContactState::kFree, 1};
      return 1;
  }
  return 0;
}

const Eigen::RowVectorXd& GapRow(const SegmentSystem& sys, int gap) {
  return gap == 0 ? sys.gap_drive : sys.gap_back;
}

EventLocator::EventLocator(const SegmentTables& tables, const SolverOptions& options)
    : t_(tables),
      gap_tolerance_(1e-12 * tables.half_backlash),
      grazing_rate_tolerance_(options.grazing_rate_tolerance) {}

double EventLocator::WallTolerance(const Eigen::RowVectorXd& row, const Eigen::VectorXd& z) const {
  double magnitude = 0.0;
  for (Eigen::Index i = 0; i < row.size(); ++i) magnitude += std::abs(row[i] * z[i]);
  return gap_tolerance_ + 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
}

int EventLocator::Outside(const SegmentSystem& sys, ContactState state, const Eigen::VectorXd& z,
                          bool with_tolerance) const {
  GapWall walls[kMaxWalls];
  const int count = ActiveWalls(sys, state, walls);
  for (int i = 0; i < count; ++i) {
    const double tolerance = with_tolerance ? WallTolerance(*walls[i].row, z) : 0.0;
    if (walls[i].sign * walls[i].row->dot(z) > tolerance) return i;
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

bool SubstepLocator::PossibleEvent(const SegmentSystem& sys, const LocatorState& state,
                                   bool segment_start) const {
  GapWall walls[kMaxWalls];
  const int count = ActiveWalls(sys, state.contact, walls);
  for (int i = 0; i < count; ++i) {
    const GapWall& w = walls[i];
    // The gap rows change at a segment boundary (e_j): the start itself may be outside.
    if (segment_start && w.sign * w.row->dot(state.z) > WallTolerance(*w.row, state.z)) {
      return true;
    }
    if (w.sign * w.row->dot(z1_) > 0.0) return true;  // crossed by the end of the sub-step
    // Turned towards the wall and back inside the sub-step: an interior extremum to examine.
    if (w.sign * w.rate->dot(state.z) > 0.0 && w.sign * w.rate->dot(z1_) < 0.0) return true;
  }
  return false;
}

bool SubstepLocator::DoStep(int segment, double start, LocatorState& state, EventHandler& handler) {
  const int n = t_.substeps[segment];
  const double d = t_.SegmentLength(segment) / n;
  for (int i = 0; i < n; ++i) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state.contact)];
    z1_.noalias() = sys.substep * state.z;
    ++state.matvecs;
    if (!PossibleEvent(sys, state, i == 0)) {
      state.z.swap(z1_);
      if (state.tangent != nullptr) state.tangent->Propagate(sys.substep);
    } else if (!Examine(segment, start + i * d, state, handler)) {
      return false;
    }
  }
  return true;
}

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
