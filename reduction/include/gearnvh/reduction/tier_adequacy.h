// Does a modal tier reproduce the modes of the full FE model that the mesh can excite?
//
// The full model, linearised in drive contact at the mean mesh stiffness, has modes phi_i
// (M-normalised, frequency f_i). A mode matters for the transmission error when the mesh sees it:
// its share of the mesh's modal compliance, (v^T phi_i)^2 / w_i^2 over the sum of that quantity
// over the computed modes, is at least `min_share` (1 %); lateral or axial modes orthogonal to the
// line of action do not count. Every mode that matters below `max_frequency_hz` (callers pass 3x
// the mesh frequency) must be reproduced by the tier: a tier mode (recovered to the physical DOF,
// T phi_r) with a mass-weighted MAC >= `min_mac` against it and a frequency within
// `max_frequency_error` (5 %). Otherwise the tier is inadequate at this operating point, and the
// lowest adequate tier is looked for in the order of cost: 1, 2, 3, 4, N20 MTA, 5.
// The full model's modes come from a dense solve up to `dense_limit` DOF and from Spectra's
// shift-invert Lanczos on the sparse pencil above (the lowest `sparse_modes`).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gearnvh/model/component_model.h"
#include "gearnvh/reduction/reduced_model.h"

namespace gearnvh {

struct TierAdequacyOptions {
  double max_frequency_hz = 0.0;      // > 0
  double min_share = 0.01;            // in (0, 1)
  double min_mac = 0.5;               // in (0, 1]
  double max_frequency_error = 0.05;  // > 0
  int dense_limit = 600;              // DOF
  int sparse_modes = 60;              // >= 1
  void Validate() const;
};

// The full model's modes that the mesh sees below the frequency limit.
struct MeshModes {
  std::vector<double> frequencies_hz;
  std::vector<double> shares;  // of the mesh's modal compliance
  Eigen::MatrixXd shapes;      // M-normalised, physical DOF
};
MeshModes FullModelMeshModes(const ComponentModel& model, const TierAdequacyOptions& options);

struct TierModeMatch {
  double full_hz = 0.0;
  double share = 0.0;
  double tier_hz = 0.0;  // the best-matching tier mode (0 when none has MAC >= min_mac)
  double mac = 0.0;
  double relative_error = 0.0;  // (tier - full) / full; 1 when missing
  bool reproduced = false;
};

struct TierAdequacy {
  Tier tier = Tier::kTier1;
  bool adequate = true;
  std::vector<TierModeMatch> modes;
  std::optional<Tier> adequate_tier;  // the lowest adequate tier, when this one is not
  // "tier 1 misses the 1234 Hz mode (12 % of the mesh compliance); use tier 3", or empty.
  std::string Warning() const;
};

// Compares `reduced` with the full model's mesh modes; when inadequate, reduces the model to the
// cheaper-first tiers until one is adequate.
TierAdequacy AssessTierAdequacy(const ComponentModel& model, const ReducedModel& reduced,
                                const MeshModes& full, const TierAdequacyOptions& options);

}  // namespace gearnvh
