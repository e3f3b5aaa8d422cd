#include "gearnvh/reduction/tier_adequacy.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

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
  double total = 0.0;
  std::vector<double> compliance(modes.frequencies_hz.size());
  for (size_t i = 0; i < compliance.size(); ++i) {
    const double w = kTwoPi * modes.frequencies_hz[i];
    const double g = model.v_drive.dot(modes.shapes.col(static_cast<Eigen::Index>(i)));
    compliance[i] = g * g / (w * w);
    total += compliance[i];
  }
  MeshModes out;
  std::vector<Eigen::Index> kept;
  for (size_t i = 0; i < compliance.size(); ++i) {
    const double share = total > 0.0 ? compliance[i] / total : 0.0;
    if (modes.frequencies_hz[i] > options.max_frequency_hz || share < options.min_share) continue;
    out.frequencies_hz.push_back(modes.frequencies_hz[i]);
    out.shares.push_back(share);
    kept.push_back(static_cast<Eigen::Index>(i));
  }
  out.shapes.resize(model.dofs, static_cast<Eigen::Index>(kept.size()));
  for (size_t c = 0; c < kept.size(); ++c) {
    out.shapes.col(static_cast<Eigen::Index>(c)) = modes.shapes.col(kept[c]);
  }
  return out;
}

namespace {

std::vector<TierModeMatch> Match(const ComponentModel& model, const ReducedModel& r,
                                 const MeshModes& full, const TierAdequacyOptions& options) {
  const Eigen::MatrixXd K =
      r.K + r.EffectiveMeshStiffness(model.mesh_summary.mean) * r.v_drive * r.v_drive.transpose();
  const NaturalModes tier = LowestNaturalModes(
      K, r.M, r.dof, true, ReducedStrainMagnitude(model, r, model.mesh_summary.mean));
  const Eigen::MatrixXd recovered = r.recovery * tier.shapes;  // physical DOF
  const Eigen::MatrixXd m_recovered = model.M * recovered;
  std::vector<TierModeMatch> out;
  for (size_t i = 0; i < full.frequencies_hz.size(); ++i) {
    TierModeMatch match;
    match.full_hz = full.frequencies_hz[i];
    match.share = full.shares[i];
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

bool Adequate(const std::vector<TierModeMatch>& modes) {
  return std::all_of(modes.begin(), modes.end(),
                     [](const TierModeMatch& m) { return m.reproduced; });
}

}  // namespace

TierAdequacy AssessTierAdequacy(const ComponentModel& model, const ReducedModel& reduced,
                                const MeshModes& full, const TierAdequacyOptions& options) {
  options.Validate();
  TierAdequacy out;
  out.tier = reduced.tier;
  out.modes = Match(model, reduced, full, options);
  out.adequate = Adequate(out.modes);
  if (out.adequate) return out;
  for (Tier t :
       {Tier::kTier1, Tier::kTier2, Tier::kTier3, Tier::kTier4, Tier::kN20Mta, Tier::kTier5}) {
    if (t == reduced.tier || !TierAvailable(model, t)) continue;
    if (Adequate(Match(model, ReduceModel(model, t), full, options))) {
      out.adequate_tier = t;
      break;
    }
  }
  return out;
}

std::string TierAdequacy::Warning() const {
  if (adequate) return "";
  const TierModeMatch* worst = nullptr;
  for (const TierModeMatch& m : modes) {
    if (!m.reproduced && (worst == nullptr || m.share > worst->share)) worst = &m;
  }
  std::string text =
      worst->tier_hz > 0.0
          ? fmt::format(
                "{} puts the {:.0f} Hz mode ({:.0f} % of the mesh compliance) at {:.0f} Hz "
                "({:+.1f} %)",
                TierName(tier), worst->full_hz, 100.0 * worst->share, worst->tier_hz,
                100.0 * worst->relative_error)
          : fmt::format("{} misses the {:.0f} Hz mode ({:.0f} % of the mesh compliance)",
                        TierName(tier), worst->full_hz, 100.0 * worst->share);
  text += adequate_tier ? fmt::format("; {} reproduces every mode the mesh sees below the limit",
                                      TierName(*adequate_tier))
                        : std::string("; no tier reproduces them all");
  return text;
}

}  // namespace gearnvh
