// Tiers of a gear train (reduction/train_reduction.h): the single pair's tiers reproduced, tier 1
// as TorsionalModes, the static compliance matrix at all meshes kept exactly by Craig–Bampton and
// MTA, and frequencies converging to the full FE model's as the tier rises.
#include "gearnvh/reduction/train_reduction.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "gearnvh/model/input_error.h"
#include "model/test_trains.h"

namespace gearnvh {
namespace {

struct Built {
  TrainSpec spec;
  GearTrain train;
  TrainStructure structure;
};

Built Build(const TrainSpec& spec) {
  ValidateTrainSpec(spec);
  Built b{spec, BuildGearTrain(spec), {}};
  b.structure = AssembleTrainStructure(b.spec, b.train);
  return b;
}

// Independent full-model compliance matrix: the dense saddle point [[K, H^T], [H, 0]] with H the
// rotation of each body's first gear held (the library removes the DOF and uses a sparse LDL^T).
Eigen::MatrixXd DenseHeldCompliance(const GearTrain& train, const TrainStructure& s) {
  std::vector<int> held;
  for (const TrainBody& body : train.topology.bodies) {
    held.push_back(TrainStructure::Dof(s.gear_node[static_cast<size_t>(body.gears.front())], kThz));
  }
  const int n = s.dofs, h = static_cast<int>(held.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n + h, n + h);
  A.topLeftCorner(n, n) = Eigen::MatrixXd(s.K);
  for (int i = 0; i < h; ++i)
    A(n + i, held[static_cast<size_t>(i)]) = A(held[static_cast<size_t>(i)], n + i) = 1.0;
  const int meshes = static_cast<int>(s.meshes.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + h, meshes);
  Eigen::MatrixXd V(n, meshes);
  for (int j = 0; j < meshes; ++j)
    V.col(j) = rhs.col(j).head(n) = s.meshes[static_cast<size_t>(j)].v_drive;
  return V.transpose() * A.fullPivLu().solve(rhs).topRows(n);
}

TEST_CASE("a schema-1 gearbox's train tiers are the pair's tiers", "[reduction][train]") {
  GearboxSpec spec = testing::StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 200.0;
  for (int s = 0; s < 2; ++s) {
    ShaftSpec shaft = testing::ElasticShaftSpec(0.01);
    shaft.gear_at = s == 0 ? 0.1 : 0.13;
    (s == 0 ? spec.input_shaft : spec.output_shaft) = shaft;
  }
  const ComponentModel pair = BuildComponentModel(spec);
  const Built t = Build(TrainOf(spec));
  for (Tier tier : kAllTiers) {
    CAPTURE(TierName(tier));
    const ReducedModel p = ReduceModel(pair, tier);
    const TrainReducedModel r = ReduceTrain(t.structure, tier);
    REQUIRE(r.dof == p.dof);
    // Same boundary, same Guyan condensation of matrices equal to rounding; the shift-invert
    // eigensolver of modal_analysis.h amplifies that rounding by ~w^2 / s (s = 1e-10 max
    // K_ii/M_ii), to ~1e-7 for the highest of these modes: 1e-6.
    REQUIRE(r.natural_frequencies_hz.size() == p.natural_frequencies_hz.size());
    for (size_t k = 0; k < p.natural_frequencies_hz.size(); ++k) {
      CHECK(r.natural_frequencies_hz[k] == Approx(p.natural_frequencies_hz[k]).epsilon(1e-6));
    }
    CHECK(r.static_compliance(0, 0) ==
          Approx(p.static_mesh_compliance).epsilon(1e-10).margin(1e-30));
    CHECK(r.rigid_body_modes == p.rigid_body_modes);
  }
  CHECK(FullStaticComplianceMatrix(t.structure)(0, 0) ==
        Approx(FullStaticMeshCompliance(pair)).epsilon(1e-12));
}

TEST_CASE("train tier 1 is the torsional model of TorsionalModes", "[reduction][train]") {
  for (const TrainSpec& spec : {testing::RigidTwoStage(), testing::ElasticTwoStage()}) {
    CAPTURE(spec.name);
    const Built t = Build(spec);
    const TrainTorsionalModes modes = TorsionalModes(t.train);
    const TrainReducedModel r = ReduceTrain(t.structure, Tier::kTier1);
    CHECK(r.dof == static_cast<int>(t.train.topology.bodies.size()));
    CHECK(r.rigid_body_modes == modes.free_rotations);
    REQUIRE(r.natural_frequencies_hz.size() == modes.frequencies_hz.size());
    // Guyan on one rotation per body turns every shaft rigidly: the same inertias (the FE's
    // consistent torsional mass sums to rho J L) and mesh stiffnesses, so the same eigenproblem.
    // The shift-invert solver of modal_analysis.h resolves w^2 to ~eps w^2 / s relative with
    // s = 1e-10 max K_ii/M_ii, i.e. up to ~1e-6 for the highest of these modes: 1e-5.
    for (size_t k = 0; k < modes.frequencies_hz.size(); ++k) {
      CHECK(r.natural_frequencies_hz[k] == Approx(modes.frequencies_hz[k]).epsilon(1e-5));
    }
  }
}

TEST_CASE("Craig-Bampton and MTA keep the static compliance matrix at all meshes",
          "[reduction][train][mta]") {
  const Built t = Build(testing::ElasticTwoStage());
  const Eigen::MatrixXd full = DenseHeldCompliance(t.train, t.structure);
  REQUIRE(full.rows() == 3);
  // The library's sparse solve against the dense saddle point: 1e-9 relative (condition of the
  // stiff-bearing/soft-shaft system ~1e6 times eps, with margin).
  CHECK((FullStaticComplianceMatrix(t.structure) - full).norm() < 1e-9 * full.norm());
  // The off-diagonal terms are real: the meshes on the layshaft deflect each other.
  CHECK(std::abs(full(0, 1)) > 1e-3 * std::sqrt(full(0, 0) * full(1, 1)));
  for (Tier tier : {Tier::kTier3, Tier::kTier4, Tier::kTier5, Tier::kN20Mta}) {
    CAPTURE(TierName(tier));
    const TrainReducedModel r = ReduceTrain(t.structure, tier);
    // Exact by construction (constraint modes; residual vectors): equal to rounding, 1e-8.
    CHECK((r.static_compliance - full).norm() < 1e-8 * full.norm());
    CHECK(r.compliance_error_vs_full < 1e-8);
  }
  // Modal truncation without residual vectors loses compliance (the check quantity MTA restores).
  const TrainReducedModel simple = ReduceTrain(t.structure, Tier::kN20Simple);
  const TrainReducedModel mta = ReduceTrain(t.structure, Tier::kN20Mta);
  CHECK(simple.compliance_error_vs_full > 1e-4);
  // A held shape per mesh and flank, and the inertia-relief directions beyond them: at most one per
  // elastic shaft (a rigid body's inertia load acts at its held rotation and deflects nothing);
  // this train's two elastic shafts give two (docs/design.md §3).
  CHECK(mta.dof == simple.dof + 6 + 2);
  // Why the vector form (docs/design.md §3): a spring g_res,j = G_full,jj - G_simple,jj in series
  // with each mesh restores each mesh's own compliance but not the meshes' coupling, which stays
  // simple truncation's; the residual vectors restore the whole matrix.
  Eigen::MatrixXd series = simple.static_compliance;
  series.diagonal() = full.diagonal();
  const double coupling_error = std::abs(series(0, 1) - full(0, 1)) / std::abs(full(0, 1));
  CAPTURE(coupling_error);
  // Simple truncation's coupling error on this train is 2.9e-3 (what a series spring would keep);
  // 1e-3 says it is a real miss, not rounding. MTA's 1e-8 as for the whole matrix above.
  CHECK(coupling_error > 1e-3);
  CHECK(std::abs(mta.static_compliance(0, 1) - full(0, 1)) < 1e-8 * std::abs(full(0, 1)));
}

TEST_CASE("train tier frequencies converge to the full FE model's as the tier rises",
          "[reduction][train]") {
  const Built t = Build(testing::ElasticTwoStage());
  const NaturalModes full = FullTrainModes(t.structure, 8);
  REQUIRE(full.rigid_body_modes == 1);
  std::vector<TrainReducedModel> tiers;
  for (Tier tier : {Tier::kTier1, Tier::kTier2, Tier::kTier3, Tier::kTier4, Tier::kTier5}) {
    tiers.push_back(ReduceTrain(t.structure, tier));
    CHECK(tiers.back().rigid_body_modes == 1);
  }
  // Nested Ritz subspaces (each tier's basis contains the one below): every frequency falls
  // monotonically as the tier rises and stays above the full model's (Rayleigh-Ritz interlacing;
  // slack 1e-9 for rounding).
  for (size_t i = 1; i < tiers.size(); ++i) {
    const auto& lower = tiers[i - 1].natural_frequencies_hz;
    const auto& upper = tiers[i].natural_frequencies_hz;
    for (size_t k = 0; k < std::min(lower.size(), upper.size()); ++k) {
      CAPTURE(i, k);
      CHECK(upper[k] <= lower[k] * (1.0 + 1e-9));
    }
  }
  for (const TrainReducedModel& r : tiers) {
    for (size_t k = 0; k < std::min(r.natural_frequencies_hz.size(), full.frequencies_hz.size());
         ++k) {
      CHECK(r.natural_frequencies_hz[k] >= full.frequencies_hz[k] * (1.0 - 1e-9));
    }
  }
  // Tier 5 (14 modes per elastic shaft, the lowest of all together) reaches the lowest six full-model frequencies within 1 %, and
  // closer than tier 3 (Guyan) does.
  for (size_t k = 0; k < 6; ++k) {
    CAPTURE(k);
    const double f = full.frequencies_hz[k];
    CHECK(std::abs(tiers[4].natural_frequencies_hz[k] - f) < 0.01 * f);
    CHECK(tiers[4].natural_frequencies_hz[k] - f <= tiers[2].natural_frequencies_hz[k] - f);
  }
  // MTA's basis lies in tier 5's: its frequencies stay above tier 5's.
  const TrainReducedModel mta = ReduceTrain(t.structure, Tier::kN20Mta);
  for (size_t k = 0; k < 6; ++k) {
    CHECK(mta.natural_frequencies_hz[k] >= tiers[4].natural_frequencies_hz[k] * (1.0 - 1e-9));
  }
}

TEST_CASE("the full model with massless shaft nodes has tier 3's modes on rigid shafts",
          "[reduction][train]") {
  // A flywheel (a torsional inertia only: its node's five other DOFs are massless, held by the
  // default support) coupled to the input, which drives two loose gears idling on a fixed output
  // shaft (massless too). On rigid shafts tier 3 keeps every gear DOF and condenses only massless
  // DOFs, which is exact: the full model's modes are tier 3's. (A rounding-level mass of a massless
  // DOF once set the eigensolver's shift to 1e31: 13 "rigid-body modes" and 1.5e7 Hz.)
  TrainSpec t;
  t.name = "neutral with a clutch damper";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {testing::RigidShaft("flywheel", 0.1), testing::RigidShaft("input", 0.01),
              testing::RigidShaft("output", 0.05)};
  t.shafts[2].fixed = true;
  t.gears = {testing::TrainGearOf("p", "input", 20), testing::TrainGearOf("p2", "input", 30),
             testing::TrainGearOf("w", "output", 40, Mounting::kLoose),
             testing::TrainGearOf("w2", "output", 30, Mounting::kLoose)};
  t.gears[1].at = 0.05;
  t.gears[3].at = 0.05;
  t.meshes = {testing::TrainMeshOf("p", "w"), testing::TrainMeshOf("p2", "w2")};
  TrainCoupling damper;
  damper.name = "clutch_damper";
  damper.shaft_a = "flywheel";
  damper.shaft_b = "input";
  damper.stiffness = 1000.0;
  t.couplings = {damper};
  t.operating.input_shaft = "flywheel";
  t.operating.speed = 1000.0 * 2.0 * M_PI / 60.0;
  t.operating.loads = {{"w", 0.2}, {"w2", 0.2}};
  const Built b = Build(t);
  const NaturalModes full = FullTrainModes(b.structure, 8);
  const TrainReducedModel tier3 = ReduceTrain(b.structure, Tier::kTier3);
  CHECK(full.rigid_body_modes == b.structure.free_rotations.cols());
  CHECK(full.rigid_body_modes == 2);  // the driven chain and the standing output shaft
  REQUIRE(full.frequencies_hz.size() == 8);
  REQUIRE(tier3.natural_frequencies_hz.size() >= 8);
  for (size_t k = 0; k < 8; ++k) {
    // Two eigensolutions of one pencil, one after an exact static condensation: rounding
    // amplified by the spread of the stiffnesses (1e3 to 1e9 N/m): 1e-7.
    CHECK(full.frequencies_hz[k] == Approx(tier3.natural_frequencies_hz[k]).epsilon(1e-7));
  }
  // The lowest mode is the clutch damper's, at the rigid torsional model's frequency less what the
  // mesh and lateral compliances take off it (1e-4; measured 5e-5).
  CHECK(full.frequencies_hz[0] ==
        Approx(TorsionalModes(b.train).frequencies_hz.front()).epsilon(1e-4));
}

TEST_CASE("a rigid-shaft train has tiers 1-3 only", "[reduction][train]") {
  const Built t = Build(testing::RigidTwoStage());
  CHECK(TrainTierAvailable(t.structure, Tier::kTier3));
  CHECK_FALSE(TrainTierAvailable(t.structure, Tier::kTier4));
  CHECK_THROWS_AS(ReduceTrain(t.structure, Tier::kTier5), InputError);
  const TrainReducedModel r = ReduceTrain(t.structure, Tier::kTier3);
  // Three rigid shafts (one node each) and the loose gear: four gear nodes of six DOF.
  CHECK(r.dof == 24);
}

}  // namespace
}  // namespace gearnvh
