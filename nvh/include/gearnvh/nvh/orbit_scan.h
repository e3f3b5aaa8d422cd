// Periodic orbits along one schema parameter (natural-parameter continuation) for
// `gearnvh orbits`. At each value: the orbit from the previous value is the first guess; if
// Newton fails from it (or at the first value) the settled state of an exact run (transient
// rounded up to whole periods, so the phase is right) and the states one, two, ... periods later
// are tried. Each point records which start converged and the orbit's stability.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/nvh/periodic_orbit.h"

namespace gearnvh {

struct OrbitScanOptions {
  Tier tier = Tier::kTier1;
  int period = 1;               // multiples of the base period; >= 1
  long transient_cycles = 300;  // settling before the first guess; >= 0
  int settled_starts = 4;       // settled guesses tried when continuation fails; >= 1
  EventMethod events = EventMethod::kSpectral;  // V3; V2 and V1 to validate
  // Cancellation (SolverOptions::cancel): once set, the point in flight and the rest fail with
  // the message "cancelled". Not owned; may be null.
  const std::atomic<bool>* cancel = nullptr;
  // How an input error of a point is worded, given the parameters the point's variant was set to:
  // the library's message names its own fields ("tier") and SI values; the app words it at the
  // path or keyword the user set, with the axis's value in the unit it is shown in. Empty: what().
  std::function<std::string(const InputError&, const std::vector<ParameterValue>&)>
      input_error_message;
  void Validate() const;
};

struct OrbitScanPoint {
  double value = 0.0;  // parameter value (SI); the file's value without a sweep
  bool ok = false;     // the gearbox variant could be built and run
  std::string message;
  std::string start;  // "continuation" | "settled run + k periods" | "" (not found)
  PeriodicOrbit orbit;
};

using OrbitScanProgress = std::function<void(int, int)>;

// `sweep` empty: one point at the file's parameters.
std::vector<OrbitScanPoint> ScanPeriodicOrbits(const GearboxSpec& base,
                                               const std::optional<AtlasAxis>& sweep,
                                               const OrbitScanOptions& options,
                                               const OrbitScanProgress& progress = {});

}  // namespace gearnvh
