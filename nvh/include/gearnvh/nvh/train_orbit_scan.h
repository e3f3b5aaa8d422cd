// Periodic orbits of a gear train along a list of train variants (natural-parameter
// continuation) for `gearnvh orbits` on schema gearnvh/2. At each variant: the orbit of the
// previous variant (same state dimension) is the first guess; if Newton (train_periodic_orbit.h)
// fails from it, or at the first variant, the settled state of an exact run from the static state
// (the transient rounded up to whole orbit periods, so the phase is right) and the states one, two,
// ... orbit periods later are tried. Multipliers are those of TrainOrbit: on the quotient by the
// free rotation (its two neutral directions, multiplier 1 and its Jordan partner, are removed;
// its angle only when a viscous drag damps its speed), 2n - 2 of them (2n - 1 then; less 2 per
// fixed shaft), by decreasing modulus.
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/train_periodic_orbit.h"

namespace gearnvh {

struct TrainOrbitScanOptions {
  int periods = 1;              // the orbit's period in common periods of the train; >= 1
  long transient_cycles = 300;  // cycles of the first mesh settled before the first guess; >= 0
  int settled_starts = 4;       // settled guesses tried when continuation fails; >= 1
  EventMethod events = EventMethod::kSpectral;
  Tier tier = Tier::kTier1;  // the train solver's tier (BuildTrainTablesAtTier)
  // Checked before each variant (ScanTrainPeriodicOrbits throws RunCancelled) and passed to its
  // runs (TrainStepperOptions::cancel). Not owned; null: never cancelled.
  const std::atomic<bool>* cancel = nullptr;
  void Validate() const;  // throws InputError naming the field
};

struct TrainOrbitScanPoint {
  bool ok = false;      // the variant could be built and run
  std::string message;  // why it failed, or why no orbit was found
  enum class Start { kNone, kContinuation, kSettled };
  Start start = Start::kNone;  // which guess converged (kNone: no orbit found)
  int settled_periods = 0;     // kSettled: orbit periods run after the settled transient
  double common_period = 0.0;  // s; 0 when the train has none
  TrainOrbit orbit;
  bool found() const { return start != Start::kNone; }
};
// "continuation", "settled run + k periods" or "" (not found).
std::string TrainOrbitStartText(const TrainOrbitScanPoint& p);

// variant(i) for i = 0 .. count-1 (it may throw InputError: that point fails, the others go on).
using TrainVariant = std::function<TrainSpec(int)>;
using TrainOrbitScanProgress = std::function<void(int done, int total)>;

std::vector<TrainOrbitScanPoint> ScanTrainPeriodicOrbits(
    int count, const TrainVariant& variant, const TrainOrbitScanOptions& options,
    const TrainOrbitScanProgress& progress = {});

}  // namespace gearnvh
