// Parts of RunWhine (whine.h) beside its sweep: the housing transfer (a table's curves resolved to
// the bearings, and the point's response per line) and the mean model's modes with their strain
// energy shares and the ranked critical speeds. Internal to the analysis library.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gearnvh/analysis/whine.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/nvh/harmonic_response.h"
#include "gearnvh/reduction/train_reduction.h"

namespace gearnvh::whine {

// A housing curve and the result's bearing it belongs to.
struct ResolvedCurve {
  const HousingCurve* curve = nullptr;
  size_t bearing = 0;
};

// The table's curves on the result's bearings; InputError naming the table when a bearing is not
// the gearbox's or the tier has no bearing forces.
std::vector<ResolvedCurve> ResolveHousing(const HousingTransfer& housing, const WhineResult& r);

// The acceleration at the housing's point at w rad/s: the curves times their bearings' forces,
// summed; NaN when w lies outside some curve's range.
double HousingResponse(const std::vector<ResolvedCurve>& curves, double w,
                       const HarmonicResponse& out);

// The mean model's modes below `limit_hz` (undamped, no gyroscopics) with their strain energy
// shares, ascending; the train's free rotation (zero stiffness energy) is left out.
std::vector<WhineMode> Modes(const HarmonicModel& model, const TrainStructure& structure,
                             const TrainReducedModel& reduced, double limit_hz);

// Every crossing of a line with a mode inside the speed range, ranked by the mode's mesh strain
// energy (then by speed).
std::vector<WhineCriticalSpeed> CriticalSpeeds(const WhineResult& r);

}  // namespace gearnvh::whine
