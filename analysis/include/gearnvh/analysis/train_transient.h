// Whether a run's transient lets the start from the static state die out. The train held in drive
// contact at its first segments (every mesh at segment 0's stiffness, tooth friction left out)
// has the generator A = [[0, I], [-M^-1 K, -M^-1 C]]; each oscillatory mode (an eigenvalue lambda
// with Im lambda > 0) decays as e^(Re lambda t). The free rotation and the fixed shafts (zeros:
// |lambda|
// <= 1e-6 of the largest) and a viscous drag's damped rotation (real) are left out, as are modes
// with a damping ratio -Re lambda / |lambda| below 1e-3 (undamped for this purpose: no transient
// removes them).
#pragma once

#include <optional>
#include <string>

#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

struct DecayingMode {
  double frequency_hz = 0.0;  // |Im lambda| / 2 pi
  double decay_rate = 0.0;    // -Re lambda, 1/s (> 0)
};

// The oscillatory mode that decays slowest; nullopt when there is none.
std::optional<DecayingMode> SlowestDecayingMode(const TrainTables& tables);

// A warning when the transient (`transient_s` seconds, `transient_cycles` cycles of the first
// mesh, which `option` counts) is shorter than three decay times of the slowest mode (more than 5 %
// of the start would be left in the record); empty otherwise. `option` names what sets the
// transient.
std::string TransientDecayWarning(const TrainTables& tables, double transient_s,
                                  long transient_cycles, const std::string& option);

}  // namespace gearnvh
