#include "gearnvh/reduction/train_reduction.h"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <optional>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/modal_analysis.h"
#include "gearnvh/reduction/craig_bampton.h"
#include "gearnvh/reduction/sparse_modes.h"
#include "mode_cut.h"
#include "residual_vectors.h"

namespace gearnvh {
namespace {

constexpr int kTier4ModesPerShaft = 4;
constexpr int kTier5ModesPerShaft = 14;

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

// One rotation per body: th_z at its node (TrainStructure::body_node; a body's nodes all carry th_z
// = 1 in its rigid rotation, so holding one removes it; the shaft's torsion between its gears
// stays).
std::vector<int> HeldDofs(const TrainStructure& s) {
  std::vector<int> held;
  for (int n : s.body_node) held.push_back(TrainStructure::Dof(n, kThz));
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
  // A body without a gear that turns with it (a fixed shaft carrying only loose gears) keeps its
  // rotation: nothing in the interior holds it.
  for (int d : HeldDofs(s)) add(d);
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

// Projects the structure onto the basis T (full DOF x n). T is block-sparse (a shaft's constraint
// modes and fixed-interface modes vanish on the other shafts), so the products run sparse.
TrainReducedModel Project(const TrainStructure& s, const Eigen::MatrixXd& T) {
  TrainReducedModel r;
  r.dof = static_cast<int>(T.cols());
  r.recovery = T;
  const Eigen::SparseMatrix<double> t = T.sparseView();
  const Eigen::SparseMatrix<double> tt = t.transpose();
  auto project = [&](const Eigen::SparseMatrix<double>& a) {
    return Eigen::MatrixXd(Eigen::SparseMatrix<double>(tt * (a * t)));
  };
  r.M = Symmetric(project(s.M));
  r.K = Symmetric(project(s.K));
  r.C = Symmetric(project(s.C));
  const Eigen::MatrixXd g = project(s.G);
  r.G = 0.5 * (g - g.transpose());
  for (const TrainMeshVectors& m : s.meshes) {
    r.v_drive.push_back(tt * m.v_drive);
    r.v_back.push_back(tt * m.v_back);
  }
  for (const Eigen::VectorXd& w : s.coupling_twist) r.coupling_twist.push_back(tt * w);
  r.body_rotations = tt * s.body_rotations;
  r.static_force = tt * s.static_force;
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
  Eigen::MatrixXd k = r.K + CouplingStaticStiffness(s, r);
  for (size_t i = 0; i < r.v_drive.size(); ++i) {
    k += s.mean_stiffness[i] * r.v_drive[i] * r.v_drive[i].transpose();
  }
  return k;
}

// The lowest elastic modes of (K, M) with the free rotations F (columns, these coordinates) removed
// by construction: the pencil restricted to the M-orthogonal complement of F (as TorsionalModes
// does). A rounding-level eigenvalue of a free rotation could not be told from a slow elastic mode
// by a zero test once the stiffest DOF is ~1e12 times stiffer; the count of free rotations is
// known from the meshes (FreeRotations). Further rigid-body modes (a direction no bearing holds)
// are still counted by the scale-aware criterion.
// Shapes, when asked, are M-normalised in the coordinates of K (x = Z y).
NaturalModes ModesWithoutFreeRotations(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M,
                                       const Eigen::MatrixXd& F, int count,
                                       bool with_shapes = false) {
  const Eigen::Index n = K.rows(), f = F.cols();
  if (f == 0) return LowestNaturalModes(K, M, count, with_shapes);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(M * F);
  const Eigen::MatrixXd Z = (qr.householderQ() * Eigen::MatrixXd::Identity(n, n)).rightCols(n - f);
  NaturalModes modes = LowestNaturalModes(Symmetric(Z.transpose() * K * Z),
                                          Symmetric(Z.transpose() * M * Z), count, with_shapes);
  modes.rigid_body_modes += static_cast<int>(f);
  if (with_shapes) modes.shapes = (Z * modes.shapes).eval();
  return modes;
}

// The free rotations in reduced coordinates: the M-orthogonal projection of the physical ones.
Eigen::MatrixXd ReducedFreeRotations(const TrainStructure& s, const TrainReducedModel& r) {
  return r.M.ldlt().solve(r.recovery.transpose() * (s.M * s.free_rotations));
}

}  // namespace

NaturalModes TrainReducedModes(const TrainStructure& s, const TrainReducedModel& r, int count,
                               bool with_shapes) {
  return ModesWithoutFreeRotations(EngagedDense(s, r), r.M, ReducedFreeRotations(s, r), count,
                                   with_shapes);
}

Eigen::MatrixXd CouplingStaticStiffness(const TrainStructure& structure,
                                        const TrainReducedModel& reduced) {
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(reduced.dof, reduced.dof);
  for (size_t j = 0; j < reduced.coupling_twist.size(); ++j) {
    const Eigen::VectorXd& w = reduced.coupling_twist[j];
    k += structure.coupling_static_increment[j] * w * w.transpose();
  }
  return k;
}

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
    throw StructureNotReducible("cannot be solved statically: a direction that no bearing holds");
  }
  return Symmetric(V.transpose() * ldlt.solve(V));
}

NaturalModes FullTrainModes(const TrainStructure& s, int count, int dense_limit, bool with_shapes) {
  const Eigen::SparseMatrix<double> K = s.EngagedStiffness();
  if (s.dofs <= dense_limit) {
    return ModesWithoutFreeRotations(Eigen::MatrixXd(K), Eigen::MatrixXd(s.M), s.free_rotations,
                                     count, with_shapes);
  }
  // Lanczos cannot restrict to the complement cheaply: the known number of free rotations are the
  // lowest eigenpairs, dropped when the zero test did not already classify them.
  const int free = static_cast<int>(s.free_rotations.cols());
  NaturalModes modes = LowestSparseNaturalModes(K, s.M, count + free, free);
  const int unclassified = std::max(0, free - modes.rigid_body_modes);
  const int drop = std::min(unclassified, static_cast<int>(modes.frequencies_hz.size()));
  modes.frequencies_hz.erase(modes.frequencies_hz.begin(), modes.frequencies_hz.begin() + drop);
  if (modes.shapes.cols() >= drop) {
    modes.shapes = modes.shapes.rightCols(modes.shapes.cols() - drop).eval();
  }
  modes.rigid_body_modes += drop;
  if (static_cast<int>(modes.frequencies_hz.size()) > count) {
    modes.frequencies_hz.resize(static_cast<size_t>(count));
    modes.shapes = modes.shapes.leftCols(count).eval();
  }
  return modes;
}

namespace {

// Tiers 1-5: the Guyan/Craig–Bampton basis projected, with modal damping on the fixed-interface
// modes.
TrainReducedModel CraigBamptonTier(const TrainStructure& s, Tier tier,
                                   const ReductionOptions& options) {
  const std::vector<int> boundary = Boundary(s, tier);
  const CraigBamptonBasis guyan = CraigBampton(s.K, s.M, boundary, 0, options);
  if (guyan.status != CraigBamptonStatus::kSuccess) {
    throw StructureNotReducible("cannot be reduced: " + guyan.message);
  }
  Eigen::MatrixXd T = guyan.T;
  std::vector<double> omega2;
  const int per_shaft = ModesPerShaft(tier);
  if (per_shaft > 0) {
    // The lowest fixed-interface modes of all elastic shafts together (a shaft with lower modes
    // gets more of them), each shaft's interior solved on its own.
    std::vector<bool> is_boundary(static_cast<size_t>(s.dofs), false);
    for (int d : boundary) is_boundary[static_cast<size_t>(d)] = true;
    std::vector<std::vector<int>> interiors;
    for (int shaft : s.elastic_shafts) {
      std::vector<int>& interior = interiors.emplace_back();
      for (size_t n = 0; n < s.nodes.size(); ++n) {
        if (s.node_body[n] != shaft) continue;
        for (int d = 0; d < 6; ++d) {
          const int dof = TrainStructure::Dof(static_cast<int>(n), static_cast<NodeDof>(d));
          if (!is_boundary[static_cast<size_t>(dof)]) interior.push_back(dof);
        }
      }
    }
    const FixedInterfaceModeSet modes = LowestFixedInterfaceModes(
        s.K, s.M, interiors, per_shaft * static_cast<int>(s.elastic_shafts.size()), options);
    if (modes.status != CraigBamptonStatus::kSuccess) {
      throw StructureNotReducible("cannot be reduced: " + modes.message);
    }
    T.conservativeResize(Eigen::NoChange, T.cols() + modes.shapes.cols());
    T.rightCols(modes.shapes.cols()) = modes.shapes;
    for (Eigen::Index j = 0; j < modes.omega2.size(); ++j) omega2.push_back(modes.omega2[j]);
  }
  TrainReducedModel r = Project(s, T);
  r.boundary_dof = static_cast<int>(boundary.size());
  r.modal_dof = static_cast<int>(omega2.size());
  // Structural damping of the fixed-interface modes (M-normalised: 2 zeta omega on the diagonal).
  for (int j = 0; j < r.modal_dof; ++j) {
    r.C(r.boundary_dof + j, r.boundary_dof + j) +=
        2.0 * options.structural_damping_ratio * std::sqrt(omega2[static_cast<size_t>(j)]);
  }
  r.tier = tier;
  return r;
}

// A change of coordinates x = P y of a reduced model.
TrainReducedModel Transform(const TrainReducedModel& a, const Eigen::MatrixXd& P) {
  TrainReducedModel r;
  r.dof = static_cast<int>(P.cols());
  r.recovery = a.recovery * P;
  r.M = Symmetric(P.transpose() * a.M * P);
  r.K = Symmetric(P.transpose() * a.K * P);
  r.C = Symmetric(P.transpose() * a.C * P);
  const Eigen::MatrixXd g = P.transpose() * a.G * P;
  r.G = 0.5 * (g - g.transpose());
  for (size_t i = 0; i < a.v_drive.size(); ++i) {
    r.v_drive.push_back(P.transpose() * a.v_drive[i]);
    r.v_back.push_back(P.transpose() * a.v_back[i]);
  }
  for (const Eigen::VectorXd& w : a.coupling_twist) r.coupling_twist.push_back(P.transpose() * w);
  r.body_rotations = P.transpose() * a.body_rotations;
  r.static_force = P.transpose() * a.static_force;
  return r;
}

// N20 simple / MTA from tier 5: as many free-free modes as tier 4 has DOF (more where the cut
// would split a cluster), and for MTA the residual vectors of every mesh and flank's held and
// inertia-relief static shapes.
TrainReducedModel Truncate(const TrainStructure& s, const TrainReducedModel& tier5, Tier tier) {
  const int keep =
      tier5.boundary_dof + kTier4ModesPerShaft * static_cast<int>(s.elastic_shafts.size());
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(tier5.K, tier5.M);
  Eigen::MatrixXd basis = eig.eigenvectors().leftCols(ClusterCut(eig.eigenvalues(), keep));
  if (tier == Tier::kN20Mta) {
    // Both flanks' held and inertia-relief static shapes of every mesh (a back flank's line of
    // action is another direction; residual_vectors.h). The lowest modes, one per held rotation,
    // are the bodies' free rotations.
    const Eigen::MatrixXd held = HeldRows(s, tier5.recovery);
    const Eigen::Index loads = 2 * static_cast<Eigen::Index>(tier5.v_drive.size());
    Eigen::MatrixXd V(tier5.dof, 2 * loads);
    V.leftCols(loads) << Columns(tier5.v_drive), Columns(tier5.v_back);
    V.rightCols(loads) =
        InertiaRelievedLoads(V.leftCols(loads), tier5.M, eig.eigenvectors().leftCols(held.rows()));
    basis = AugmentWithResiduals(std::move(basis), tier5.M, HeldStaticResponses(tier5.K, held, V));
  }
  TrainReducedModel r = Transform(tier5, basis);
  r.boundary_dof = 0;
  r.modal_dof = r.dof;
  r.tier = tier;
  return r;
}

// Names, compliance matrix against the full model's, natural frequencies.
void Finish(const TrainStructure& s, const Eigen::MatrixXd& full_compliance, TrainReducedModel& r) {
  r.name = TierName(r.tier);
  r.full_static_compliance = full_compliance;
  r.static_compliance =
      Symmetric(Columns(r.v_drive).transpose() *
                HeldStaticResponses(r.K, HeldRows(s, r.recovery), Columns(r.v_drive)));
  const double full_norm = full_compliance.norm();
  r.compliance_error_vs_full =
      full_norm > 0.0 ? (r.static_compliance - full_compliance).norm() / full_norm : 0.0;
  const NaturalModes modes = TrainReducedModes(s, r, kReportedFrequencies);
  r.natural_frequencies_hz = modes.frequencies_hz;
  r.rigid_body_modes = modes.rigid_body_modes;
}

}  // namespace

std::vector<TrainReducedModel> ReduceTrainTiers(const TrainStructure& s,
                                                const std::vector<Tier>& tiers,
                                                const ReductionOptions& options) {
  options.Validate();
  for (Tier tier : tiers) {
    if (!TrainTierAvailable(s, tier)) {
      throw TierNotAvailable(tier, "needs at least one elastic shaft (with segments) in the train");
    }
  }
  const Eigen::MatrixXd full_compliance = FullStaticComplianceMatrix(s);
  std::optional<TrainReducedModel> tier5;  // shared by tier 5, N20 simple and N20 MTA
  auto tier5_model = [&]() -> const TrainReducedModel& {
    if (!tier5) tier5 = CraigBamptonTier(s, Tier::kTier5, options);
    return *tier5;
  };
  std::vector<TrainReducedModel> out;
  for (Tier tier : tiers) {
    TrainReducedModel r = tier == Tier::kN20Simple || tier == Tier::kN20Mta
                              ? Truncate(s, tier5_model(), tier)
                          : tier == Tier::kTier5 ? tier5_model()
                                                 : CraigBamptonTier(s, tier, options);
    Finish(s, full_compliance, r);
    out.push_back(std::move(r));
  }
  return out;
}

TrainReducedModel ReduceTrain(const TrainStructure& s, Tier tier, const ReductionOptions& options) {
  return std::move(ReduceTrainTiers(s, {tier}, options).front());
}

Eigen::MatrixXd BearingPointRows(const StructureBearing& bearing,
                                 const TrainReducedModel& reduced) {
  const Eigen::MatrixXd& T = reduced.recovery;
  const auto row = [&](NodeDof d) { return T.row(TrainStructure::Dof(bearing.node, d)); };
  Eigen::MatrixXd p(3, T.cols());
  p.row(0) = row(kUx) + bearing.offset * row(kThy);
  p.row(1) = row(kUy) - bearing.offset * row(kThx);
  p.row(2) = row(kUz);
  return p;
}

}  // namespace gearnvh
