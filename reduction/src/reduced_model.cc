#include "gearnvh/reduction/reduced_model.h"

#include <Eigen/SparseCholesky>
#include <chrono>
#include <cmath>
#include <numbers>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/modal_analysis.h"
#include "gearnvh/reduction/craig_bampton.h"
#include "mode_cut.h"
#include "residual_vectors.h"

namespace gearnvh {

void ReductionOptions::Validate() const {
  if (!(structural_damping_ratio >= 0.0 && structural_damping_ratio < 1.0)) {
    throw InputError("ReductionOptions.structural_damping_ratio", 0,
                     std::to_string(structural_damping_ratio), "must be in [0, 1)");
  }
  if (dense_eigen_threshold < 8) {
    throw InputError("ReductionOptions.dense_eigen_threshold", 0,
                     std::to_string(dense_eigen_threshold), "must be >= 8");
  }
}

namespace {

constexpr int kTier4Modes = 8;
constexpr int kTier5Modes = 28;
constexpr int kTruncatedModes = 20;

std::vector<int> Boundary(const ComponentModel& m, Tier tier) {
  std::vector<NodeDof> dofs;
  if (tier == Tier::kTier1)
    dofs = {kThz};
  else if (tier == Tier::kTier2)
    dofs = {kUx, kUy, kThz};
  else
    dofs = {kUx, kUy, kUz, kThx, kThy, kThz};
  std::vector<int> b;
  for (int node : {m.pinion_node, m.wheel_node}) {
    for (NodeDof d : dofs) b.push_back(ComponentModel::Dof(node, d));
  }
  return b;
}

int ModesOf(Tier tier) {
  switch (tier) {
    case Tier::kTier4:
      return kTier4Modes;
    case Tier::kTier5:
    case Tier::kN20Simple:
    case Tier::kN20Mta:
      return kTier5Modes;
    default:
      return 0;
  }
}

// Projects the full model onto the basis T (full DOF x n).
ReducedModel Project(const ComponentModel& m, const Eigen::MatrixXd& T) {
  ReducedModel r;
  r.dof = static_cast<int>(T.cols());
  r.recovery = T;
  r.M = T.transpose() * (m.M * T);
  r.K = T.transpose() * (m.K * T);
  r.C = T.transpose() * (m.C * T);
  r.G = T.transpose() * (m.G * T);
  // Symmetrise away the rounding of the triple products (exact symmetry is a solver precondition).
  r.M = 0.5 * (r.M + r.M.transpose()).eval();
  r.K = 0.5 * (r.K + r.K.transpose()).eval();
  r.C = 0.5 * (r.C + r.C.transpose()).eval();
  r.G = 0.5 * (r.G - r.G.transpose()).eval();
  r.v_drive = T.transpose() * m.v_drive;
  r.v_back = T.transpose() * m.v_back;
  r.friction_translation_drive = T.transpose() * m.translation_friction_drive;
  r.friction_translation_back = T.transpose() * m.translation_friction_back;
  r.pinion_torsion = T.row(m.PinionDof(kThz)).transpose();
  r.wheel_torsion = T.row(m.WheelDof(kThz)).transpose();
  r.static_force = T.transpose() * m.static_force;
  return r;
}

// Applies a change of coordinates x = P y to a reduced model (modal truncation, MTA vector form).
ReducedModel Transform(const ReducedModel& a, const Eigen::MatrixXd& P) {
  ReducedModel r;
  r.dof = static_cast<int>(P.cols());
  r.recovery = a.recovery * P;
  r.M = P.transpose() * a.M * P;
  r.K = P.transpose() * a.K * P;
  r.C = P.transpose() * a.C * P;
  r.G = P.transpose() * a.G * P;
  r.M = 0.5 * (r.M + r.M.transpose()).eval();
  r.K = 0.5 * (r.K + r.K.transpose()).eval();
  r.C = 0.5 * (r.C + r.C.transpose()).eval();
  r.G = 0.5 * (r.G - r.G.transpose()).eval();
  for (auto [dst, src] : {std::pair{&r.v_drive, &a.v_drive},
                          {&r.v_back, &a.v_back},
                          {&r.friction_translation_drive, &a.friction_translation_drive},
                          {&r.friction_translation_back, &a.friction_translation_back},
                          {&r.pinion_torsion, &a.pinion_torsion},
                          {&r.wheel_torsion, &a.wheel_torsion},
                          {&r.static_force, &a.static_force}}) {
    *dst = P.transpose() * *src;
  }
  return r;
}

// Held-rotation static response of a dense reduced model: K x = v subject to C x = 0 (C = gear
// rotation rows of the recovery matrix), by the saddle-point system.
Eigen::VectorXd HeldStaticResponse(const ReducedModel& r, const Eigen::VectorXd& v) {
  const int n = r.dof;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n + 2, n + 2);
  A.topLeftCorner(n, n) = r.K;
  A.block(n, 0, 1, n) = r.pinion_torsion.transpose();
  A.block(n + 1, 0, 1, n) = r.wheel_torsion.transpose();
  A.block(0, n, n, 1) = r.pinion_torsion;
  A.block(0, n + 1, n, 1) = r.wheel_torsion;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 2);
  rhs.head(n) = v;
  const Eigen::VectorXd sol = A.fullPivLu().solve(rhs);
  return sol.head(n);
}

void Finish(const ComponentModel& m, ReducedModel& r, double full_compliance) {
  r.static_mesh_compliance = r.v_drive.dot(HeldStaticResponse(r, r.v_drive));
  r.full_static_mesh_compliance = full_compliance;
  r.compliance_error_vs_full =
      full_compliance > 0.0 ? (r.static_mesh_compliance - full_compliance) / full_compliance : 0.0;
  r.natural_frequencies_hz = ReducedNaturalFrequencies(m, r, m.mesh_summary.mean,
                                                       kReportedFrequencies, &r.rigid_body_modes);
}

}  // namespace

bool TierAvailable(const ComponentModel& model, Tier tier) {
  return ModesOf(tier) == 0 || model.dofs - 12 >= kTier5Modes;
}

void RequireTierAvailable(const ComponentModel& model, Tier tier) {
  if (TierAvailable(model, tier)) return;
  throw TierNotAvailable(tier, "needs flexible shafts (at least " + std::to_string(kTier5Modes) +
                                   " interior DOF); this model has " + std::to_string(model.dofs) +
                                   " DOF");
}

double FullStaticMeshCompliance(const ComponentModel& m) {
  // Remove the two held gear-rotation DOF; the rest is positive definite (bearings ground it).
  const int n = m.dofs;
  const int held_a = m.PinionDof(kThz), held_b = m.WheelDof(kThz);
  std::vector<int> map(n, -1);
  int k = 0;
  for (int i = 0; i < n; ++i) {
    if (i != held_a && i != held_b) map[i] = k++;
  }
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < m.K.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(m.K, c); it; ++it) {
      if (map[it.row()] >= 0 && map[it.col()] >= 0)
        t.emplace_back(map[it.row()], map[it.col()], it.value());
    }
  }
  Eigen::SparseMatrix<double> Kc(k, k);
  Kc.setFromTriplets(t.begin(), t.end());
  Eigen::VectorXd v(k);
  for (int i = 0; i < n; ++i) {
    if (map[i] >= 0) v[map[i]] = m.v_drive[i];
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Kc);
  return v.dot(ldlt.solve(v));
}

StrainMagnitude ReducedStrainMagnitude(const ComponentModel& model, const ReducedModel& r,
                                       double mean_mesh_stiffness) {
  return [&model, &r, mean_mesh_stiffness](const Eigen::VectorXd& x) {
    return FullStrainMagnitude(model, mean_mesh_stiffness, r.recovery * x);
  };
}

std::vector<double> ReducedNaturalFrequencies(const ComponentModel& model, const ReducedModel& r,
                                              double mean_mesh_stiffness, int count,
                                              int* rigid_body_modes) {
  const Eigen::MatrixXd K = r.K + mean_mesh_stiffness * r.v_drive * r.v_drive.transpose();
  const NaturalModes modes = LowestNaturalModes(
      K, r.M, count, false, ReducedStrainMagnitude(model, r, mean_mesh_stiffness));
  if (rigid_body_modes) *rigid_body_modes = modes.rigid_body_modes;
  return modes.frequencies_hz;
}

ReducedModel ReduceModel(const ComponentModel& m, Tier tier, const ReductionOptions& options) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  RequireTierAvailable(m, tier);
  const double full_compliance = FullStaticMeshCompliance(m);
  const std::vector<int> boundary = Boundary(m, tier);
  const CraigBamptonBasis guyan = CraigBampton(m.K, m.M, boundary, 0, options);
  if (guyan.status != CraigBamptonStatus::kSuccess) {
    throw StructureNotReducible("cannot be reduced: " + guyan.message);
  }
  // The lowest fixed-interface modes of both shafts together, each shaft's interior solved on its
  // own (LowestFixedInterfaceModes), as a train's.
  std::vector<bool> is_boundary(static_cast<size_t>(m.dofs), false);
  for (int d : boundary) is_boundary[static_cast<size_t>(d)] = true;
  std::vector<std::vector<int>> interiors(2);
  for (int dof = 0; ModesOf(tier) > 0 && dof < m.dofs; ++dof) {
    if (!is_boundary[static_cast<size_t>(dof)])
      interiors[static_cast<size_t>(m.nodes[static_cast<size_t>(dof / 6)].shaft)].push_back(dof);
  }
  const FixedInterfaceModeSet fixed =
      LowestFixedInterfaceModes(m.K, m.M, interiors, ModesOf(tier), options);
  if (fixed.status != CraigBamptonStatus::kSuccess) {
    throw StructureNotReducible("cannot be reduced: " + fixed.message);
  }
  Eigen::MatrixXd T(m.dofs, guyan.T.cols() + fixed.shapes.cols());
  T << guyan.T, fixed.shapes;
  ReducedModel r = Project(m, T);
  r.boundary_dof = static_cast<int>(boundary.size());
  r.modal_dof = static_cast<int>(fixed.omega2.size());
  // Structural damping of the fixed-interface modes (mass-normalised: 2 zeta omega on the
  // diagonal).
  for (int j = 0; j < r.modal_dof; ++j) {
    r.C(r.boundary_dof + j, r.boundary_dof + j) +=
        2.0 * options.structural_damping_ratio * std::sqrt(fixed.omega2[j]);
  }
  if (tier == Tier::kN20Simple || tier == Tier::kN20Mta) {
    // Free-free modes of the tier-5 model, the lowest 20 kept (more where the cut would split a
    // cluster), M-normalised.
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(r.K, r.M);
    Eigen::MatrixXd basis =
        eig.eigenvectors().leftCols(ClusterCut(eig.eigenvalues(), kTruncatedModes));
    if (tier == Tier::kN20Mta) {
      // Residual vectors of both flanks' held and inertia-relief static shapes (the back flank's
      // line of action is another direction; residual_vectors.h). The two lowest modes are the
      // gear bodies' free rotations.
      Eigen::MatrixXd loads(r.dof, 2);
      loads << r.v_drive, r.v_back;
      const Eigen::MatrixXd relieved =
          InertiaRelievedLoads(loads, r.M, eig.eigenvectors().leftCols(2));
      Eigen::MatrixXd shapes(r.dof, 4);
      shapes << HeldStaticResponse(r, loads.col(0)), HeldStaticResponse(r, loads.col(1)),
          HeldStaticResponse(r, relieved.col(0)), HeldStaticResponse(r, relieved.col(1));
      basis = AugmentWithResiduals(std::move(basis), r.M, shapes);
    }
    ReducedModel t = Transform(r, basis);
    t.boundary_dof = 0;
    t.modal_dof = t.dof;
    r = std::move(t);
  }
  r.tier = tier;
  r.name = TierName(tier);
  Finish(m, r, full_compliance);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace gearnvh
