// The train solver on the reduced tiers of a train (solver/train_reduced_tables.h): tier-k tables
// against tier 1 on a stiff train, against CVODE and against the linear periodic solution.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/reduction/train_reduction.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

// Two loaded stages, input (rigid) -> layshaft (elastic: g2 at 50 mm, g3 at 150 mm) -> output
// (rigid), every shaft on bearings; an engine order 2 of `excitation` rad/s^2.
TrainSpec FlexibleTwoStage(double load, double excitation, double rpm) {
  TrainSpec t = testing::TwoStageTrain(load, excitation, rpm);
  t.shafts[0].bearings = {{0.0, 3e8, 1e8, 1e3, 500.0}, {0.08, 3e8, 0.0, 1e3, 500.0}};
  t.shafts[2].bearings = t.shafts[0].bearings;
  t.shafts[1].inertia.reset();
  t.shafts[1].elastic = testing::ElasticShaftSpec();
  t.gears[1].at = 0.05;
  t.gears[2].at = 0.15;
  return t;
}

// The same train made stiff: every bearing and support 1e11 N/m (tilt 1e7 N m/rad) and the
// layshaft's modulus x 1e4, so that only the torsional motion of tier 1 is left.
TrainSpec StiffTwoStage(double load, double excitation, double rpm) {
  TrainSpec t = FlexibleTwoStage(load, excitation, rpm);
  // The layshaft's own material (the gears keep steel: the mesh stiffness does not change).
  t.materials["stiff steel"] = t.materials["steel"];
  t.materials["stiff steel"].youngs_modulus *= 1e4;
  t.shafts[1].elastic->material = "stiff steel";
  for (TrainShaft& s : t.shafts) {
    std::vector<BearingSpec>& bearings = s.elastic ? s.elastic->bearings : s.bearings;
    for (BearingSpec& b : bearings) {
      b.radial_stiffness = 1e11;
      b.axial_stiffness = 1e11;
      b.tilt_stiffness = 1e7;
    }
  }
  return t;
}

struct TierModel {
  TrainSpec spec;
  GearTrain train;
  TrainTables tables;
  TierModel(TrainSpec s, Tier tier, const TrainTableOptions& options = {})
      : spec(std::move(s)),
        train(BuildGearTrain(spec)),
        tables(BuildTrainTablesAtTier(spec, train, tier, options)) {}
};

// TE of every mesh at `times` from the static state.
Eigen::MatrixXd TeSamples(const TrainTables& t, const std::vector<double>& times,
                          const TrainStepperOptions& options = {}) {
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepper stepper(t, options, z0, states0);
  Eigen::MatrixXd te(static_cast<Eigen::Index>(times.size()),
                     static_cast<Eigen::Index>(t.meshes.size()));
  for (size_t k = 0; k < times.size(); ++k) {
    REQUIRE(stepper.Run(times[k]));
    for (size_t i = 0; i < t.meshes.size(); ++i)
      te(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) =
          t.meshes[i].v.dot(stepper.state().head(t.n));
  }
  return te;
}

TEST_CASE("train tiers: the reduced tables are consistent (generator, flanks, free rotation)",
          "[solver][train][tiers]") {
  const TierModel s(FlexibleTwoStage(100.0, 500.0, 600.0), Tier::kTier3);
  const TrainTables& t = s.tables;
  CHECK(t.tier == Tier::kTier3);
  CHECK(t.bodies() == 3);
  CHECK(t.n > t.bodies());
  CHECK(t.m == 2 * t.n + 1 + t.excitation_states());  // x, x', 1 and the orders' states
  // Tier 3 keeps the lateral terms: the back flank's vector differs from the drive flank's.
  for (const TrainMeshTable& mt : t.meshes) CHECK(mt.distinct_back);
  // The free rotation is neutral: no gap sees it and the structure does not resist it (rounding
  // of the projection x_r = M^-1 T^T M R: 1e-9 of the norms is far below a real residual, which
  // would be O(1)).
  for (const TrainMeshTable& mt : t.meshes) {
    CHECK(std::abs(mt.v.dot(t.rigid_rotation)) <= 1e-9 * mt.v.norm());
    CHECK(std::abs(mt.v_back.dot(t.rigid_rotation)) <= 1e-9 * mt.v_back.norm());
  }
  CHECK((t.structural_stiffness * t.rigid_rotation).norm() <= 1e-9 * t.structural_stiffness.norm());
  // The cache's generator equals an independent assembly for every drive/free/back combination.
  TrainSystemCache cache(t, {});
  TupleKey key(static_cast<size_t>(cache.KeyWords()));
  const ContactState all[3] = {ContactState::kBack, ContactState::kFree, ContactState::kDrive};
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const std::vector<int> seg = {3, 7};
      const std::vector<ContactState> st = {all[a], all[b]};
      const Eigen::MatrixXd A = cache.Get(seg, st, key).A;
      const Eigen::MatrixXd B = AssembleTrainGenerator(t, seg, st);
      // Two assemblies of the same sums in different order: a few ulps of the largest entry.
      CHECK((A - B).cwiseAbs().maxCoeff() <= 1e-13 * B.cwiseAbs().maxCoeff());
    }
  }
}

TEST_CASE("train tiers: a stiff train gives tier 1's TE at tiers 2 and 3",
          "[solver][train][tiers]") {
  // Bearings 1e11 N/m against mesh stiffnesses ~3e8 N/m and a layshaft 1e4 times stiffer: the
  // lateral, axial and shaft deformations are ~3e-3 of the mesh deflection and their modes far
  // above the mesh frequencies, so every tier reduces to tier 1's torsional train. Permanent
  // contact (load 200 N m, an engine order) keeps the comparison free of rattle's amplification.
  // (Stiffer bearings leave the lateral modes of x and y degenerate and uncoupled: every
  // decomposition is then ill-conditioned and the dense path, exact but slow at those
  // frequencies, takes every piece.)
  const TrainSpec spec = StiffTwoStage(200.0, 3000.0, 600.0);
  TrainStepperOptions options;
  const TierModel one(spec, Tier::kTier1);
  const double period = one.tables.meshes.front().period;
  std::vector<double> times;
  for (int k = 1; k <= 16; ++k) times.push_back(k * period / 8.0);  // 2 cycles of the first mesh
  // The mesh deflection TE - b (what the structure's compliance would change), per mesh.
  const auto deflection = [](const TrainTables& t, Eigen::MatrixXd te) {
    for (size_t i = 0; i < t.meshes.size(); ++i)
      te.col(static_cast<Eigen::Index>(i)).array() -= t.meshes[i].half_backlash;
    return te;
  };
  const Eigen::MatrixXd d1 = deflection(one.tables, TeSamples(one.tables, times, options));
  const double scale = d1.cwiseAbs().maxCoeff();
  const Eigen::MatrixXd dyn1 = d1.rowwise() - d1.colwise().mean();
  const double dyn_scale = dyn1.cwiseAbs().maxCoeff();
  REQUIRE(dyn_scale > 1e-3 * scale);  // the excitation does move the TE
  for (Tier tier : {Tier::kTier2, Tier::kTier3}) {
    const TierModel k(spec, tier, options.tables);
    const Eigen::MatrixXd dk = deflection(k.tables, TeSamples(k.tables, times, options));
    const double diff = (dk - d1).cwiseAbs().maxCoeff();
    const Eigen::MatrixXd dynk = dk.rowwise() - dk.colwise().mean();
    const double dyn_diff = (dynk - dyn1).cwiseAbs().maxCoeff();
    INFO(TierName(tier) << ": deflection difference " << diff << " m of " << scale
                        << " m; dynamic part " << dyn_diff << " m of " << dyn_scale << " m");
    // Tolerance: 2e-2 of the deflection and of its dynamic part, above the stiff structure's
    // own compliance (~3e-3 of the mesh's; measured 2.8e-3 and 6.6e-3) and far below what a missing
    // mesh term, a wrong inertia or a wrong load mapping would change (O(1)).
    CHECK(diff <= 2e-2 * scale);
    CHECK(dyn_diff <= 2e-2 * dyn_scale);
  }
}

TEST_CASE("train tiers: friction has tier 1's effect at tiers 2 and 3 on a stiff train",
          "[solver][train][tiers][friction]") {
  // The stiff train of the test above with mu = 0.06 on both meshes: friction's effect on each
  // mesh's deflection (with minus without) at tiers 2 and 3 against tier 1's. The reduced tiers
  // carry the full friction vector (sliding translations, arms on s_a th_z of both gears) in their
  // own coordinates and the loss torque at the input's first gear; a wrong sign or mapping of any
  // part changes the effect by O(1).
  TrainSpec spec = StiffTwoStage(200.0, 3000.0, 600.0);
  TrainSpec rough = spec;
  for (TrainMesh& m : rough.meshes) m.mesh.friction_coefficient = 0.06;
  const TierModel one(spec, Tier::kTier1), one_rough(rough, Tier::kTier1);
  const double period = one.tables.meshes.front().period;
  std::vector<double> times;
  for (int k = 1; k <= 16; ++k) times.push_back(k * period / 8.0);
  const Eigen::MatrixXd effect1 = TeSamples(one_rough.tables, times) - TeSamples(one.tables, times);
  const double scale = effect1.cwiseAbs().maxCoeff();
  REQUIRE(scale > 1e-8);  // friction moves the deflection (~1e-5 m) by a few per cent
  for (Tier tier : {Tier::kTier2, Tier::kTier3}) {
    const TierModel k(spec, tier), k_rough(rough, tier);
    for (const TrainMeshTable& mt : k_rough.tables.meshes) REQUIRE(mt.has_friction());
    CHECK(k_rough.tables.friction_loss_torque == one_rough.tables.friction_loss_torque);
    // The generator with friction equals the independent (CVODE) assembly.
    TrainSystemCache cache(k_rough.tables, {});
    TupleKey key(static_cast<size_t>(cache.KeyWords()));
    for (const ContactState st : {ContactState::kDrive, ContactState::kBack}) {
      const std::vector<int> seg = {3, 7};
      const std::vector<ContactState> states = {st, ContactState::kDrive};
      const Eigen::MatrixXd B = AssembleTrainGenerator(k_rough.tables, seg, states);
      CHECK((cache.Get(seg, states, key).A - B).cwiseAbs().maxCoeff() <=
            1e-13 * B.cwiseAbs().maxCoeff());
    }
    const Eigen::MatrixXd effect = TeSamples(k_rough.tables, times) - TeSamples(k.tables, times);
    const double diff = (effect - effect1).cwiseAbs().maxCoeff();
    INFO(TierName(tier) << ": friction's effect differs from tier 1's by " << diff << " m of "
                        << scale << " m");
    // Tolerance: 5e-2 of the effect, above the stiff structure's own share (~3e-3 to 7e-3 of the
    // deflection and its dynamic part, above) and the sliding translations on 1e11 N/m bearings,
    // far below an error of sign or mapping (O(1)). Measured 1.1e-2 at tiers 2 and 3.
    CHECK(diff <= 5e-2 * scale);
  }
}

TEST_CASE("train tiers: a flexible rattling train agrees with CVODE at tier 3",
          "[solver][train][tiers][reference]") {
  // The elastic two-stage train of the model tests (three meshes, a helical stage, a loose gear
  // with drag, both senses of rotation) at tier 3, with an engine order so that the loose gear
  // rattles.
  TrainSpec spec = testing::ElasticTwoStage();
  spec.operating.excitation = {{2.0, 3000.0, 0.0}};
  spec.analysis.segments_per_cycle = 8;
  const TierModel s(spec, Tier::kTier3);
  const TrainTables& t = s.tables;
  const auto [z0, states0] = TrainStaticState(t);
  TrainReferenceOptions ro;
  ro.end_time = 0.006;
  ro.rtol = 1e-13;
  ro.sample_interval = t.meshes[0].period / 8.0;
  const TrainReferenceResult ref = SimulateTrainReference(t, z0, states0, ro);
  REQUIRE(ref.success);
  INFO(ref.events.size() << " reference events");
  REQUIRE(ref.events.size() >= 2);
  TrainStepper stepper(t, {}, z0, states0);
  double worst = 0.0;
  const double scale = ref.te.cwiseAbs().maxCoeff();
  for (size_t k = 0; k < ref.sample_times.size(); ++k) {
    REQUIRE(stepper.Run(ref.sample_times[k]));
    for (size_t i = 0; i < t.meshes.size(); ++i) {
      const double te = t.meshes[i].v.dot(stepper.state().head(t.n));
      worst = std::max(
          worst, std::abs(te - ref.te(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i))));
    }
  }
  // Tolerance: the 1e-8 of the TE (CVODE at rtol 1e-13; a short horizon because rattle
  // amplifies any difference, as at tier 1).
  INFO("worst TE difference " << worst << " m of " << scale << " m, " << stepper.summary().events
                              << " events");
  CHECK(worst <= 1e-8 * scale);
  // The same contact events inside the compared window.
  long inside = 0;
  for (const TrainReferenceEvent& e : ref.events) inside += e.time <= ref.sample_times.back();
  CHECK(stepper.summary().events - stepper.summary().start_switches == inside);
}

TEST_CASE("train tiers: permanent contact at tier 3 equals the linear periodic steady state",
          "[solver][train][tiers]") {
  // As the tier-1 test: every mesh in drive contact, the period map from dense Pade propagators
  // of an independent assembly and its fixed point (COD: the free rotation is the one null
  // direction).
  const TierModel s(FlexibleTwoStage(300.0, 100.0, 300.0), Tier::kTier3);
  const TrainTables& t = s.tables;
  const int n = t.n;
  REQUIRE(t.common_period > 0.0);
  const testing::LinearPeriodicState orbit = testing::DriveContactPeriodicState(t);
  const std::vector<ContactState> drive(2, ContactState::kDrive);
  const Eigen::VectorXd& z = orbit.z;
  TrainStepper stepper(t, {}, z, drive);
  double te_scale = 0.0, worst = 0.0;
  Eigen::VectorXd reference = z;
  for (const testing::LinearPeriodicState::Piece& piece : orbit.pieces) {
    reference = piece.map * reference;
    REQUIRE(stepper.Run(piece.start + piece.h));
    for (const TrainMeshTable& mt : t.meshes) {
      const double expected = mt.v.dot(reference.head(n));
      te_scale = std::max(te_scale, std::abs(expected));
      worst = std::max(worst, std::abs(mt.v.dot(stepper.state().head(n)) - expected));
    }
  }
  CHECK(stepper.summary().events == 0);
  // Tolerance: 1e-9 of the TE (tier 1: 1e-11). The tier-3 model's bearing modes are ~100x
  // faster than its mesh modes, so its decompositions are worse conditioned (measured 2e-10 of
  // the TE); still far below any modelling difference (a wrong segment stiffness or a missing
  // structural term moves the TE by > 1e-4 of it).
  INFO("worst TE difference " << worst << " m, TE scale " << te_scale << " m");
  CHECK(worst <= 1e-9 * te_scale);
}

TEST_CASE("train tiers: the loose gear's rattle index uses its own rotation at tier 3",
          "[solver][train][tiers]") {
  // The body-angle row of each body is its first gear's th_z in its sense of rotation: applied to
  // the free rotation it gives the body's share of the rigid motion, |w_b| / |w_in| times the
  // input's (the nominal speed ratios), for the loose gear as for the shafts.
  const TierModel s(testing::ElasticTwoStage(), Tier::kTier3);
  const TrainTables& t = s.tables;
  const Eigen::VectorXd angles = t.body_angles * t.rigid_rotation;
  const int in = s.train.topology.input_body;
  for (int b = 0; b < t.bodies(); ++b) {
    const double ratio = std::abs(s.train.topology.bodies[static_cast<size_t>(b)].speed /
                                  s.train.topology.bodies[static_cast<size_t>(in)].speed);
    // Tolerance: rounding of the projection (1e-9, as above).
    CHECK(std::abs(angles[b] - ratio * angles[in]) <= 1e-9 * std::abs(angles[in]));
  }
}

TEST_CASE("train tiers: a rigid shaft's inertia does not shorten the tier-3 sub-step",
          "[solver][train][tiers]") {
  // The flexible two-stage train with the rigid input shaft's lumped inertia at 8 and at 1000
  // kg m^2. That inertia is torsional (model/train_structure.cc): were it a polar inertia with
  // gyroscopic moment w J on the input node's tilts (whose tilt inertia is g1's I_d alone), the
  // tier-3 generator would carry a nutation at ~w J / I_d, growing in proportion to J (125x from 8
  // to 1000: ~1e8 rad/s at 600 rpm), and the dense sub-step 1/(2 rho) would shrink by as much.
  // Without it a heavier torsional inertia can only lower the undamped frequencies (Rayleigh) and
  // the damping rate lambda_max(M^-1 C); the tier-3 basis changes with J, so the bound and the
  // largest |eigenvalue| of the drive tuple's generator may move a little: factor 1.05.
  auto drive_tuple = [](double j) {
    TrainSpec spec = FlexibleTwoStage(100.0, 0.0, 600.0);
    spec.shafts[0].inertia = j;
    const TierModel s(spec, Tier::kTier3);
    TrainSystemCache cache(s.tables, {});
    TupleKey key(static_cast<size_t>(cache.KeyWords()));
    const TrainSystem sys =
        cache.Get(std::vector<int>(s.tables.meshes.size(), 0),
                  std::vector<ContactState>(s.tables.meshes.size(), ContactState::kDrive), key);
    const Eigen::EigenSolver<Eigen::MatrixXd> eig(sys.A, false);
    REQUIRE(eig.info() == Eigen::Success);
    return std::pair{sys.rho, eig.eigenvalues().cwiseAbs().maxCoeff()};
  };
  const auto [rho_light, lambda_light] = drive_tuple(8.0);
  const auto [rho_heavy, lambda_heavy] = drive_tuple(1000.0);
  INFO("rho " << rho_light << " -> " << rho_heavy << " 1/s, max |lambda| " << lambda_light
              << " -> " << lambda_heavy);
  CHECK(lambda_heavy <= rho_heavy);  // the bound holds
  CHECK(rho_heavy <= 1.05 * rho_light);
  CHECK(lambda_heavy <= 1.05 * lambda_light);
}

}  // namespace
}  // namespace gearnvh
