// Tooth friction on gear trains (solver/train_tables.h): against the schema-1 pair's solver, the
// power balance of the static torque flow, CVODE, and the frictionless model.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_specs.h"
#include "model/test_trains.h"
#include "solver/solver_fixture.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;
using testing::MeshTe;

TrainSpec WithFriction(TrainSpec spec, double mu) {
  for (TrainMesh& m : spec.meshes) m.mesh.friction_coefficient = mu;
  return spec;
}

// The pair's state z (tier 1: pinion and wheel th_z about +z) as the one-mesh train's (running
// angles: theta_a = th_z pinion, theta_b = -th_z wheel), at rest in the rigid rotation's frame.
Eigen::VectorXd TrainStateOf(const testing::SolverSetup& pair, const TrainTables& t,
                             const Eigen::VectorXd& z) {
  const int n = pair.tables.n;
  const TrainMeshTable& mt = t.meshes[0];
  Eigen::VectorXd out = Eigen::VectorXd::Zero(t.m);
  for (int part = 0; part < 2; ++part) {
    const Eigen::VectorXd x = z.segment(part * n, n);
    out[part * t.n + mt.body_a] = pair.reduced.pinion_torsion.dot(x);
    out[part * t.n + mt.body_b] = -pair.reduced.wheel_torsion.dot(x);
  }
  out[t.constant_slot()] = 1.0;
  return out;
}

TEST_CASE("train friction: a one-mesh train with friction has the pair's TE and friction loss",
          "[solver][train][friction]") {
  // The schema-1 pair and TrainOf(pair) are one model (two torsional bodies, one mesh, the pair's
  // friction vector per segment, the pinion driven by the load plus the mean friction loss),
  // stepped by two independent solvers (ExactStepper and TrainStepper) from the same state (the
  // pair's static equilibrium: the least-squares states of the two differ with friction, whose
  // loss is balanced in the cycle mean only). Loaded (permanent contact), dynamic (mesh 500 Hz).
  GearboxSpec pair = testing::LoadedTestPair();
  pair.mesh.friction_coefficient = 0.08;
  GearboxSpec clean = pair;
  clean.mesh.friction_coefficient = 0.0;
  const SolverOptions options = testing::LoadedTestPairRun();
  const testing::SolverSetup with_setup(pair, Tier::kTier1), clean_setup(clean, Tier::kTier1);
  REQUIRE(with_setup.tables.n == 2);
  const Eigen::VectorXd z0 = DriveEquilibrium(with_setup.tables);
  const SolverResult with = SimulateExact(with_setup.tables, z0, ContactState::kDrive, options);
  const SolverResult without = SimulateExact(
      clean_setup.tables, DriveEquilibrium(clean_setup.tables), ContactState::kDrive, options);

  const Model train(TrainOf(pair));
  const TrainTables& t = train.tables;
  REQUIRE(t.meshes[0].has_friction());
  // The friction loss: the same sum over the same segmentation, in another order.
  INFO("friction loss: pair " << with_setup.tables.friction_loss_torque << " N m, train "
                              << t.friction_loss_torque << " N m");
  CHECK(with_setup.tables.friction_loss_torque > 0.0);
  CHECK(t.friction_loss_torque == Approx(with_setup.tables.friction_loss_torque).epsilon(1e-12));
  TrainStepper stepper(t, {}, TrainStateOf(with_setup, t, z0),
                       std::vector<ContactState>{ContactState::kDrive});
  double worst = 0.0, effect = 0.0;
  for (size_t k = 0; k < with.trajectory.samples.size(); ++k) {
    const TrajectorySample& p = with.trajectory.samples[k];
    REQUIRE(stepper.Run(p.time));
    worst = std::max(worst, std::abs(MeshTe(t, stepper, 0) - p.te));
    effect = std::max(effect, std::abs(p.te - without.trajectory.samples[k].te));
  }
  INFO("largest TE difference " << worst << " m, friction moves the TE by " << effect << " m; "
                                << stepper.summary().events << " contact events");
  CHECK(stepper.summary().events == 0);  // permanent contact
  // Friction moves the TE by a good part of a micrometre (the check below is not vacuous) ...
  CHECK(effect > 1e-8);
  // ... and the two solvers agree to 1e-6 of that: two implementations of one model whose
  // rounding (~1e-12 relative on a 2e-5 m TE: 2e-17 m) sits far below, while a wrong arm, sign or
  // loss torque would move the TE by a fraction of the effect. Measured 9.6e-17 m of 6.4e-7 m.
  CHECK(worst <= 1e-6 * effect);
}

// Mean over the sampled cycle of the loaded pairs' share-weighted sliding speed
// |rho_a w_a - rho_b w_b| (rho_a = roll, rho_b = |T1T2| - roll), m/s: the power balance's own
// evaluation of the friction loss (the solver's is the segment means of the arms on the free
// rotation).
// On the back flank when the mesh's static torque flow loads it (its own line of action, roll
// measured the same way).
double MeanSlidingSpeed(const TrainMeshModel& mm, double speed_a, double speed_b) {
  const double length = mm.geometry.line_of_action_length;
  double sum = 0.0;
  for (const FlankSample& s : mm.back_flank_loaded ? mm.cycle.back : mm.cycle.drive) {
    for (int p = 0; p < s.pair_count; ++p) {
      const PairState& pair = s.pairs[static_cast<size_t>(p)];
      if (!pair.loaded) continue;
      sum += pair.load_share * std::abs(pair.roll * speed_a - (length - pair.roll) * speed_b);
    }
  }
  return sum / static_cast<double>(mm.cycle.drive.size());
}

// The static power balance of a two-stage train whose output gear g4 carries `load` N m: per mesh
// the friction power mu F_i <sliding speed> of its loaded flank (F_i its normal force at the static
// torque flow), W, and the input torque supplying the load's power and those losses, N m.
struct StaticPowerBalance {
  std::vector<double> mesh_loss;
  double input_torque = 0.0;
};

StaticPowerBalance PowerBalance(const Model& s, double mu, double load) {
  const TrainTopology& topo = s.train.topology;
  const auto speed = [&](int body) {
    return std::abs(topo.bodies[static_cast<size_t>(body)].speed);
  };
  StaticPowerBalance out;
  double loss = 0.0;
  for (const TrainMeshModel& mm : s.train.meshes) {
    const double force = mm.transmitted_torque / mm.geometry.wheel.base;
    out.mesh_loss.push_back(mu * force * MeanSlidingSpeed(mm, speed(mm.body_a), speed(mm.body_b)));
    loss += out.mesh_loss.back();
  }
  const int output = topo.gear_body[static_cast<size_t>(s.spec.GearIndex("g4"))];
  out.input_torque = (load * speed(output) + loss) / speed(topo.input_body);
  return out;
}

TEST_CASE("train friction: the input supplies the loads and the friction loss (power balance)",
          "[solver][train][friction]") {
  // Two loaded stages, mu = 0.06: the input torque times its speed is the load's power plus each
  // mesh's friction power mu F_i <sliding speed>, F_i the mesh's normal force at the static torque
  // flow, evaluated on the fine sampled mesh cycle (2048 samples) rather than the segmentation.
  const Model s(WithFriction(testing::TwoStageTrain(150.0, 0.0, 600.0), 0.06));
  const Model clean(testing::TwoStageTrain(150.0, 0.0, 600.0));
  const TrainTables& t = s.tables;
  const int input = s.train.topology.input_body;
  const double expected = PowerBalance(s, 0.06, 150.0).input_torque;
  INFO("input torque " << t.force[input] << " N m, power balance " << expected
                       << " N m (difference " << t.force[input] - expected
                       << " N m), friction loss " << t.friction_loss_torque << " N m");
  // The loss is a real part of the input torque here (~1 %) ...
  CHECK(t.friction_loss_torque > 2e-3 * t.force[input]);
  CHECK(t.force[input] ==
        Approx(clean.tables.force[input] + t.friction_loss_torque).epsilon(1e-14));
  // ... and equals the power balance to 2e-3 of the loss: the sampled mean is the midpoint rule
  // over 2048 cells of a function with jumps where pairs enter and leave and a kink at the pitch
  // point (error ~ jumps x cell / 2: ~1e-3 of the mean), the segment means Gauss-Legendre
  // quadrature between those breaks (rounding). A wrong arm or speed ratio is O(1) of the loss.
  CHECK(std::abs(t.force[input] - expected) <= 2e-3 * t.friction_loss_torque);

  // Dynamically: over 40 cycles of the first mesh in permanent contact the free rotation keeps
  // its speed to a few per cent of the drift the loss would cause if the input did not supply it
  // (the residual: the dynamic normal force differs from the static F_i by O(mu) and its
  // fluctuation correlates with the arms, as on the pair). Measured: 1.0e-2 of the drift.
  const auto start = TrainStaticState(t);
  TrainTables unbalanced = t;
  unbalanced.force[input] -= t.friction_loss_torque;
  const double end = 40.0 * t.meshes[0].period;
  const auto rigid_speed = [&](const TrainTables& tables) {
    TrainStepper stepper(tables, {}, start.first, start.second);
    REQUIRE(stepper.Run(end));
    CHECK(stepper.summary().events == 0);
    return tables.recenter_row.dot(stepper.state().segment(tables.n, tables.n));
  };
  const double start_speed = t.recenter_row.dot(start.first.segment(t.n, t.n));
  const double balanced = rigid_speed(t) - start_speed;
  const double drift = rigid_speed(unbalanced) - start_speed;
  INFO("free rotation's speed change: " << balanced << " with the loss supplied, " << drift
                                        << " without");
  // Without it the rotation decelerates by dT r_in t (to O(mu) of the same residual).
  CHECK(drift == Approx(-t.friction_loss_torque * t.rigid_rotation[input] * end).epsilon(0.1));
  CHECK(std::abs(balanced) <= 0.05 * std::abs(drift));
}

TEST_CASE("train friction: a back-loaded mesh brakes with its back flank (power balance)",
          "[solver][train][friction]") {
  // The two-stage train with its second stage listed driven gear first: power flows from that
  // mesh's gear b to its gear a, so the static torque flow loads its back flank, whose friction
  // loss (sliding on the back line of action) the input supplies too. Tolerance as above.
  TrainSpec spec = testing::TwoStageTrain(150.0, 0.0, 600.0);
  spec.meshes[1] = testing::TrainMeshOf("g4", "g3");
  const Model s(WithFriction(spec, 0.06));
  const Model clean(spec);
  REQUIRE(!s.train.meshes[0].back_flank_loaded);
  REQUIRE(s.train.meshes[1].back_flank_loaded);
  const TrainTables& t = s.tables;
  const int input = s.train.topology.input_body;
  const StaticPowerBalance balance = PowerBalance(s, 0.06, 150.0);
  const double expected = balance.input_torque;
  const double back_power = balance.mesh_loss[1];
  const double loss_power = balance.mesh_loss[0] + back_power;
  INFO("input torque " << t.force[input] << " N m, power balance " << expected
                       << " N m, friction loss " << t.friction_loss_torque << " N m");
  // The back-loaded mesh's share is a real part of the loss (a dropped or sign-flipped back flank
  // term moves the input torque by 2 x that share).
  CHECK(back_power > 0.2 * loss_power);
  CHECK(t.force[input] ==
        Approx(clean.tables.force[input] + t.friction_loss_torque).epsilon(1e-14));
  CHECK(std::abs(t.force[input] - expected) <= 2e-3 * t.friction_loss_torque);
}

TEST_CASE("train friction: the CVODE reference and V2 agree with V3 on a rattling train",
          "[solver][train][friction][reference]") {
  // The rattling train of train_stepper_test.cc with mu = 0.05 on both meshes: the loose gear's
  // impacts switch the non-symmetric generator on and off. CVODE (its own generator assembly and
  // gap functions, train_reference.cc) and the dense Taylor path (V2, with the non-symmetric
  // pencil's sub-step bound) against the closed forms (V3).
  // V3 decomposes every tuple at its first entry, so the closed forms of the non-symmetric
  // generators are compared (by default this short run would take the dense path as V2 does).
  const Model s(WithFriction(testing::RattlerTrain(1500.0), 0.05));
  TrainStepperOptions eager;
  eager.tables.decompose_after_visits = 1;
  const testing::ReferenceAgreement a = testing::AgreeWithReference(s.tables, 0.006, eager);
  REQUIRE(a.reference_events >= 4);
  CHECK(a.v2_events == a.v3_events);
  INFO("worst TE difference: CVODE "
       << a.worst_reference << " m, V2 " << a.worst_v2 << " m over " << a.reference_events
       << " events; V3 " << a.v3_summary.cache.decompositions << " decompositions ("
       << a.v3_summary.cache.ill_conditioned << " ill-conditioned), " << a.v3_summary.dense_pieces
       << " dense pieces");
  CHECK(a.v3_summary.cache.decompositions > a.v3_summary.cache.ill_conditioned);
  // Tolerance: 1e-8 of the TE, as the frictionless rattling train (CVODE at rtol 1e-13, the
  // horizon where rattle's amplification keeps the reference trusted).
  CHECK(a.worst_reference <= 1e-8 * a.scale);
  CHECK(a.worst_v2 <= 1e-8 * a.scale);
}

TEST_CASE("train friction: the dense path's sub-step bounds the non-symmetric generator",
          "[solver][train][friction]") {
  // rho(A) substep <= 1/2 must hold for every tuple (the Taylor path's convergence); with
  // friction the pencil is non-symmetric and the bound is |c| + sqrt|k| (train_tables.h). A
  // large mu (0.3) makes the non-symmetric part as large as the schema allows it to be useful.
  const Model s(WithFriction(testing::RattlerTrain(0.0), 0.3));
  const TrainTables& t = s.tables;
  TrainSystemCache cache(t, {});
  TupleKey key(static_cast<size_t>(cache.KeyWords()));
  const ContactState all[3] = {ContactState::kBack, ContactState::kFree, ContactState::kDrive};
  int checked = 0;
  for (int j = 0; j < t.meshes[0].segments(); j += 3) {
    for (const ContactState a : all) {
      for (const ContactState b : all) {
        const std::vector<int> seg = {j, j % t.meshes[1].segments()};
        const std::vector<ContactState> st = {a, b};
        const TrainSystem& sys = cache.Get(seg, st, key);
        const double rho =
            Eigen::EigenSolver<Eigen::MatrixXd>(sys.A, false).eigenvalues().cwiseAbs().maxCoeff();
        CHECK(rho * sys.substep <= 0.5);
        // The generator is the independent assembly's (CVODE's).
        const Eigen::MatrixXd B = AssembleTrainGenerator(t, seg, st);
        CHECK((sys.A - B).cwiseAbs().maxCoeff() <= 1e-13 * B.cwiseAbs().maxCoeff());
        ++checked;
      }
    }
  }
  CHECK(checked >= 9);
}

TEST_CASE("train friction: mu = 0 is the frictionless model and small mu is continuous",
          "[solver][train][friction]") {
  // mu = 0 builds no friction terms (the frictionless code path, unchanged); mu = 1e-9 moves the
  // TE of a rattling train by O(1e-9) of friction's own effect at mu = 0.05 (no switch in the
  // model or the event search at mu -> 0).
  const TrainSpec spec = testing::RattlerTrain(1500.0);
  const Model zero(WithFriction(spec, 0.0)), tiny(WithFriction(spec, 1e-9)),
      full(WithFriction(spec, 0.05));
  for (const TrainMeshTable& mt : zero.tables.meshes) CHECK_FALSE(mt.has_friction());
  CHECK(zero.tables.friction_loss_torque == 0.0);
  const double end = 0.003;
  const auto te_at = [&](const TrainTables& t) {
    const auto [z0, states0] = TrainStaticState(t);
    TrainStepper stepper(t, {}, z0, states0);
    REQUIRE(stepper.Run(end));
    return std::pair{MeshTe(t, stepper, 0), MeshTe(t, stepper, 1)};
  };
  const auto [a0, b0] = te_at(zero.tables);
  const auto [a1, b1] = te_at(tiny.tables);
  const auto [a2, b2] = te_at(full.tables);
  const double effect = std::max(std::abs(a2 - a0), std::abs(b2 - b0));
  const double small = std::max(std::abs(a1 - a0), std::abs(b1 - b0));
  INFO("TE change: mu = 0.05 " << effect << " m, mu = 1e-9 " << small << " m");
  CHECK(effect > 1e-9);
  // Linear response: 1e-9 / 0.05 = 2e-8 of the effect; 1e-6 allows rattle's amplification of
  // the rounding over 3 ms, far below a discontinuity (O(1) of the effect).
  CHECK(small <= 1e-6 * effect);
}

}  // namespace
}  // namespace gearnvh
