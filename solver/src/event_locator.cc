#include "gearnvh/solver/event_locator.h"

#include <cmath>
#include <limits>

#include "gearnvh/solver/spectral_locator.h"
#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

EventLocator::EventLocator(const SegmentTables& tables, const SolverOptions& options)
    : t_(tables),
      gap_tolerance_(1e-12 * tables.half_backlash),
      grazing_rate_tolerance_(options.grazing_rate_tolerance),
      cancel_(options.cancel) {}

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
