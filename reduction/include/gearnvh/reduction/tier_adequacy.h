// Does a modal tier reproduce the modes of the full FE model that the meshes can excite? One test
// for every gearbox (a schema-1 pair's ComponentModel, a train's TrainStructure).
//
// The full model, linearised in drive contact with every mesh at its mean stiffness, has modes
// phi_i (M-normalised, frequency f_i). A mode matters for the transmission error when a mesh sees
// it: its share of mesh m's modal compliance, (v_m^T phi_i)^2 / w_i^2 over the sum of that quantity
// over the computed modes, is at least `min_share` (1 %) for some mesh m; lateral or axial modes
// orthogonal to every line of action do not count; mesh m counts the modes up to its own limit
// (callers pass 3x its mesh frequency; a pair's is `max_frequency_hz`). Every mode that matters
// must be reproduced by the tier: a
// tier mode (recovered to the physical DOF, T phi_r) with a mass-weighted MAC >= `min_mac` against
// it and a frequency within `max_frequency_error` (5 %). Otherwise the tier is inadequate at this
// operating point, and the lowest adequate tier is looked for in the order of cost: 1, 2, 3, 4, N20
// MTA, 5. The full model's modes come from a dense solve up to `dense_limit` DOF and from
// Spectra's shift-invert Lanczos on the sparse pencil above (the lowest `sparse_modes`, for a train
// doubled until they pass the highest limit; a solve that stops short makes the check incomplete,
// and says so). A train's free rotations are removed by construction in the dense solve, and as
// the known number of lowest eigenpairs in the sparse one (train_reduction.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/modal_analysis.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/reduction/train_reduction.h"

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

// The full model's modes that the meshes see below the frequency limit.
struct MeshModes {
  std::vector<double> frequencies_hz;
  std::vector<double> shares;  // of the modal compliance of the mesh that sees it most
  std::vector<int> mesh;       // that mesh (index in file order; 0 for a pair)
  Eigen::MatrixXd shapes;      // M-normalised, physical DOF
  // Whether the solve reached every limit (false: stopped short or failed), and how far it got.
  bool complete = true;
  double found_up_to_hz = 0.0;
};
// Of `modes` (with M-normalised shapes, every mode computed), those that a mesh with vector v_m in
// `meshes` sees below its limit limits_hz[m] (the share rule above).
MeshModes MeshSeenModes(const NaturalModes& modes, const std::vector<Eigen::VectorXd>& meshes,
                        const std::vector<double>& limits_hz, const TierAdequacyOptions& options);
// A pair: its one mesh up to options.max_frequency_hz. A train: mesh m up to limits_hz[m].
MeshModes FullModelMeshModes(const ComponentModel& model, const TierAdequacyOptions& options);
MeshModes FullModelMeshModes(const TrainStructure& structure, const std::vector<double>& limits_hz,
                             const TierAdequacyOptions& options);

struct TierModeMatch {
  double full_hz = 0.0;
  double share = 0.0;
  int mesh = 0;          // the mesh that sees it most
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
  bool complete = true;               // MeshModes::complete of the full model's modes
  double found_up_to_hz = 0.0;
  // "tier 1 misses the 1234 Hz mode (12 % of the mesh compliance); tier 3 reproduces ...", or
  // empty. With several `mesh_names` (file order) the mesh that sees the mode is named.
  std::string Warning(const std::vector<std::string>& mesh_names = {}) const;
};

// Compares `reduced` with the full model's mesh modes; when inadequate, reduces the model to the
// cheaper-first tiers until one is adequate (a tier the structure cannot be reduced to is skipped).
TierAdequacy AssessTierAdequacy(const ComponentModel& model, const ReducedModel& reduced,
                                const MeshModes& full, const TierAdequacyOptions& options);
TierAdequacy AssessTierAdequacy(const TrainStructure& structure, const TrainReducedModel& reduced,
                                const MeshModes& full, const TierAdequacyOptions& options,
                                const ReductionOptions& reduction = {});

}  // namespace gearnvh
