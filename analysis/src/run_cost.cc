#include "gearnvh/analysis/run_cost.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/solver/train_rate_bound.h"
#include "gearnvh/solver/train_stepper.h"

namespace gearnvh {

const char* RateTermName(RateTerm term) {
  switch (term) {
    case RateTerm::kStiffness:
      return "stiffness (the highest undamped mode)";
    case RateTerm::kDamping:
      return "damping";
    case RateTerm::kGyroscopic:
      return "gyroscopic moments";
    case RateTerm::kFriction:
      return "tooth friction";
    case RateTerm::kExcitation:
      return "the engine orders";
  }
  return "";
}

namespace {

// The node whose disk spins fastest against its own tilt inertia: |w_in G(th_x, th_y)| / I_d, the
// nutation rate a gyroscopic moment drives there, and its body.
void GyroscopicCause(const TrainSpec& spec, RunCostEstimate& out) {
  const GearTrain train = BuildGearTrain(spec);
  const TrainStructure s = AssembleTrainStructure(spec, train);
  const Eigen::MatrixXd G(s.G), M(s.M);
  double best = 0.0;
  for (size_t node = 0; node < s.nodes.size(); ++node) {
    const int x = TrainStructure::Dof(static_cast<int>(node), kThx);
    const int y = TrainStructure::Dof(static_cast<int>(node), kThy);
    const double ip = std::abs(G(x, y));
    const double id = std::min(M(x, x), M(y, y));
    if (!(ip > 0.0) || !(id > 0.0)) continue;
    const double rate = std::abs(spec.operating.speed) * ip / id;
    if (rate <= best) continue;
    best = rate;
    const int body = s.node_body[node];
    out.cause_body = body;
    out.cause_body_name = train.topology.bodies[static_cast<size_t>(body)].name;
    // G is per unit input speed: spin w_b / w_in times I_p.
    const double spin =
        train.topology.bodies[static_cast<size_t>(body)].speed / spec.operating.speed;
    out.cause_body_inertia = spin != 0.0 ? ip / std::abs(spin) : 0.0;
    out.cause_nutation_rate = rate;
  }
}

}  // namespace

RunCostEstimate EstimateRunCost(const TrainTables& t, double simulated_s, const TrainSpec* spec) {
  RunCostEstimate out;
  out.tier = t.tier;
  out.state_dim = t.m;
  out.simulated_s = simulated_s;
  if (t.n == 0) return out;
  for (const TrainMeshTable& mt : t.meshes)
    out.fastest_mesh_hz = std::max(out.fastest_mesh_hz, 1.0 / mt.period);
  // The tuple the run starts in with every mesh in drive (the couplings' stages as at rest):
  // segment 0 of every mesh at t = 0.
  const std::vector<int> segments(t.meshes.size(), 0);
  const std::vector<ContactState> drive = LoadedContactStates(t);
  const TuplePencil pencil = AssembleTuplePencil(t, segments, drive);
  const double damping = DampingRateBound(t, pencil.C);
  const TupleRateBound bound = BoundTupleRate(t, pencil, damping);
  out.mode_hz = bound.stiffness_frequency / (2.0 * std::numbers::pi);
  // The engine orders' exosystem turns at their frequencies (A is block triangular).
  out.rho = std::max(bound.rho, t.HighestExcitationFrequency());
  out.substep_s = out.rho > 0.0 ? 0.5 / out.rho : 0.0;
  // rho's terms (BoundTupleRate): w, the symmetric damping, the skew (gyroscopic) part of C_0 and
  // friction's share.
  const double gyroscopic = GyroscopicRateBound(t);
  const std::pair<RateTerm, double> terms[] = {
      {RateTerm::kStiffness, bound.stiffness_frequency},
      {RateTerm::kDamping, damping - gyroscopic},
      {RateTerm::kGyroscopic, gyroscopic},
      {RateTerm::kFriction, bound.friction_rate},
      {RateTerm::kExcitation, t.HighestExcitationFrequency()}};
  for (const auto& [term, rate] : terms) {
    if (rate > out.dominant_rate) {
      out.dominant = term;
      out.dominant_rate = rate;
    }
  }
  // The body that moves most in that mode: its eigenvector of M^-1/2 K M^-1/2, back to angles.
  const Eigen::VectorXd scale = t.inertia.cwiseSqrt().cwiseInverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scale.asDiagonal() * pencil.K *
                                                           scale.asDiagonal());
  if (eig.info() != Eigen::Success) {
    RunCostEstimate failed;
    failed.simulated_s = simulated_s;
    return failed;
  }
  const Eigen::VectorXd x = scale.cwiseProduct(eig.eigenvectors().col(t.n - 1));
  Eigen::Index body = 0;
  (t.body_angles * x).cwiseAbs().maxCoeff(&body);
  out.body = static_cast<int>(body);
  out.cause_body = out.body;
  out.cause_body_name = t.body_names[static_cast<size_t>(body)];
  out.cause_body_inertia = t.body_inertia[body];
  if (out.dominant == RateTerm::kGyroscopic && spec != nullptr) GyroscopicCause(*spec, out);
  if (out.substep_s > 0.0) {
    out.substeps = simulated_s / out.substep_s;
    const double m = static_cast<double>(t.m);
    out.wall_s = out.substeps * kSubstepSecondsPerState2 * m * m;
  }
  return out;
}

RunCostEstimate CombineRunCosts(const std::vector<RunCostEstimate>& runs, int parallel) {
  if (runs.empty()) return {};
  const auto costliest = std::max_element(
      runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.wall_s < b.wall_s; });
  RunCostEstimate out = *costliest;
  out.simulated_s = out.substeps = out.wall_s = 0.0;
  out.runs = 0;
  for (const RunCostEstimate& r : runs) {
    out.simulated_s += r.simulated_s;
    out.substeps += r.substeps;
    out.wall_s += r.wall_s;
    out.runs += r.runs;
  }
  out.wall_s /= std::max(1, std::min(parallel, out.runs));
  return out;
}

namespace {

std::string Duration(double s) {
  if (s < 120.0) return fmt::format("{:.3g} s", s);
  if (s < 3600.0) return fmt::format("{:.3g} min", s / 60.0);
  if (s < 2.0 * 86400.0) return fmt::format("{:.3g} h", s / 3600.0);
  if (s < 2.0 * 365.25 * 86400.0) return fmt::format("{:.3g} days", s / 86400.0);
  return fmt::format("{:.3g} years", s / (365.25 * 86400.0));
}

}  // namespace

std::string RunCostText(const RunCostEstimate& c, const std::string& what) {
  std::string cause;
  switch (c.dominant) {
    case RateTerm::kStiffness:
    case RateTerm::kDamping:
    case RateTerm::kFriction:
      cause = fmt::format(
          "{}: the highest mode of the train is {:.4g} Hz, {:.0f}x the fastest mesh frequency "
          "({:.4g} Hz), mostly body {}{}",
          RateTermName(c.dominant), c.mode_hz,
          c.fastest_mesh_hz > 0.0 ? c.mode_hz / c.fastest_mesh_hz : 0.0, c.fastest_mesh_hz,
          c.cause_body_name,
          c.cause_body_inertia > 0.0
              ? fmt::format(", inertia {:.3g} kg m² (a tiny inertia on stiff meshes or couplings "
                            "makes a very high mode; check the inertias and couplings.X.stiffness)",
                            c.cause_body_inertia)
              : "");
      break;
    case RateTerm::kGyroscopic:
      cause = c.cause_body_name.empty()
                  ? std::string("gyroscopic moments of the bodies at their speeds")
                  : fmt::format(
                        "gyroscopic moments: body {} (polar inertia {:.3g} kg m²) spins at "
                        "{:.3g} rad/s against its own tilt inertia (a nutation of |w| I_p / I_d; "
                        "check its inertias)",
                        c.cause_body_name, c.cause_body_inertia, c.cause_nutation_rate);
      break;
    case RateTerm::kExcitation:
      cause = fmt::format(
          "the engine orders: the highest turns at {:.4g} Hz, {:.0f}x the fastest mesh frequency "
          "({:.4g} Hz); the solver carries each order exactly, so an order this high costs its "
          "own sub-steps",
          c.rho / (2.0 * std::numbers::pi),
          c.fastest_mesh_hz > 0.0 ? c.rho / (2.0 * std::numbers::pi) / c.fastest_mesh_hz : 0.0,
          c.fastest_mesh_hz);
      break;
  }
  return fmt::format(
      "{} would take about {} ({:.3g} dense sub-steps of at most {:.3g} s for the {:.4g} s "
      "simulated, state dimension {}; estimated at {:g} s per sub-step per squared state "
      "dimension); the sub-step is half the inverse of the bound on the generator's spectral "
      "radius ({:.4g} 1/s), dominated by {}",
      what, Duration(c.wall_s), c.substeps, c.substep_s, c.simulated_s, c.state_dim,
      kSubstepSecondsPerState2, c.rho, cause);
}

std::string CheckRunCost(const RunCostEstimate& cost, bool allow_slow, const std::string& what,
                         const OptionNames& names) {
  if (!(cost.wall_s > kSlowRunWarnSeconds)) return {};
  const std::string text = RunCostText(cost, what);
  if (cost.wall_s > kSlowRunRefuseSeconds && !allow_slow) {
    throw InputError(names("allow-slow"), 0, "",
                     fmt::format("not given, and {}; refused: more than {} without {} (fewer "
                                 "cycles, a lower tier or a corrected inertia make it shorter)",
                                 text, Duration(kSlowRunRefuseSeconds), names("allow-slow")));
  }
  return text;
}

}  // namespace gearnvh
