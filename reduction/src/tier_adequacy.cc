#include "gearnvh/reduction/tier_adequacy.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/modal_analysis.h"
#include "gearnvh/reduction/sparse_modes.h"

namespace gearnvh {

void TierAdequacyOptions::Validate() const {
  auto fail = [](const char* field, double v, const char* rule) {
    throw InputError(std::string("TierAdequacyOptions.") + field, 0, std::to_string(v), rule);
  };
  if (!(max_frequency_hz > 0.0)) fail("max_frequency_hz", max_frequency_hz, "must be > 0");
  if (!(min_share > 0.0 && min_share < 1.0)) fail("min_share", min_share, "must be in (0, 1)");
  if (!(min_mac > 0.0 && min_mac <= 1.0)) fail("min_mac", min_mac, "must be in (0, 1]");
  if (!(max_frequency_error > 0.0)) {
    fail("max_frequency_error", max_frequency_error, "must be > 0");
  }
  if (sparse_modes < 1) fail("sparse_modes", sparse_modes, "must be >= 1");
}

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

}  // namespace

MeshModes MeshSeenModes(const NaturalModes& modes, const std::vector<Eigen::VectorXd>& meshes,
                        const std::vector<double>& limits_hz, const TierAdequacyOptions& options) {
  options.Validate();
  if (limits_hz.size() != meshes.size()) {
    throw std::invalid_argument("MeshSeenModes: one frequency limit per mesh");
  }
  const size_t count = modes.frequencies_hz.size();
  // compliance[m][i] = (v_m^T phi_i)^2 / w_i^2, each mesh's share over the computed modes.
  std::vector<std::vector<double>> compliance(meshes.size(), std::vector<double>(count));
  std::vector<double> total(meshes.size(), 0.0);
  for (size_t m = 0; m < meshes.size(); ++m) {
    for (size_t i = 0; i < count; ++i) {
      const double w = kTwoPi * modes.frequencies_hz[i];
      const double g = meshes[m].dot(modes.shapes.col(static_cast<Eigen::Index>(i)));
      compliance[m][i] = g * g / (w * w);
      total[m] += compliance[m][i];
    }
  }
  MeshModes out;
  std::vector<Eigen::Index> kept;
  for (size_t i = 0; i < count; ++i) {
    double share = 0.0;
    int seen_by = 0;
    for (size_t m = 0; m < meshes.size(); ++m) {
      const bool excited = modes.frequencies_hz[i] <= limits_hz[m];
      const double s = excited && total[m] > 0.0 ? compliance[m][i] / total[m] : 0.0;
      if (s > share) {
        share = s;
        seen_by = static_cast<int>(m);
      }
    }
    if (share < options.min_share) continue;  // above every mesh's limit the share is 0
    out.frequencies_hz.push_back(modes.frequencies_hz[i]);
    out.shares.push_back(share);
    out.mesh.push_back(seen_by);
    kept.push_back(static_cast<Eigen::Index>(i));
  }
  out.shapes.resize(modes.shapes.rows(), static_cast<Eigen::Index>(kept.size()));
  for (size_t c = 0; c < kept.size(); ++c) {
    out.shapes.col(static_cast<Eigen::Index>(c)) = modes.shapes.col(kept[c]);
  }
  return out;
}

MeshModes FullModelMeshModes(const ComponentModel& model, const TierAdequacyOptions& options) {
  options.Validate();
  Eigen::SparseMatrix<double> K = model.K;
  const Eigen::SparseMatrix<double> mesh =
      (model.mesh_summary.mean * model.v_drive * model.v_drive.transpose()).sparseView();
  K += mesh;
  const StrainMagnitude magnitude = [&](const Eigen::VectorXd& x) {
    return FullStrainMagnitude(model, model.mesh_summary.mean, x);
  };
  const NaturalModes modes =
      model.dofs <= options.dense_limit
          ? LowestNaturalModes(Eigen::MatrixXd(K), Eigen::MatrixXd(model.M), model.dofs, true,
                               magnitude)
          : LowestSparseNaturalModes(K, model.M, options.sparse_modes, 1, magnitude);
  return MeshSeenModes(modes, {model.v_drive}, {options.max_frequency_hz}, options);
}

MeshModes FullModelMeshModes(const TrainStructure& structure, const std::vector<double>& limits_hz,
                             const TierAdequacyOptions& options) {
  options.Validate();
  const bool dense = structure.dofs <= options.dense_limit;
  int count = dense ? structure.dofs : options.sparse_modes;
  NaturalModes modes = FullTrainModes(structure, count, options.dense_limit, true);
  // Lanczos gives the lowest `count`: ask for more until they pass the highest limit.
  const double highest = *std::max_element(limits_hz.begin(), limits_hz.end());
  const auto short_of_limit = [&] {
    return static_cast<int>(modes.frequencies_hz.size()) == count &&
           modes.frequencies_hz.back() < highest;
  };
  while (!dense && short_of_limit() && 2 * count < structure.dofs) {
    count *= 2;
    modes = FullTrainModes(structure, count, options.dense_limit, true);
  }
  std::vector<Eigen::VectorXd> meshes;
  for (const TrainMeshVectors& m : structure.meshes) meshes.push_back(m.v_drive);
  MeshModes out = MeshSeenModes(modes, meshes, limits_hz, options);
  out.complete = !modes.frequencies_hz.empty() && !short_of_limit();
  out.found_up_to_hz = modes.frequencies_hz.empty() ? 0.0 : modes.frequencies_hz.back();
  return out;
}

namespace {

// Each full mode matched with the tier mode (shapes recovered to the physical DOF) of largest
// mass-weighted MAC.
std::vector<TierModeMatch> Match(const NaturalModes& tier, const Eigen::MatrixXd& recovery,
                                 const Eigen::SparseMatrix<double>& M, const MeshModes& full,
                                 const TierAdequacyOptions& options) {
  const Eigen::MatrixXd recovered = recovery * tier.shapes;  // physical DOF
  const Eigen::MatrixXd m_recovered = M * recovered;
  std::vector<TierModeMatch> out;
  for (size_t i = 0; i < full.frequencies_hz.size(); ++i) {
    TierModeMatch match;
    match.full_hz = full.frequencies_hz[i];
    match.share = full.shares[i];
    match.mesh = full.mesh[i];
    match.relative_error = 1.0;
    const Eigen::VectorXd phi = full.shapes.col(static_cast<Eigen::Index>(i));
    for (Eigen::Index j = 0; j < recovered.cols(); ++j) {
      const double cross = phi.dot(m_recovered.col(j));
      const double mac =
          cross * cross / recovered.col(j).dot(m_recovered.col(j));  // phi^T M phi = 1
      if (mac < options.min_mac || mac <= match.mac) continue;
      match.mac = mac;
      match.tier_hz = tier.frequencies_hz[static_cast<size_t>(j)];
      match.relative_error = (match.tier_hz - match.full_hz) / match.full_hz;
    }
    match.reproduced = match.mac >= options.min_mac &&
                       std::abs(match.relative_error) <= options.max_frequency_error;
    out.push_back(match);
  }
  return out;
}

std::vector<TierModeMatch> Match(const ComponentModel& model, const ReducedModel& r,
                                 const MeshModes& full, const TierAdequacyOptions& options) {
  const Eigen::MatrixXd K = r.K + model.mesh_summary.mean * r.v_drive * r.v_drive.transpose();
  const NaturalModes tier = LowestNaturalModes(
      K, r.M, r.dof, true, ReducedStrainMagnitude(model, r, model.mesh_summary.mean));
  return Match(tier, r.recovery, model.M, full, options);
}

std::vector<TierModeMatch> Match(const TrainStructure& structure, const TrainReducedModel& r,
                                 const MeshModes& full, const TierAdequacyOptions& options) {
  return Match(TrainReducedModes(structure, r, r.dof, true), r.recovery, structure.M, full,
               options);
}

bool Adequate(const std::vector<TierModeMatch>& modes) {
  return std::all_of(modes.begin(), modes.end(),
                     [](const TierModeMatch& m) { return m.reproduced; });
}

// The verdict on `tier` (its matches), and when inadequate the lowest adequate tier in the order
// of cost: `adequate_at(t)` reduces to tier t (nullopt: not available) and matches it.
TierAdequacy Assess(Tier tier, const MeshModes& full, std::vector<TierModeMatch> matches,
                    const std::function<std::optional<bool>(Tier)>& adequate_at) {
  TierAdequacy out;
  out.tier = tier;
  out.complete = full.complete;
  out.found_up_to_hz = full.found_up_to_hz;
  out.modes = std::move(matches);
  out.adequate = Adequate(out.modes);
  if (out.adequate) return out;
  for (Tier t :
       {Tier::kTier1, Tier::kTier2, Tier::kTier3, Tier::kTier4, Tier::kN20Mta, Tier::kTier5}) {
    if (t == tier) continue;
    if (adequate_at(t).value_or(false)) {
      out.adequate_tier = t;
      break;
    }
  }
  return out;
}

}  // namespace

TierAdequacy AssessTierAdequacy(const ComponentModel& model, const ReducedModel& reduced,
                                const MeshModes& full, const TierAdequacyOptions& options) {
  options.Validate();
  return Assess(reduced.tier, full, Match(model, reduced, full, options),
                [&](Tier t) -> std::optional<bool> {
                  if (!TierAvailable(model, t)) return std::nullopt;
                  return Adequate(Match(model, ReduceModel(model, t), full, options));
                });
}

TierAdequacy AssessTierAdequacy(const TrainStructure& structure, const TrainReducedModel& reduced,
                                const MeshModes& full, const TierAdequacyOptions& options,
                                const ReductionOptions& reduction) {
  options.Validate();
  return Assess(
      reduced.tier, full, Match(structure, reduced, full, options),
      [&](Tier t) -> std::optional<bool> {
        if (!TrainTierAvailable(structure, t)) return std::nullopt;
        try {
          return Adequate(Match(structure, ReduceTrain(structure, t, reduction), full, options));
        } catch (const StructureNotReducible&) {
          return std::nullopt;  // a tier this structure cannot have is no advice
        }
      });
}

std::string TierAdequacy::Warning(const std::vector<std::string>& mesh_names) const {
  // The modes the full model's solve did not reach were not checked: said, not passed over.
  const std::string unchecked =
      complete ? std::string()
               : fmt::format(
                     "the full model's modes were found only up to {:.0f} Hz: {} was "
                     "checked against those",
                     found_up_to_hz, TierName(tier));
  if (adequate) return unchecked;
  const TierModeMatch* worst = nullptr;
  for (const TierModeMatch& m : modes) {
    if (!m.reproduced && (worst == nullptr || m.share > worst->share)) worst = &m;
  }
  // One mesh: "the mesh compliance"; several: the mesh that sees the mode most, by name.
  const std::string whose =
      mesh_names.size() > 1 && worst->mesh >= 0 &&
              static_cast<size_t>(worst->mesh) < mesh_names.size()
          ? "the compliance of mesh " + mesh_names[static_cast<size_t>(worst->mesh)]
          : std::string("the mesh compliance");
  std::string text =
      worst->tier_hz > 0.0
          ? fmt::format("{} puts the {:.0f} Hz mode ({:.0f} % of {}) at {:.0f} Hz ({:+.1f} %)",
                        TierName(tier), worst->full_hz, 100.0 * worst->share, whose, worst->tier_hz,
                        100.0 * worst->relative_error)
          : fmt::format("{} misses the {:.0f} Hz mode ({:.0f} % of {})", TierName(tier),
                        worst->full_hz, 100.0 * worst->share, whose);
  text += adequate_tier ? fmt::format("; {} reproduces every mode {} below the limit",
                                      TierName(*adequate_tier),
                                      mesh_names.size() > 1 ? "the meshes see" : "the mesh sees")
                        : std::string("; no tier reproduces them all");
  return unchecked.empty() ? text : text + "; " + unchecked;
}

}  // namespace gearnvh
