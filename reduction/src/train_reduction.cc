#include "gearnvh/reduction/train_reduction.h"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/modal_analysis.h"
#include "gearnvh/reduction/craig_bampton.h"
#include "gearnvh/reduction/sparse_modes.h"

namespace gearnvh {
namespace {

constexpr int kTier4ModesPerShaft = 4;
constexpr int kTier5ModesPerShaft = 14;
constexpr int kReportedFrequencies = 10;

int ModesPerShaft(Tier tier) {
  switch (tier) {
    case Tier::kTier4:
      return kTier4ModesPerShaft;
    case Tier::kTier5:
    case Tier::kN20Simple:
    case Tier::kN20Mta:
      return kTier5ModesPerShaft;
    default:
      return 0;
  }
}

// Gear nodes in gear order, without repeats (gears fixed on one rigid shaft share its node).
std::vector<int> GearNodes(const TrainStructure& s) {
  std::vector<int> nodes;
  for (int n : s.gear_node) {
    if (std::find(nodes.begin(), nodes.end(), n) == nodes.end()) nodes.push_back(n);
  }
  return nodes;
}

// One rotation per body: th_z at the node of its first gear (a body's nodes all carry th_z = 1 in
// its rigid rotation, so holding one removes it; the shaft's torsion between its gears stays).
std::vector<int> HeldDofs(const TrainStructure& s) {
  std::vector<int> first_node(static_cast<size_t>(s.body_rotations.cols()), -1);
  for (int n : s.gear_node) {
    int& f = first_node[static_cast<size_t>(s.node_body[static_cast<size_t>(n)])];
    if (f < 0) f = n;
  }
  std::vector<int> held;
  for (int n : first_node) held.push_back(TrainStructure::Dof(n, kThz));
  return held;
}

std::vector<int> Boundary(const TrainStructure& s, Tier tier) {
  std::vector<int> b;
  auto add = [&](int dof) {
    if (std::find(b.begin(), b.end(), dof) == b.end()) b.push_back(dof);
  };
  if (tier == Tier::kTier1 || tier == Tier::kTier2) {
    for (int d : HeldDofs(s)) add(d);
    if (tier == Tier::kTier2) {
      for (int n : GearNodes(s)) {
        add(TrainStructure::Dof(n, kUx));
        add(TrainStructure::Dof(n, kUy));
      }
    }
    return b;
  }
  for (int n : GearNodes(s)) {
    for (int d = 0; d < 6; ++d) add(TrainStructure::Dof(n, static_cast<NodeDof>(d)));
  }
  return b;
}

// Held static responses X (dof x meshes) of a dense model: K x_j = v_j on the null space Z of the
// held rows H (x = Z y, Z^T K Z y = Z^T v_j). Redundant held rows (two gears held through one rigid
// tier-1 rotation) would be dropped by the rank-revealing QR of H^T.
Eigen::MatrixXd HeldStaticResponses(const Eigen::MatrixXd& K, const Eigen::MatrixXd& H,
                                    const Eigen::MatrixXd& V) {
  const Eigen::Index n = K.rows();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(H.transpose());
  qr.setThreshold(1e-10);
  const Eigen::Index rank = qr.rank();
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd Z = Q.rightCols(n - rank);
  if (Z.cols() == 0) return Eigen::MatrixXd::Zero(n, V.cols());
  const Eigen::MatrixXd Kz = Z.transpose() * K * Z;
  return Z * Kz.ldlt().solve(Z.transpose() * V);
}

Eigen::MatrixXd Columns(const std::vector<Eigen::VectorXd>& v) {
  Eigen::MatrixXd m(v.empty() ? 0 : v.front().size(), static_cast<Eigen::Index>(v.size()));
  for (size_t i = 0; i < v.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = v[i];
  return m;
}

Eigen::MatrixXd Symmetric(const Eigen::MatrixXd& a) { return 0.5 * (a + a.transpose()); }

// Projects the structure onto the basis T (full DOF x n).
TrainReducedModel Project(const TrainStructure& s, const Eigen::MatrixXd& T) {
  TrainReducedModel r;
  r.dof = static_cast<int>(T.cols());
  r.recovery = T;
  r.M = Symmetric(T.transpose() * (s.M * T));
  r.K = Symmetric(T.transpose() * (s.K * T));
  r.C = Symmetric(T.transpose() * (s.C * T));
  const Eigen::MatrixXd g = T.transpose() * (s.G * T);
  r.G = 0.5 * (g - g.transpose());
  for (const TrainMeshVectors& m : s.meshes) {
    r.v_drive.push_back(T.transpose() * m.v_drive);
    r.v_back.push_back(T.transpose() * m.v_back);
  }
  r.body_rotations = T.transpose() * s.body_rotations;
  r.static_force = T.transpose() * s.static_force;
  return r;
}

// The held rows of a reduced model: the gear-rotation rows of its recovery matrix.
Eigen::MatrixXd HeldRows(const TrainStructure& s, const Eigen::MatrixXd& T) {
  const std::vector<int> held = HeldDofs(s);
  Eigen::MatrixXd H(static_cast<Eigen::Index>(held.size()), T.cols());
  for (size_t i = 0; i < held.size(); ++i) H.row(static_cast<Eigen::Index>(i)) = T.row(held[i]);
  return H;
}

Eigen::MatrixXd EngagedDense(const TrainStructure& s, const TrainReducedModel& r) {
  Eigen::MatrixXd k = r.K;
  for (size_t i = 0; i < r.v_drive.size(); ++i) {
    k += s.mean_stiffness[i] * r.v_drive[i] * r.v_drive[i].transpose();
  }
  return k;
}

}  // namespace

bool TrainTierAvailable(const TrainStructure& s, Tier tier) {
  return ModesPerShaft(tier) == 0 || !s.elastic_shafts.empty();
}

Eigen::MatrixXd FullStaticComplianceMatrix(const TrainStructure& s) {
  const int n = s.dofs;
  std::vector<int> map(static_cast<size_t>(n), 0);
  for (int d : HeldDofs(s)) map[static_cast<size_t>(d)] = -1;
  int k = 0;
  for (int i = 0; i < n; ++i) {
    if (map[static_cast<size_t>(i)] == 0) map[static_cast<size_t>(i)] = k++;
  }
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < s.K.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(s.K, c); it; ++it) {
      const int r = map[static_cast<size_t>(it.row())], col = map[static_cast<size_t>(it.col())];
      if (r >= 0 && col >= 0) t.emplace_back(r, col, it.value());
    }
  }
  Eigen::SparseMatrix<double> Kc(k, k);
  Kc.setFromTriplets(t.begin(), t.end());
  const Eigen::Index meshes = static_cast<Eigen::Index>(s.meshes.size());
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(k, meshes);
  for (Eigen::Index j = 0; j < meshes; ++j) {
    for (int i = 0; i < n; ++i) {
      if (map[static_cast<size_t>(i)] >= 0)
        V(map[static_cast<size_t>(i)], j) = s.meshes[j].v_drive[i];
    }
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Kc);
  if (ldlt.info() != Eigen::Success) {
    throw InputError("shafts", 0, "",
                     "cannot be solved statically: a direction that no bearing holds");
  }
  return Symmetric(V.transpose() * ldlt.solve(V));
}

NaturalModes FullTrainModes(const TrainStructure& s, int count, int dense_limit) {
  const Eigen::SparseMatrix<double> K = s.EngagedStiffness();
  if (s.dofs <= dense_limit) {
    return LowestNaturalModes(Eigen::MatrixXd(K), Eigen::MatrixXd(s.M), count);
  }
  return LowestSparseNaturalModes(K, s.M, count, static_cast<int>(s.free_rotations.cols()));
}

TrainReducedModel ReduceTrain(const TrainStructure& s, Tier tier, const ReductionOptions& options) {
  options.Validate();
  if (!TrainTierAvailable(s, tier)) {
    throw InputError("analysis.tier", 0, TierName(tier),
                     "needs at least one elastic shaft (with segments) in the train");
  }
  const std::vector<int> boundary = Boundary(s, tier);
  const CraigBamptonBasis guyan = CraigBampton(s.K, s.M, boundary, 0, options);
  if (guyan.status != CraigBamptonStatus::kSuccess) {
    throw InputError("shafts", 0, "", "cannot be reduced: " + guyan.message);
  }
  Eigen::MatrixXd T = guyan.T;
  std::vector<double> omega2;
  const int per_shaft = ModesPerShaft(tier);
  if (per_shaft > 0) {
    std::vector<bool> is_boundary(static_cast<size_t>(s.dofs), false);
    for (int d : boundary) is_boundary[static_cast<size_t>(d)] = true;
    for (int shaft : s.elastic_shafts) {
      std::vector<int> interior;
      for (size_t n = 0; n < s.nodes.size(); ++n) {
        if (s.node_body[n] != shaft) continue;
        for (int d = 0; d < 6; ++d) {
          const int dof = TrainStructure::Dof(static_cast<int>(n), static_cast<NodeDof>(d));
          if (!is_boundary[static_cast<size_t>(dof)]) interior.push_back(dof);
        }
      }
      const FixedInterfaceModeSet modes =
          FixedInterfaceModes(s.K, s.M, interior, per_shaft, options);
      if (modes.status != CraigBamptonStatus::kSuccess) {
        throw InputError("shafts", 0, "", "cannot be reduced: " + modes.message);
      }
      T.conservativeResize(Eigen::NoChange, T.cols() + modes.shapes.cols());
      T.rightCols(modes.shapes.cols()) = modes.shapes;
      for (Eigen::Index j = 0; j < modes.omega2.size(); ++j) omega2.push_back(modes.omega2[j]);
    }
  }
  TrainReducedModel r = Project(s, T);
  r.boundary_dof = static_cast<int>(boundary.size());
  r.modal_dof = static_cast<int>(omega2.size());
  // Structural damping of the fixed-interface modes (M-normalised: 2 zeta omega on the diagonal).
  for (int j = 0; j < r.modal_dof; ++j) {
    r.C(r.boundary_dof + j, r.boundary_dof + j) +=
        2.0 * options.structural_damping_ratio * std::sqrt(omega2[static_cast<size_t>(j)]);
  }
  if (tier == Tier::kN20Simple || tier == Tier::kN20Mta) {
    // As many free-free modes of tier 5 as tier 4 has DOF.
    const int keep = std::min(
        r.dof, r.boundary_dof + kTier4ModesPerShaft * static_cast<int>(s.elastic_shafts.size()));
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(r.K, r.M);
    Eigen::MatrixXd basis = eig.eigenvectors().leftCols(keep);
    if (tier == Tier::kN20Mta) {
      const Eigen::MatrixXd X =
          HeldStaticResponses(r.K, HeldRows(s, r.recovery), Columns(r.v_drive));
      const Eigen::MatrixXd R = X - basis * (basis.transpose() * r.M * X);
      // M-orthonormal residual vectors; a residual that the kept modes already span is dropped.
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> gram(Symmetric(R.transpose() * r.M * R));
      const double largest = gram.eigenvalues().size() > 0 ? gram.eigenvalues().maxCoeff() : 0.0;
      for (Eigen::Index k = 0; k < gram.eigenvalues().size(); ++k) {
        const double lambda = gram.eigenvalues()[k];
        if (!(lambda > 1e-14 * largest)) continue;
        basis.conservativeResize(Eigen::NoChange, basis.cols() + 1);
        basis.rightCols(1) = R * gram.eigenvectors().col(k) / std::sqrt(lambda);
      }
    }
    TrainReducedModel t = Project(s, r.recovery * basis);
    t.boundary_dof = 0;
    t.modal_dof = t.dof;
    r = std::move(t);
  }
  r.tier = tier;
  r.name = TierName(tier);
  r.full_static_compliance = FullStaticComplianceMatrix(s);
  r.static_compliance =
      Symmetric(Columns(r.v_drive).transpose() *
                HeldStaticResponses(r.K, HeldRows(s, r.recovery), Columns(r.v_drive)));
  const double full_norm = r.full_static_compliance.norm();
  r.compliance_error_vs_full =
      full_norm > 0.0 ? (r.static_compliance - r.full_static_compliance).norm() / full_norm : 0.0;
  const NaturalModes modes = LowestNaturalModes(EngagedDense(s, r), r.M, kReportedFrequencies);
  r.natural_frequencies_hz = modes.frequencies_hz;
  r.rigid_body_modes = modes.rigid_body_modes;
  return r;
}

}  // namespace gearnvh
