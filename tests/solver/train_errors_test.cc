// Runout and pitch errors on gear trains (solver/train_tables.h, train_errors.cc): against the
// schema-1 pair's solver, decoupled stages, and the quasi-static closed forms of the error lines.
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <numbers>

#include "gearnvh/model/mesh_segmentation.h"
#include "gearnvh/model/mesh_stiffness.h"
#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_specs.h"
#include "model/test_trains.h"
#include "solver/solver_fixture.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

using testing::kRpm;
using Model = testing::TrainModel;
using testing::MeshTe;

// A pitch-error pattern with every tooth different (no symmetry a wrong tooth index could hide in).
std::vector<double> PitchPattern(int teeth, double size, double seed) {
  std::vector<double> f(static_cast<size_t>(teeth));
  for (int i = 0; i < teeth; ++i) f[static_cast<size_t>(i)] = size * std::sin(seed * (i + 1) * i);
  return f;
}

TEST_CASE("train errors: a one-mesh train with runout or pitch errors has the pair's TE",
          "[solver][train][errors]") {
  // The schema-1 pair and TrainOf(pair) are one model (two torsional bodies, one mesh, the error
  // held at its mean over each segment) stepped by two independent solvers (ExactStepper and
  // TrainStepper). Loaded, dynamic (1500 rpm: mesh at 500 Hz), errors on both gears.
  GearboxSpec pair = testing::LoadedTestPair();
  const int kind = GENERATE(0, 1, 2);
  const double a = 5e-6;
  if (kind == 0) {
    pair.pinion.runout = Runout{a, 0.4};
    pair.wheel.runout = Runout{0.6 * a, -1.1};
  } else if (kind == 1) {
    pair.pinion.pitch_errors = PitchPattern(20, a, 0.37);
    pair.wheel.pitch_errors = PitchPattern(30, 0.5 * a, 0.71);
  } else {
    pair.wheel.runout = Runout{a, 2.0};
    pair.pinion.pitch_errors = PitchPattern(20, 0.5 * a, 0.53);
  }
  GearboxSpec clean = pair;
  clean.pinion.runout.reset();
  clean.wheel.runout.reset();
  clean.pinion.pitch_errors.clear();
  clean.wheel.pitch_errors.clear();
  const SolverOptions options = testing::LoadedTestPairRun();
  const auto run_pair = [&](const GearboxSpec& spec) {
    const testing::SolverSetup s(spec, Tier::kTier1);
    return SimulateExact(s.tables, DriveEquilibrium(s.tables), ContactState::kDrive, options);
  };
  const SolverResult with = run_pair(pair), without = run_pair(clean);

  const Model train(TrainOf(pair));
  REQUIRE(train.tables.error_inputs == 1);
  REQUIRE(train.tables.m == 2 * train.tables.n + 2 + train.tables.excitation_states());
  // The common period holds whole revolutions of both gears: lcm(20, 30) = 60 mesh cycles.
  CHECK(train.tables.common_period / train.tables.meshes[0].period == Approx(60.0).epsilon(1e-12));
  const auto [z0, s0] = TrainStaticState(train.tables);
  TrainStepper stepper(train.tables, {}, z0, s0);
  double worst = 0.0, effect = 0.0;
  for (size_t k = 0; k < with.trajectory.samples.size(); ++k) {
    const TrajectorySample& p = with.trajectory.samples[k];
    REQUIRE(stepper.Run(p.time));
    worst = std::max(worst, std::abs(MeshTe(train.tables, stepper, 0) - p.te));
    effect = std::max(effect, std::abs(p.te - without.trajectory.samples[k].te));
  }
  INFO("kind " << kind << ": largest TE difference " << worst << " m, the errors move the TE by "
               << effect << " m; " << stepper.summary().events << " contact events");
  // The errors move the TE by a good part of their size (the check below is not vacuous) ...
  CHECK(effect > 0.3 * a);
  // ... and the two solvers agree to 1e-6 of that (5e-12 m): two implementations of one model
  // whose rounding (decompositions, expm, ~1e-12 relative on a 2e-5 m TE) sits far below, and
  // far above it anything a wrong tooth index, phase, speed or input sign would make (~1e-6 m).
  // Measured 3e-17 m: both solvers hold the same inputs and propagate the same generators.
  CHECK(worst <= 1e-6 * effect);
}

TrainGear& Gear(TrainSpec& t, const std::string& name) {
  for (TrainGear& g : t.gears) {
    if (g.name == name) return g;
  }
  FAIL("no gear " << name);
  return t.gears.front();
}

TEST_CASE("train errors: an error of one stage's gear shows in that mesh only",
          "[solver][train][errors]") {
  // Pitch errors on g3 (the layshaft's second-stage gear). With a massive layshaft the stages
  // decouple (train_stepper_test.cc: what is left is r_b dT t^2 / (2 J_lay), here with the
  // error's force dT ~ k a r_b ~ 2e8 N/m * 3e-6 m * 0.02 m = 12 N m: < 1e-11 m over 0.05 s).
  // So mesh 2 equals the second stage alone with the same error, and mesh 1 the first stage
  // alone, without any. Pitch errors only: they are constant over each segment of their mesh, so
  // the finer union grid of the whole train holds the same input; a runout's mean over the union
  // grid's shorter segments differs from its mean over a stage's own (first order in the segment
  // length, 7e-8 m here), a legitimate difference of the piecewise model this test is not about
  // (runout is compared on one grid in the one-mesh test above).
  const double j_lay = 1e8, a = 3e-6;
  TrainSpec full_spec = testing::TwoStageAlone(0, j_lay),
            second_spec = testing::TwoStageAlone(2, j_lay);
  for (TrainSpec* t : {&full_spec, &second_spec}) {
    Gear(*t, "g3").gear.pitch_errors = PitchPattern(20, a, 0.29);
  }
  const Model full(full_spec), first(testing::TwoStageAlone(1, j_lay)), second(second_spec),
      clean(testing::TwoStageAlone(0, j_lay));
  REQUIRE(full.tables.error_inputs == 1);
  REQUIRE(full.tables.meshes[0].error_input == -1);
  REQUIRE(full.tables.meshes[1].error_input == 0);
  const auto start = [](const Model& m) {
    const auto [z, s] = TrainStaticState(m.tables);
    return TrainStepper(m.tables, {}, z, s);
  };
  TrainStepper f = start(full), s1 = start(first), s2 = start(second), c = start(clean);
  const double period = full.tables.meshes[0].period;
  double worst[2] = {0.0, 0.0}, scale[2] = {0.0, 0.0}, effect = 0.0;
  for (int k = 1; k <= 800; ++k) {
    const double time = k * period / 8.0;
    for (TrainStepper* s : {&f, &s1, &s2, &c}) REQUIRE(s->Run(time));
    const double te[2] = {MeshTe(full.tables, f, 0), MeshTe(full.tables, f, 1)};
    const double alone[2] = {MeshTe(first.tables, s1, 0), MeshTe(second.tables, s2, 0)};
    for (int i = 0; i < 2; ++i) {
      worst[i] = std::max(worst[i], std::abs(te[i] - alone[i]));
      scale[i] = std::max(scale[i], std::abs(alone[i]));
    }
    effect = std::max(effect, std::abs(te[1] - MeshTe(clean.tables, c, 1)));
  }
  CHECK(f.summary().events == 0);
  INFO("TE differences " << worst[0] << ", " << worst[1] << " m; the error moves mesh 2 by "
                         << effect << " m");
  CHECK(effect > 0.3 * a);
  // Tolerance: 1e-7 of the TE (~1e-11 m), above the coupling left through the layshaft and far
  // below the error's own effect (> 1e-6 m) that a mesh taking the wrong gear's error would show.
  CHECK(worst[0] <= 1e-7 * scale[0]);
  CHECK(worst[1] <= 1e-7 * scale[1]);
}

// Input (g1, 20) -> idler (g2, 30, on its own shaft) -> output (g3, 25): the idler takes part in
// both meshes. Slow (6 rpm: mesh at 2 Hz, three decades below the mesh modes) and loaded, so the
// response is quasi-static: each mesh's TE is its wall plus F/k(t), and an error input u_i(t)
// adds to it one for one. Heavy mesh damping makes the ringing after each segment's step decay
// within 0.3 ms (0.06 % of a 0.5 s mesh cycle).
TrainSpec IdlerTrain() {
  TrainSpec t;
  t.name = "idler";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {testing::RigidShaft("input", 2e-3), testing::RigidShaft("idler", 1e-3),
              testing::RigidShaft("output", 5e-3)};
  t.gears = {testing::TrainGearOf("g1", "input", 20), testing::TrainGearOf("g2", "idler", 30),
             testing::TrainGearOf("g3", "output", 25)};
  t.meshes = {testing::TrainMeshOf("g1", "g2"), testing::TrainMeshOf("g2", "g3")};
  for (TrainMesh& m : t.meshes) m.mesh.damping_ratio = 0.3;
  t.operating.input_shaft = "input";
  t.operating.speed = 6.0 * kRpm;
  t.operating.loads = {{"output", 100.0}};
  t.analysis.segments_per_cycle = 16;
  return t;
}

// The complex line c_i(nu) = (2 / N) sum_k D_i(t_k) exp(-2 pi i nu t_k) of each mesh's error
// response D_i = TE_i(with errors) - TE_i(without) (the difference removes the mesh harmonics of
// F/k(t)), over `cycles` mesh cycles from t0 at `per_cycle` midpoint samples per cycle: the
// midpoint rule of the Fourier integral of a piecewise-constant signal.
std::vector<std::vector<std::complex<double>>> ErrorLines(const TrainSpec& with_errors,
                                                          const std::vector<double>& nus,
                                                          long cycles, int per_cycle) {
  TrainSpec without = with_errors;
  for (TrainGear& g : without.gears) {
    g.gear.runout.reset();
    g.gear.pitch_errors.clear();
  }
  const Model a(with_errors), b(without);
  const auto start = [](const Model& m) {
    const auto [z, s] = TrainStaticState(m.tables);
    return TrainStepper(m.tables, {}, z, s);
  };
  TrainStepper sa = start(a), sb = start(b);
  const double period = a.tables.meshes[0].period, dt = period / per_cycle;
  const double t0 = 2.0 * period;  // the start's transient has long decayed
  const long samples = cycles * per_cycle;
  const size_t meshes = a.tables.meshes.size();
  std::vector<std::vector<std::complex<double>>> lines(
      meshes, std::vector<std::complex<double>>(nus.size()));
  for (long k = 0; k < samples; ++k) {
    const double t = t0 + (static_cast<double>(k) + 0.5) * dt;
    REQUIRE(sa.Run(t));
    REQUIRE(sb.Run(t));
    for (size_t i = 0; i < meshes; ++i) {
      const double d =
          MeshTe(a.tables, sa, static_cast<int>(i)) - MeshTe(b.tables, sb, static_cast<int>(i));
      for (size_t q = 0; q < nus.size(); ++q)
        lines[i][q] += d * std::polar(2.0 / static_cast<double>(samples), -2.0 * std::numbers::pi * nus[q] * t);
    }
  }
  CHECK(sa.summary().events == 0);
  return lines;
}

TEST_CASE("train errors: an idler's runout enters both its meshes at its own angle",
          "[solver][train][errors]") {
  // Quasi-static: D_i(t) = u_i(t) = a sin(w_idler t + phi) held at its segment means, so the line
  // at the idler's rotation frequency is a exp(i (phi - pi/2)) in both meshes (whose segment
  // grids differ: mesh 1 and mesh 2 have 20- and 30-tooth pinions), attenuated by the segment
  // mean's sinc, (pi f h)^2 / 6 = 2e-6.
  TrainSpec spec = IdlerTrain();
  const double a = 4e-6, phi = 0.8;
  Gear(spec, "g2").gear.runout = Runout{a, phi};
  const double idler_hz = 6.0 / 60.0 * 20.0 / 30.0;
  const long cycles = 30;  // one idler revolution
  const auto lines = ErrorLines(spec, {idler_hz}, cycles, 256);
  const std::complex<double> expected = std::polar(a, phi - 0.5 * std::numbers::pi);
  for (size_t i = 0; i < 2; ++i) {
    INFO("mesh " << i << ": line " << lines[i][0] << " m, expected " << expected);
    // Tolerance 1e-3 a: the midpoint rule over 256 samples per cycle of a sinusoid (exact up to
    // aliasing, ~1e-6) plus the quasi-static residue (f / f_n)^2 ~ 1e-6 and the steps' ringing
    // (< 1e-4 of a); a phase from the wrong gear angle or speed is off by O(1).
    CHECK(std::abs(lines[i][0] - expected) <= 1e-3 * a);
  }
}

// Hat H(nu) = int H(t) exp(-2 pi i nu t) dt of the pulse one tooth's deviation makes in a mesh:
// weight w_qj over segment j of the q-th mesh cycle after the tooth entered (MeshErrorExcitation).
std::complex<double> PulseTransform(const MeshSegmentation& seg, double period, double nu) {
  std::complex<double> sum = 0.0;
  for (const MeshSegment& s : seg.segments) {
    for (const auto& [q, w] : s.error_weights) {
      const double t0 = (q + s.tau_begin) * period, t1 = (q + s.tau_end) * period;
      const double omega = 2.0 * std::numbers::pi * nu;
      sum += w * (std::polar(1.0, -omega * t0) - std::polar(1.0, -omega * t1)) /
             std::complex<double>(0.0, omega);
    }
  }
  return sum;
}

TEST_CASE(
    "train errors: sinusoidal pitch errors of an idler put sidebands fm +- f at the closed "
    "form in both meshes",
    "[solver][train][errors]") {
  // Pitch errors f_k = A sin(2 pi k / z + phi) on the idler (z = 30 teeth). In each mesh the error
  // input is sum_c f_(c mod z) H(t - c T): the sampled sinusoid convolved with one tooth's pulse
  // H (PulseTransform). Its Fourier series has lines only at nu = (k z +- 1) f_idler, each of
  // one-sided amplitude A |Hat H(nu)| / T, T the mesh period (sum over the z cycles of
  // f_c exp(-2 pi i nu c T) = z A / 2 for those nu, 0 otherwise). Quasi-static, the TE carries it
  // one for one: the sidebands fm - f and fm + f (k = 1) and the 1x line (k = 0).
  TrainSpec spec = IdlerTrain();
  const double A = 2e-6;
  std::vector<double> f(30);
  for (int k = 0; k < 30; ++k) f[static_cast<size_t>(k)] = A * std::sin(2.0 * std::numbers::pi * k / 30 + 0.3);
  Gear(spec, "g2").gear.pitch_errors = f;
  const double idler_hz = 6.0 / 60.0 * 20.0 / 30.0, mesh_hz = 30.0 * idler_hz;
  const std::vector<double> nus = {mesh_hz - idler_hz, mesh_hz + idler_hz, idler_hz,
                                   mesh_hz + 2.0 * idler_hz};
  const auto lines = ErrorLines(spec, nus, 30, 256);
  const Model m(spec);
  for (size_t i = 0; i < 2; ++i) {
    const TrainMeshModel& mm = m.train.meshes[i];
    const MeshSegmentation seg = SegmentMeshCycle(mm.pair, MeshEvaluator(mm.pair, mm.geometry),
                                                  spec.analysis.segments_per_cycle);
    const double period = m.tables.meshes[i].period;
    for (size_t q = 0; q < 3; ++q) {
      const double expected = A * std::abs(PulseTransform(seg, period, nus[q])) / period;
      INFO("mesh " << i << " at " << nus[q] << " Hz: " << std::abs(lines[i][q])
                   << " m, closed form " << expected << " m");
      // Tolerance 2e-4 A: the midpoint rule of a piecewise-constant signal (256 samples per
      // cycle: each of the ~16 x 30 steps per period misplaced by up to half a sample, ~1e-4 A
      // after their signs average; measured 6e-5 A) and the quasi-static residue (~1e-6 A). The
      // sidebands are small (~2e-2 A: Hat H(fm) = 0, the pairs' weights sum to one at every
      // instant), so this is 1 % of a sideband; the 1x line is ~A. A wrong tooth order, pulse or
      // mesh would move them by O(1).
      CHECK(std::abs(std::abs(lines[i][q]) - expected) <= 2e-4 * A);
      CHECK(expected > 0.015 * A);
    }
    // No line at fm + 2 f: the error's pattern has the first tooth order only.
    CHECK(std::abs(lines[i][3]) < 2e-4 * A);
  }
}

TEST_CASE("train errors: the CVODE reference and V2 agree with V3 on a rattling train with errors",
          "[solver][train][errors][reference]") {
  // The rattling train of train_stepper_test.cc with runout on the loose gear g4 and pitch errors
  // on g1 (two error inputs; the loose gear's runout moves the walls its impacts hit). CVODE (its
  // own gap functions and generator assembly, train_reference.cc) and the dense Taylor path (V2)
  // against the closed forms (V3).
  TrainSpec spec = testing::RattlerTrain(1500.0);
  Gear(spec, "g4").gear.runout = Runout{10e-6, 1.3};
  Gear(spec, "g1").gear.pitch_errors = PitchPattern(20, 5e-6, 0.61);
  const Model s(spec);
  REQUIRE(s.tables.error_inputs == 2);
  const testing::ReferenceAgreement a = testing::AgreeWithReference(s.tables, 0.006);
  REQUIRE(a.reference_events >= 4);  // the loose gear rattles (5 events here)
  CHECK(a.v2_events == a.v3_events);
  INFO("worst TE difference: CVODE " << a.worst_reference << " m, V2 " << a.worst_v2 << " m over "
                                     << a.reference_events << " events");
  // Tolerance: 1e-8 of the TE, as the error-free rattling train (train_stepper_test.cc: CVODE at
  // rtol 1e-13). The errors make this train rattle harder: differences grow ~100-fold per 3.75 ms
  // (measured 1e-14 m at 3.75 ms, 1e-12 m at 7.5 ms), so the horizon is 6 ms. An error input
  // missing from one side, or set at the wrong time, moves the TE by ~1e-6 m (the errors' size).
  CHECK(a.worst_reference <= 1e-8 * a.scale);
  CHECK(a.worst_v2 <= 1e-8 * a.scale);
}

TEST_CASE("train errors: certified jumps carry the error inputs (jumped equals stepped)",
          "[solver][train][errors]") {
  // A loaded two-stage reducer in permanent contact with runout on g1 and pitch errors on g3: the
  // common period holds their revolutions, the cycle map sets the error inputs per grid segment
  // as the stepper does, so the jumped transient lands on the stepped one's periodic orbit.
  TrainSpec spec = testing::TwoStageTrain(300.0, 100.0, 300.0);
  // Small errors: with 4 um of runout the orbit came within 3 um of a wall, inside the
  // certificate's curvature bound (~3 um per sub-step here), and the map was refused (no margin).
  Gear(spec, "g1").gear.runout = Runout{1e-6, 0.5};
  Gear(spec, "g3").gear.pitch_errors = PitchPattern(20, 0.5e-6, 0.41);
  const Model m(spec);
  const TrainTables& t = m.tables;
  REQUIRE(t.error_inputs == 2);
  REQUIRE(t.common_period > 0.0);
  const double start = 20.0 * t.common_period, end = start + t.common_period;
  const testing::RecordedTrainRun stepped = testing::RunTrainFromStatic(t, false, start, end);
  const testing::RecordedTrainRun jumped = testing::RunTrainFromStatic(t, true, start, end);
  CHECK(stepped.summary.events == 0);
  INFO("cycle map info " << static_cast<int>(jumped.summary.cycle_map_info));
  REQUIRE(jumped.summary.jumps == TrainStepperSummary::Jumps::kJumped);
  CHECK(jumped.summary.jumped_periods >= 18);
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    const TrainMeshStatistics& a = stepped.stats.meshes[i];
    const TrainMeshStatistics& b = jumped.stats.meshes[i];
    const double pp = a.te_peak_to_peak;
    INFO("mesh " << i << ": TE mean " << a.te_mean << " / " << b.te_mean << ", p-p " << pp << " / "
                 << b.te_peak_to_peak);
    // Tolerance 1e-10 of the TE p-p, as for the error-free reducer (train_cycle_map_test.cc: both
    // runs reach one orbit to rounding, measured ~1e-12); an error input missing from the map or
    // set at the wrong segment moves the p-p by > 1e-3.
    CHECK(std::abs(a.te_mean - b.te_mean) <= 1e-10 * pp);
    CHECK(std::abs(a.te_rms - b.te_rms) <= 1e-10 * pp);
    CHECK(std::abs(a.te_peak_to_peak - b.te_peak_to_peak) <= 1e-10 * pp);
  }
}

}  // namespace
}  // namespace gearnvh
