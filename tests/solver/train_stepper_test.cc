// The exact event-driven solver on gear trains at tier 1 (solver/train_stepper.h): closed forms,
// an independent linear periodic solution, the CVODE reference, the cache bound, allocations.
#include "gearnvh/solver/train_stepper.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_statistics.h"
#include "model/test_specs.h"
#include "model/test_trains.h"
#include "solver/train_model.h"
#include "support/allocation_counter.h"

namespace gearnvh {
namespace {


// The small rattling train and the two-stage train of tests/model/test_trains.h.
TrainSpec Rattler(double excitation) { return testing::RattlerTrain(excitation); }
TrainSpec TwoStage(double load, double excitation, double rpm) {
  return testing::TwoStageTrain(load, excitation, rpm);
}

using Model = testing::TrainModel;

double Gap(const TrainTables& t, size_t i, const std::vector<int>& seg, const Eigen::VectorXd& z,
           bool drive) {
  const TrainMeshTable& mt = t.meshes[i];
  const double e = mt.error[static_cast<size_t>(seg[i])];
  return mt.v.dot(z.head(t.n)) - e + (drive ? -mt.half_backlash : mt.half_backlash);
}

// First t in [0, h] where a + b t + c t^2 reaches 0 from the side of its value at 0 (a != 0).
double FirstQuadraticRoot(double a, double b, double c, double h) {
  double best = -1.0;
  const auto consider = [&](double r) {
    if (r >= 0.0 && r <= h && (best < 0.0 || r < best)) best = r;
  };
  if (c == 0.0) {
    if (b != 0.0) consider(-a / b);
    return best;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return -1.0;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  consider(q / c);
  if (q != 0.0) consider(a / q);
  return best;
}

TEST_CASE("train tables: the cache's generator equals an independent assembly for every state",
          "[solver][train]") {
  const Model s(Rattler(1500.0));
  TrainSystemCache cache(s.tables, {});
  TupleKey key(static_cast<size_t>(cache.KeyWords()));
  const ContactState all[3] = {ContactState::kBack, ContactState::kFree, ContactState::kDrive};
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const std::vector<int> seg = {3, 7};
      const std::vector<ContactState> st = {all[a], all[b]};
      const Eigen::MatrixXd A = cache.Get(seg, st, key).A;
      const Eigen::MatrixXd B = AssembleTrainGenerator(s.tables, seg, st);
      // Two assemblies of the same sums: equal to a few ulps of the largest entry.
      CHECK((A - B).cwiseAbs().maxCoeff() <= 1e-14 * B.cwiseAbs().maxCoeff());
    }
  }
  CHECK(cache.summary().misses == 9);
  // The free rotation opens no gap: v_i^T r = 0 for every mesh.
  for (const TrainMeshTable& mt : s.tables.meshes)
    CHECK(std::abs(mt.v.dot(s.tables.rigid_rotation)) <= 1e-14 * mt.v.norm());
}

TEST_CASE("train: the common period is whole for every mesh, or reported as none",
          "[solver][train]") {
  // 20 -> 40, 20 -> 40 with engine order 2: every mesh is whole after one input revolution
  // (20 and 10 cycles), the order after one.
  const Model small(TwoStage(100.0, 0.0, 1000.0));
  CHECK(small.tables.common_period == Approx(small.tables.InputRevolution()).epsilon(1e-15));
  // 23 -> 41, 19 -> 37: the second mesh does 19 * 23/41 cycles per input revolution, whole
  // after 41 revolutions (the first is whole after one).
  TrainSpec coprime = TwoStage(100.0, 0.0, 1000.0);
  coprime.gears[0].gear.teeth = 23;
  coprime.gears[1].gear.teeth = 41;
  coprime.gears[2].gear.teeth = 19;
  coprime.gears[3].gear.teeth = 37;
  const Model m(coprime);
  CHECK(m.tables.common_period == Approx(41.0 * m.tables.InputRevolution()).epsilon(1e-15));
  // Large coprime counts (9973 -> 9967, 9949 -> 9941): whole only after 9967 revolutions, beyond
  // the 1000 searched, so none (a 1e-9 relative test once took 277 revolutions, where the
  // second mesh is 0.0015 cycles out of phase).
  TrainSpec large = coprime;
  large.gears[0].gear.teeth = 9973;
  large.gears[1].gear.teeth = 9967;
  large.gears[2].gear.teeth = 9949;
  large.gears[3].gear.teeth = 9941;
  for (TrainGear& g : large.gears) g.gear.module = 0.5e-3;
  const Model l(large);
  CHECK(l.tables.common_period == 0.0);
}

TEST_CASE("train: a free loose gear under constant drag follows its parabola until it hits",
          "[solver][train]") {
  // No excitation, every mesh free at t = 0: every body moves on its own parabola
  // th_j(t) = th_j0 + w_j0 t + f_j t^2 / (2 J_j) until the first impact, and the first impact is
  // the earliest root of the piecewise quadratic gaps (e_ij is constant per mesh segment). The
  // loose gear g4 idles on the input shaft, or on a fixed shaft that stands (neutral at
  // standstill), whose angle stays 0.
  const bool standing = GENERATE(false, true);
  TrainSpec spec = Rattler(0.0);
  if (standing) {
    spec.shafts.push_back(testing::RigidShaft("carrier", 0.01));
    spec.shafts.back().fixed = true;
    spec.gears[3].shaft = "carrier";
  }
  CAPTURE(standing);
  const Model s(spec);
  const TrainTables& t = s.tables;
  const int n = t.n;
  Eigen::VectorXd z0 = Eigen::VectorXd::Zero(t.m);
  z0[t.constant_slot()] = 1.0;
  const int loose = standing ? 3 : 2;  // bodies: input, layshaft, (carrier,) the loose gear g4
  REQUIRE(t.loose[loose]);
  z0[n + loose] = -0.3;  // rad/s towards the drive flank of g3-g4
  const std::vector<ContactState> free(2, ContactState::kFree);
  for (size_t i = 0; i < 2; ++i) {
    REQUIRE(Gap(t, i, std::vector<int>{0, 0}, z0, true) < 0.0);
    REQUIRE(Gap(t, i, std::vector<int>{0, 0}, z0, false) > 0.0);
  }

  // Closed form: walk the grid, per segment the quadratic of each gap.
  const Eigen::VectorXd acc = t.force.cwiseQuotient(t.inertia);
  const auto x_at = [&](double time) {
    return Eigen::VectorXd(z0.head(n) + z0.segment(n, n) * time + 0.5 * acc * time * time);
  };
  double impact = -1.0;
  int impact_mesh = -1;
  for (TrainGrid grid(t); impact < 0.0 && grid.start() < 0.1; grid.Next()) {
    const double t0 = grid.start(), h = grid.end() - grid.start();
    for (size_t i = 0; i < 2; ++i) {
      const TrainMeshTable& mt = t.meshes[i];
      const double e = mt.error[static_cast<size_t>(grid.segments()[i])];
      // delta(t0 + tau) = a + b tau + c tau^2.
      const double a = mt.v.dot(x_at(t0));
      const double b = mt.v.dot(z0.segment(n, n) + acc * t0);
      const double c = 0.5 * mt.v.dot(acc);
      for (double wall : {e + mt.half_backlash, e - mt.half_backlash}) {
        double root = (wall > e) == (a - wall > 0.0) ? 0.0 : -1.0;  // outside at the boundary
        if (root < 0.0) root = FirstQuadraticRoot(a - wall, b, c, h);
        if (root >= 0.0 && (impact < 0.0 || t0 + root < impact)) {
          impact = t0 + root;
          impact_mesh = static_cast<int>(i);
        }
      }
    }
  }
  REQUIRE(impact > 0.0);

  TrainStepper stepper(t, {}, z0, free);
  // The parabola at 20 times before the impact. Tolerance: the all-free generator is nilpotent, its
  // exponential a finite series, so the state is exact to rounding of the angles (~1e-16 rad
  // relative to |th| <= 1e-3 rad): 1e-15 rad absolute.
  for (int k = 1; k <= 20; ++k) {
    const double time = impact * k / 21.0;
    REQUIRE(stepper.Run(time));
    CHECK(stepper.summary().events == 0);
    const Eigen::VectorXd x = x_at(time);
    CHECK(std::abs(stepper.state()[loose] - x[loose]) <= 1e-15);
    CHECK(std::abs(stepper.state()[0] - x[0]) <= 1e-15);
    if (standing) CHECK(stepper.state()[2] == 0.0);
  }
  REQUIRE(stepper.Run(impact * 1.5));
  REQUIRE(stepper.summary().events >= 1);
  // The stepper's first event: rerun to just before and just after the closed-form root.
  // Tolerance: the root is conditioned by |g'| ~ 1e-2 m/s against a gap rounding of ~1e-19 m, so
  // it is exact to ~1e-17 s; 1e-13 s (3e-11 of a mesh period) leaves room for the time sums.
  TrainStepper before(t, {}, z0, free), after(t, {}, z0, free);
  REQUIRE(before.Run(impact - 1e-13));
  REQUIRE(after.Run(impact + 1e-13));
  CHECK(before.summary().events == 0);
  CHECK(after.summary().events >= 1);
  CHECK(after.states()[static_cast<size_t>(impact_mesh)] != ContactState::kFree);
}

TEST_CASE("train: permanent contact equals the linear periodic steady state", "[solver][train]") {
  // Large load, small excitation: every mesh stays in drive contact, so the response is the
  // periodic solution of a linear time-periodic system. Reference: the period map built from dense
  // propagators expm(A h) of an independent assembly, and its fixed point (I - P) y = p (COD: the
  // free rotation's position is the one null direction; it moves no TE).
  const Model s(TwoStage(300.0, 100.0, 300.0));
  const TrainTables& t = s.tables;
  const int n = t.n;
  REQUIRE(t.common_period > 0.0);
  const testing::LinearPeriodicState orbit = testing::DriveContactPeriodicState(t);
  const std::vector<ContactState> drive(2, ContactState::kDrive);
  const Eigen::VectorXd& z = orbit.z;
  TrainStepper stepper(t, {}, z, drive);
  double te_scale = 0.0;
  double worst = 0.0;
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
  // The orbit is periodic: one period brings the TE back (the fixed point's own residual, ~1e-12
  // of the TE with the COD solve; 1e-9 is a loose sanity bound).
  for (const TrainMeshTable& mt : t.meshes)
    CHECK(std::abs(mt.v.dot(reference.head(n) - z.head(n))) <= 1e-9 * te_scale);
  // Tolerance: both sides propagate the same piecewise model over ~600 grid segments, one through
  // the decoupled closed form (state error ~ cond(S) eps per segment, cond(S) <= 1e6, damped), the
  // other through Pade; 1e-11 of the TE is above their rounding (measured ~1e-13 of it) and far
  // below any modelling difference (a wrong segment mean or stiffness moves the TE by > 1e-4).
  INFO("worst TE difference " << worst << " m, TE scale " << te_scale << " m");
  CHECK(worst <= 1e-11 * te_scale);
}

TEST_CASE("train: the CVODE reference agrees on a rattling train", "[solver][train][reference]") {
  const Model s(Rattler(1500.0));
  const TrainTables& t = s.tables;
  const auto [z0, states0] = TrainStaticState(t);
  TrainReferenceOptions ro;
  ro.end_time = 0.008;
  ro.rtol = 1e-13;
  ro.sample_interval = t.meshes[0].period / 16.0;
  const TrainReferenceResult ref = SimulateTrainReference(t, z0, states0, ro);
  REQUIRE(ref.success);
  REQUIRE(ref.events.size() >= 10);  // the loose gear does rattle

  TrainStepper stepper(t, {}, z0, states0);
  double worst = 0.0, scale = 0.0;
  for (size_t k = 0; k < ref.sample_times.size(); ++k) {
    scale = std::max(scale, ref.te.row(static_cast<Eigen::Index>(k)).cwiseAbs().maxCoeff());
    REQUIRE(stepper.Run(ref.sample_times[k]));
    for (size_t i = 0; i < t.meshes.size(); ++i) {
      const double te = t.meshes[i].v.dot(stepper.state().head(t.n));
      worst = std::max(
          worst, std::abs(te - ref.te(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i))));
    }
  }
  // Tolerance: the 1e-8 of the TE. CVODE runs at rtol 1e-13; the rattling loose gear
  // amplifies any difference (about tenfold per millisecond here, measured), so the horizon is
  // 8 ms (15 events), where the difference is still ~1e-13 m, set by CVODE.
  INFO("worst TE difference " << worst << " m over " << ref.sample_times.size() << " samples, "
                              << ref.events.size() << " events");
  CHECK(worst <= 1e-8 * scale);

  // Event by event: same mesh and transition, and the state switched within +-1e-7 of a mesh
  // period (4e-10 s) of CVODE's root: a TE difference of ~1e-13 m over gap rates >= 1e-4 m/s moves
  // a root by ~1e-9 s at worst.
  TrainStepper events(t, {}, z0, states0);
  size_t k = 0;
  const double period = t.meshes[0].period;
  for (const TrainReferenceEvent& e : ref.events) {
    REQUIRE(events.Run(e.time - 1e-7 * period));
    const ContactState before = events.states()[static_cast<size_t>(e.mesh)];
    REQUIRE(events.Run(e.time + 1e-7 * period));
    const ContactState after = events.states()[static_cast<size_t>(e.mesh)];
    INFO("event " << k << " of mesh " << e.mesh << " at " << e.time << " s");
    CHECK(before == e.from);
    CHECK(after == e.to);
    ++k;
  }
  CHECK(k >= 10);
}

TEST_CASE("train: the CVODE reference steps over a piece too short for its absolute time",
          "[solver][train][reference]") {
  // CVODE refuses an interval under 2u max(|t0|, |tout|) (CV_TOO_CLOSE). Late in a long run one
  // ulp of the time is more than 1e-12 of a grid segment (here after 12000 segments, t / h ~ 1e4
  // > 1 / (1e-12 / 2.2e-16) ~ 4500), so a run ending one ulp after a grid boundary leaves a
  // last piece that only the absolute-time guard (NegligiblePiece) steps over; without it the run
  // fails (CV_TOO_CLOSE). The loaded two-stage train; rtol 1e-6 keeps it cheap (~1 s).
  const Model s(TwoStage(100.0, 0.0, 1000.0));
  const TrainTables& t = s.tables;
  TrainGrid grid(t);
  for (int k = 0; k < 12000; ++k) grid.Next();
  const double boundary = grid.start();
  const double h = grid.end() - grid.start();
  const double piece = std::nextafter(boundary, 2.0 * boundary) - boundary;  // one ulp
  REQUIRE(piece > 1e-12 * h);
  REQUIRE(piece < std::numeric_limits<double>::epsilon() * boundary);  // 2u t, u = eps / 2
  const auto [z0, states0] = TrainStaticState(t);
  TrainReferenceOptions ro;
  ro.end_time = boundary + piece;
  ro.rtol = 1e-6;
  const TrainReferenceResult ref = SimulateTrainReference(t, z0, states0, ro);
  INFO(ref.message);
  CHECK(ref.success);
}

TEST_CASE("train: a tiny cache limit forces evictions and changes nothing", "[solver][train]") {
  const Model s(Rattler(1500.0));
  const auto [z0, states0] = TrainStaticState(s.tables);
  TrainStepperOptions tight;
  tight.tables.cache_limit_bytes = 1;  // keeps only the tuple in use
  TrainStepper a(s.tables, {}, z0, states0), b(s.tables, tight, z0, states0);
  REQUIRE(a.Run(0.03));
  REQUIRE(b.Run(0.03));
  CHECK(b.summary().cache.evictions > 0);
  CHECK(b.summary().cache.tuples == 1);
  CHECK(a.summary().cache.evictions == 0);
  CHECK(a.summary().events == b.summary().events);
  CHECK(a.summary().events > 10);
  // Tolerance: a rebuilt tuple is the same computation on the same inputs, so the runs agree to
  // the last bit; 1e-15 of the state's norm allows for nothing more than that.
  CHECK((a.state() - b.state()).norm() <= 1e-15 * a.state().norm());
}

TEST_CASE("train: a run stopped by the event limit says where and on which mesh",
          "[solver][train]") {
  const Model s(Rattler(1500.0));
  const auto [z0, states0] = TrainStaticState(s.tables);
  TrainStepperOptions limited;
  limited.max_events_per_segment = 1;  // the rattler has grid segments with two or more events
  TrainStepper stepper(s.tables, limited, z0, states0);
  CHECK(!stepper.Run(0.03));
  const TrainStepperSummary summary = stepper.summary();
  const std::string message = TrainStepperMessage(summary);
  INFO(message);
  CHECK(summary.info == TrainStepperSummary::Info::kTooManyEvents);
  CHECK(message.find("more than 1 contact events") == 0);
  bool names_mesh = false;
  for (const TrainMeshTable& mt : s.tables.meshes)
    names_mesh = names_mesh || message.find("the last on mesh " + mt.name) != std::string::npos;
  CHECK(names_mesh);
  CHECK(summary.stopped_on_mesh.size() > 0);
}

TEST_CASE("train: the stepping loop does not allocate once the cache holds the tuples",
          "[solver][train][allocation]") {
  const Model s(Rattler(1500.0));
  const auto [z0, states0] = TrainStaticState(s.tables);
  // Each tuple is decomposed at its first entry: under the default lazy policy a repeated run
  // decomposes tuples the first run only entered once or twice, and the rattling amplifies that
  // rounding difference into a different trajectory with other tuples. The dense path (every
  // tuple before its decomposition) is covered by the never-decomposing runs: V3 with an
  // unreachable threshold, and V2 (with its exact recording).
  const auto [method, decompose] = GENERATE(table<EventMethod, int>(
      {{EventMethod::kSpectral, 1}, {EventMethod::kSpectral, 1000000}, {EventMethod::kTaylor, 3}}));
  TrainStepperOptions options;
  options.events = method;
  options.tables.decompose_after_visits = decompose;
  TrainStepper stepper(s.tables, options, z0, states0);
  TrainRecorder warm(s.tables, 32, 0.0);
  REQUIRE(stepper.Run(0.02, &warm));
  const long misses = stepper.summary().cache.misses;
  stepper.Reset(z0, states0);  // the same trajectory again: every tuple is cached
  TrainRecorder recorder(s.tables, 32, 0.0);
  testing::AllocationCounter counter;
  REQUIRE(stepper.Run(0.02, &recorder));
  CHECK(counter.count() == 0);
  CHECK(stepper.summary().cache.misses == misses);
  CHECK(stepper.summary().events > 10);
  if (method == EventMethod::kTaylor || decompose > 1) CHECK(stepper.summary().dense_pieces > 0);
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("train: two meshes decoupled by a massive layshaft reproduce one-mesh trains",
          "[solver][train]") {
  // With a massive layshaft the first stage is the input turning against a layshaft at nominal
  // speed, the second the layshaft (as an input without excitation) driving the output. What
  // couples them is the layshaft's motion under the other stage's force fluctuation dT:
  // r_b dT t^2 / (2 J_lay) < 0.04 m * 10 N m * (0.05 s)^2 / 2e8 kg m^2 = 5e-12 m with
  // J_lay = 1e8 kg m^2. Both stages run in permanent contact (no chaos amplifies differences).
  const double j_lay = 1e8;
  const Model full(testing::TwoStageAlone(0, j_lay)), first(testing::TwoStageAlone(1, j_lay)),
      second(testing::TwoStageAlone(2, j_lay));
  REQUIRE(first.tables.meshes[0].transmitted_torque ==
          Approx(full.tables.meshes[0].transmitted_torque).epsilon(1e-12));
  REQUIRE(second.tables.meshes[0].transmitted_torque ==
          Approx(full.tables.meshes[1].transmitted_torque).epsilon(1e-12));
  const auto [z_full, s_full] = TrainStaticState(full.tables);
  const auto [z_first, s_first] = TrainStaticState(first.tables);
  const auto [z_second, s_second] = TrainStaticState(second.tables);
  TrainStepper a(full.tables, {}, z_full, s_full), b(first.tables, {}, z_first, s_first),
      c(second.tables, {}, z_second, s_second);
  const double period = full.tables.meshes[0].period;
  double worst[2] = {0.0, 0.0}, scale[2] = {0.0, 0.0};
  for (int k = 1; k <= 400; ++k) {
    const double time = k * period / 8.0;
    REQUIRE(a.Run(time));
    REQUIRE(b.Run(time));
    REQUIRE(c.Run(time));
    const double te[2] = {full.tables.meshes[0].v.dot(a.state().head(full.tables.n)),
                          full.tables.meshes[1].v.dot(a.state().head(full.tables.n))};
    const double alone[2] = {first.tables.meshes[0].v.dot(b.state().head(first.tables.n)),
                             second.tables.meshes[0].v.dot(c.state().head(second.tables.n))};
    for (int i = 0; i < 2; ++i) {
      worst[i] = std::max(worst[i], std::abs(te[i] - alone[i]));
      scale[i] = std::max(scale[i], std::abs(alone[i]));
    }
  }
  CHECK(a.summary().events == 0);
  // Tolerance: 1e-7 of the TE (1e-11 m), above the < 5e-12 m coupling left through the layshaft
  // (measured 5e-16 m) and far below what a wrong per-mesh period, phase or load would make.
  INFO("TE differences " << worst[0] << ", " << worst[1] << " m");
  CHECK(worst[0] <= 1e-7 * scale[0]);
  CHECK(worst[1] <= 1e-7 * scale[1]);
}

TEST_CASE("train: the dense fallback agrees with the closed-form path", "[solver][train]") {
  // max_condition = 1 sends every tuple to the dense Taylor path (cond(S) > 1 always): an
  // independent locator on the same model. Tolerance: both are exact to rounding; over 8 ms of
  // rattling (differences grow ~tenfold per ms, see the CVODE test) 1e-8 of the TE.
  const Model s(Rattler(1500.0));
  const auto [z0, states0] = TrainStaticState(s.tables);
  TrainStepperOptions dense;
  dense.tables.max_condition = 1.0;
  dense.tables.decompose_after_visits = 1;  // every tuple tries (and fails) at its first entry
  TrainStepperOptions spectral;
  spectral.tables.decompose_after_visits = 1;
  TrainStepper a(s.tables, spectral, z0, states0), b(s.tables, dense, z0, states0);
  double worst = 0.0, scale = 0.0;
  for (int k = 1; k <= 64; ++k) {
    const double time = 0.008 * k / 64.0;
    REQUIRE(a.Run(time));
    REQUIRE(b.Run(time));
    for (const TrainMeshTable& mt : s.tables.meshes) {
      const double te = mt.v.dot(a.state().head(s.tables.n));
      worst = std::max(worst, std::abs(te - mt.v.dot(b.state().head(s.tables.n))));
      scale = std::max(scale, std::abs(te));
    }
  }
  CHECK(a.summary().dense_pieces == 0);
  CHECK(b.summary().dense_pieces > 0);
  CHECK(b.summary().cache.ill_conditioned == b.summary().cache.misses);
  CHECK(a.summary().events == b.summary().events);
  CHECK(a.summary().events >= 10);
  INFO("worst TE difference " << worst << " m");
  CHECK(worst <= 1e-8 * scale);
}

// The V1, V2 and V3 train locators on the rattling train: the same events (mesh, transition,
// order) and the same TE. Each run keeps its event log through the recorder's counts and the
// states seen at dense checkpoints.
struct MethodRun {
  std::vector<double> te;  // per checkpoint and mesh
  std::vector<ContactState> states;
  TrainStepperSummary summary;
};

MethodRun RunMethod(const TrainTables& t, EventMethod method, int checkpoints, double end) {
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepperOptions options;
  options.events = method;
  TrainStepper stepper(t, options, z0, states0);
  MethodRun out;
  for (int k = 1; k <= checkpoints; ++k) {
    REQUIRE(stepper.Run(end * k / checkpoints));
    for (const TrainMeshTable& mt : t.meshes) out.te.push_back(mt.v.dot(stepper.state().head(t.n)));
    out.states.insert(out.states.end(), stepper.states().begin(), stepper.states().end());
  }
  out.summary = stepper.summary();
  return out;
}

TEST_CASE("train: V1, V2 and V3 agree on a rattling train", "[solver][train][methods]") {
  const Model s(Rattler(1500.0));
  const double end = 0.008;  // 15+ events (see the CVODE test)
  const int checkpoints = 256;
  const MethodRun v3 = RunMethod(s.tables, EventMethod::kSpectral, checkpoints, end);
  const MethodRun v2 = RunMethod(s.tables, EventMethod::kTaylor, checkpoints, end);
  const MethodRun v1 = RunMethod(s.tables, EventMethod::kDyadic, checkpoints, end);
  REQUIRE(v3.summary.events >= 10);
  CHECK(v2.summary.dense_pieces > 0);
  CHECK(v1.summary.dyadic_substeps >= v3.summary.events);
  // The same events: counts, and the contact state of every mesh at each of 256 checkpoints
  // (31 us apart, shorter than any contact or flight here) is the same.
  CHECK(v2.summary.events == v3.summary.events);
  CHECK(v1.summary.events == v3.summary.events);
  CHECK(v2.states == v3.states);
  CHECK(v1.states == v3.states);
  double scale = 0.0, worst2 = 0.0, worst1 = 0.0;
  for (size_t k = 0; k < v3.te.size(); ++k) {
    scale = std::max(scale, std::abs(v3.te[k]));
    worst2 = std::max(worst2, std::abs(v2.te[k] - v3.te[k]));
    worst1 = std::max(worst1, std::abs(v1.te[k] - v3.te[k]));
  }
  INFO("worst TE difference V2 " << worst2 << " m, V1 " << worst1 << " m, TE scale " << scale);
  // Tolerances: V2 and V3 are exact to rounding; over 8 ms of rattling (differences grow about
  // tenfold per ms, see the CVODE test) 1e-8 of the TE, as the CVODE reference. V1 places every
  // event at the end of its dyadic cell, up to d 2^-34 late (d <= the sub-step, ~1e-5 s here:
  // ~1e-15 s), a TE error of |g'| 1e-15 s ~ 1e-18 m per event before growth: 1e-8 too.
  CHECK(worst2 <= 1e-8 * scale);
  CHECK(worst1 <= 1e-8 * scale);
}

TEST_CASE("train: V1 places a crossing whose finer cells are lost in the gap's rounding",
          "[solver][train][methods]") {
  // Three shafts, 1 N m on the last, engine order 2 of 500 rad/s^2 at 1000 rpm: the excitation
  // swings the angles to ~1e-2 rad, so a gap (differences of r_b theta ~ 1e-4 m) carries rounding
  // of ~1e-19 m, while a separation at |g'| ~ 1e-4 m/s moves it by ~1e-19 m per cell of d 2^-34.
  // Bisecting such a crossing to the finest cell crawled through cells that do not move z (a
  // user's `validate` ran for two minutes and V1 then disagreed with V3 by 1e-4).
  TrainSpec spec = TwoStage(1.0, 500.0, 1000.0);
  spec.shafts[0].inertia = 2e-3;
  spec.shafts[1].inertia = 3e-3;
  spec.shafts[2].inertia = 1e-3;
  spec.gears[0].gear.teeth = 23;
  spec.gears[1].gear.teeth = 41;
  spec.gears[2].gear.teeth = 19;
  spec.gears[3].gear.teeth = 37;
  for (TrainGear& g : spec.gears) g.gear.bore_diameter = 20e-3;
  spec.analysis.segments_per_cycle = 32;
  const Model s(spec);
  const double end = 16.0 * s.tables.meshes[0].period;
  const int checkpoints = 64;
  const MethodRun v3 = RunMethod(s.tables, EventMethod::kSpectral, checkpoints, end);
  const MethodRun v1 = RunMethod(s.tables, EventMethod::kDyadic, checkpoints, end);
  REQUIRE(v3.summary.events >= 10);
  CHECK(v1.summary.events == v3.summary.events);
  CHECK(v1.states == v3.states);
  // A walk takes at most 2 x 34 aligned steps plus 34 bisections per crossing or turn it
  // resolves: 400 cell maps per flagged sub-step is generous (the crawl took millions).
  INFO(v1.summary.dyadic_matvecs << " cell maps in " << v1.summary.dyadic_substeps
                                 << " flagged sub-steps");
  CHECK(v1.summary.dyadic_matvecs <= 400 * v1.summary.dyadic_substeps);
  double scale = 0.0, worst = 0.0;
  for (size_t k = 0; k < v3.te.size(); ++k) {
    scale = std::max(scale, std::abs(v3.te[k]));
    worst = std::max(worst, std::abs(v1.te[k] - v3.te[k]));
  }
  // As the V1/V3 agreement above: 1e-8 of the TE (measured 3e-9 by validate).
  CHECK(worst <= 1e-8 * scale);
}

TEST_CASE("train: V1, V2 and V3 find a near-grazing excursion and ignore a near miss",
          "[solver][train][methods]") {
  // The rattler without the layshaft load (so the meshes barely accelerate apart) and without
  // excitation, every mesh free: the loose gear's gap delta_1(t) = a + b t + c t^2 is a parabola
  // whose extremum at t_a is placed eps = 1e-9 m beyond its wall (a brief excursion: an event) or
  // eps inside it (a near miss: none). The excursion lasts 2 sqrt(eps / |c|) ~ 30 us, shorter than
  // a grid segment (230 us), with |g'| ~ 1e-4 m/s at its roots (far from grazing's 1e-9 m/s).
  TrainSpec spec = Rattler(0.0);
  spec.operating.loads = {{"g4", 0.05}};
  const Model s(spec);
  const TrainTables& t = s.tables;
  const int n = t.n;
  const int loose = 2;
  REQUIRE(t.loose[loose]);
  const TrainMeshTable& mt = t.meshes[1];
  const Eigen::VectorXd acc = t.force.cwiseQuotient(t.inertia);
  const double c = 0.5 * mt.v.dot(acc);
  REQUIRE(std::abs(c) > 1.0);  // m/s^2: the drag does curve the gap
  // t_a: the middle of the first grid segment longer than 150 us after 200 us.
  TrainGrid grid(t);
  while (grid.start() < 200e-6 || grid.end() - grid.start() < 150e-6) grid.Next();
  const double t_a = 0.5 * (grid.start() + grid.end());
  const double e = mt.error[static_cast<size_t>(grid.segments()[1])];
  const double eps = 1e-9;
  const std::vector<ContactState> free(2, ContactState::kFree);
  for (const double side : {1.0, -1.0}) {  // +1 beyond the wall, -1 short of it
    // A maximum (c < 0) reaches the drive wall e + b from below, a minimum the back wall e - b.
    const double peak =
        c < 0.0 ? e + mt.half_backlash + side * eps : e - mt.half_backlash - side * eps;
    Eigen::VectorXd z0 = Eigen::VectorXd::Zero(t.m);
    z0[t.constant_slot()] = 1.0;
    z0[loose] = (peak + c * t_a * t_a) / mt.v[loose];  // delta(0) = peak + c t_a^2
    z0[n + loose] = -2.0 * c * t_a / mt.v[loose];      // delta'(t_a) = 0
    // The first root of delta(t) = peak - side eps, before t_a.
    const double root = t_a - std::sqrt(eps / std::abs(c));
    for (const EventMethod method :
         {EventMethod::kSpectral, EventMethod::kTaylor, EventMethod::kDyadic}) {
      INFO("method " << EventMethodName(method) << ", side " << side);
      TrainStepperOptions options;
      options.events = method;
      TrainStepper before(t, options, z0, free), after(t, options, z0, free);
      // Tolerance of the event time: 1e-10 s. The root is conditioned by |g'| ~ 1e-4 m/s against
      // a gap rounding of ~1e-19 m (1e-15 s); V1 places it up to d 2^-34 ~ 1e-14 s late.
      REQUIRE(before.Run(root - 1e-10));
      CHECK(before.summary().events == 0);
      REQUIRE(after.Run(grid.end()));
      if (side > 0.0) {
        CHECK(after.summary().events >= 1);
        TrainStepper just(t, options, z0, free);
        REQUIRE(just.Run(root + 1e-10));
        CHECK(just.summary().events == 1);
        CHECK(just.states()[1] != ContactState::kFree);
        CHECK(just.states()[0] == ContactState::kFree);
      } else {
        CHECK(after.summary().events == 0);
        CHECK(after.states()[1] == ContactState::kFree);
      }
    }
  }
}

TEST_CASE("train: the recorded statistics are exact, against dense samples of the exact state",
          "[solver][train][statistics]") {
  // The rattling train over [10, 30] ms. Independent evaluation: the stepper's state at 40001
  // evenly spaced times (exact, no interpolation), each output from the state (TE v^T x, force
  // k (v^T x - wall) + c v^T x' with the mesh's segment from a separately walked TrainGrid,
  // acceleration as the row of an independently assembled generator), integrated by Simpson's
  // rule. The recorder integrates polynomial chunks in closed form and certifies extrema.
  const Model s(Rattler(1500.0));
  const TrainTables& t = s.tables;
  const int n = t.n;
  const auto [z0, states0] = TrainStaticState(t);
  const double start = 0.01, end = 0.03;
  // One run, recorded and sampled: a rattling train amplifies rounding (about tenfold per ms), so
  // two runs stopped at different times part after ~10 ms.
  TrainStepper dense(t, {}, z0, states0);
  TrainRecorder recorder(t, 32, start);
  recorder.KeepEvents(1000000);
  REQUIRE(dense.Run(start, &recorder));

  const int samples = 40000;  // even: Simpson
  const size_t meshes = t.meshes.size();
  std::vector<double> te_sum(meshes, 0.0), te_sum2(meshes, 0.0), force_sum(meshes, 0.0);
  std::vector<double> te_min(meshes, 1e300), te_max(meshes, -1e300), force_max(meshes, -1e300);
  std::vector<double> acc_sum(static_cast<size_t>(n), 0.0), acc_sum2(static_cast<size_t>(n), 0.0);
  TrainGrid grid(t);
  const double dt = (end - start) / samples;
  for (int k = 0; k <= samples; ++k) {
    const double time = start + k * dt;
    REQUIRE(dense.Run(time, &recorder));
    while (grid.end() <= time) grid.Next();
    const double weight = (k == 0 || k == samples) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
    const Eigen::VectorXd& z = dense.state();
    for (size_t i = 0; i < meshes; ++i) {
      const TrainMeshTable& mt = t.meshes[i];
      const double te = mt.v.dot(z.head(n));
      double force = 0.0;
      const ContactState st = dense.states()[i];
      if (st != ContactState::kFree) {
        const bool drive = st == ContactState::kDrive;
        const size_t j = static_cast<size_t>(grid.segments()[i]);
        force = (drive ? mt.k_drive[j] : mt.k_back[j]) *
                    (te - t.Wall(static_cast<int>(i), grid.segments()[i], drive)) +
                mt.damping * mt.v.dot(z.segment(n, n));
      }
      te_sum[i] += weight * te;
      te_sum2[i] += weight * te * te;
      force_sum[i] += weight * force;
      te_min[i] = std::min(te_min[i], te);
      te_max[i] = std::max(te_max[i], te);
      force_max[i] = std::max(force_max[i], force);
    }
    const Eigen::VectorXd acc = AssembleTrainGenerator(t, grid.segments(), dense.states()) * z;
    for (int b = 0; b < n; ++b) {
      acc_sum[static_cast<size_t>(b)] += weight * acc[n + b];
      acc_sum2[static_cast<size_t>(b)] += weight * acc[n + b] * acc[n + b];
    }
  }
  const TrainStatistics exact = recorder.Result();
  REQUIRE(dense.summary().events >= 20);
  const double third = dt / 3.0 / (end - start);  // Simpson weights, divided by the duration
  for (size_t i = 0; i < meshes; ++i) {
    const TrainMeshStatistics& e = exact.meshes[i];
    const double mean = te_sum[i] * third;
    const double rms = std::sqrt(std::max(0.0, te_sum2[i] * third - mean * mean));
    const double p2p = te_max[i] - te_min[i];
    INFO("mesh " << i << ": mean " << e.te_mean << " / " << mean << ", rms " << e.te_rms << " / "
                 << rms << ", p-p " << e.te_peak_to_peak << " / " << p2p << ", force mean "
                 << e.force_mean << " / " << force_sum[i] * third << ", max " << e.force_max
                 << " / " << force_max[i]);
    // Tolerances: Simpson's error on a signal whose derivatives jump at impacts is O(dt^2) per
    // jump (dt = 0.5 us, a contact lasts >= 50 us here): 1e-5 of the TE's p-p for its mean and
    // RMS, 1e-4 of the force scale for its mean. Extrema: the samples are a subset of the window,
    // so the exact extrema enclose them (to rounding, 1e-12 relative); a sampled TE peak misses
    // the true one by ~(dt / contact)^2: 1e-5 of the p-p. The force jumps at segment boundaries
    // (k_j, e_j), so its maximum can be a one-sided limit there, which samples approach only to
    // dt |F'| (measured 6.6e-4 of the maximum on the loaded mesh): 3e-3.
    CHECK(std::abs(e.te_mean - mean) <= 1e-5 * p2p);
    CHECK(std::abs(e.te_rms - rms) <= 1e-5 * p2p);
    CHECK(e.te_peak_to_peak >= p2p * (1.0 - 1e-12));
    CHECK(e.te_peak_to_peak <= p2p * (1.0 + 1e-5));
    CHECK(std::abs(e.force_mean - force_sum[i] * third) <= 1e-4 * std::abs(force_max[i]));
    CHECK(e.force_max >= force_max[i] - 1e-12 * std::abs(force_max[i]));
    CHECK(e.force_max <= force_max[i] + 3e-3 * std::abs(force_max[i]));
  }
  REQUIRE(exact.loose_gears.size() == 1);
  const size_t b = static_cast<size_t>(exact.loose_gears[0].body);
  const double acc_mean = acc_sum[b] * third;
  const double rattle = std::sqrt(std::max(0.0, acc_sum2[b] * third - acc_mean * acc_mean));
  INFO("rattle index " << exact.loose_gears[0].rattle_index << " / " << rattle);
  // The acceleration jumps at every event and segment boundary: Simpson's rule is first order
  // there, ~dt / contact per jump (measured 1.4e-4): 1e-3.
  CHECK(std::abs(exact.loose_gears[0].rattle_index - rattle) <= 1e-3 * rattle);

  // The loose gear's impacts from the kept event list (free -> contact on its meshes), with the
  // effective mass from the bodies' inertias and base radii (m_e = J_a J_b / (J_a r_b^2 +
  // J_b r_a^2): v = r_a e_a - r_b e_b, so r_a = v_a and r_b = -v_b): equal to rounding of the same
  // sums (1e-12).
  const TrainLooseGearStatistics& g = exact.loose_gears[0];
  REQUIRE(recorder.window_events() == static_cast<long>(recorder.events().size()));
  long drive = 0, back = 0;
  double sum2 = 0.0, vmax = 0.0, energy = 0.0;
  for (const TrainEventRecord& e : recorder.events()) {
    const TrainMeshTable& mt = t.meshes[static_cast<size_t>(e.mesh)];
    if (mt.body_a != g.body && mt.body_b != g.body) continue;
    if (e.event.from != ContactState::kFree) continue;
    (e.event.to == ContactState::kDrive ? drive : back) += 1;
    const double ja = t.inertia[mt.body_a], jb = t.inertia[mt.body_b];
    const double ra = mt.v[mt.body_a], rb = -mt.v[mt.body_b];
    sum2 += e.event.gap_rate * e.event.gap_rate;
    vmax = std::max(vmax, std::abs(e.event.gap_rate));
    energy += 0.5 * ja * jb / (ja * rb * rb + jb * ra * ra) * e.event.gap_rate * e.event.gap_rate;
  }
  REQUIRE(drive + back >= 5);  // it rattles (8 impacts in this window)
  CHECK(g.drive_impacts == drive);
  CHECK(g.back_impacts == back);
  CHECK(g.impacts == drive + back);
  CHECK(g.rank == 1);
  CHECK(g.drive_impacts_per_second == Approx(drive / (end - start)).epsilon(1e-12));
  CHECK(g.back_impacts_per_second == Approx(back / (end - start)).epsilon(1e-12));
  CHECK(g.impact_velocity_rms == Approx(std::sqrt(sum2 / (drive + back))).epsilon(1e-12));
  CHECK(g.impact_velocity_max == vmax);
  CHECK(g.impact_energy_per_second == Approx(energy / (end - start)).epsilon(1e-12));
}

TEST_CASE("train: lazy decomposition (dense until a tuple's third entry) agrees with eager",
          "[solver][train]") {
  // The default policy propagates a tuple on the dense path until it is entered for the
  // decompose_after_visits-th time; eager decomposes at the first entry. Both paths are exact to
  // rounding, so over 8 ms of rattling (differences grow ~tenfold per ms) 1e-8 of the TE, as the
  // dense-fallback test.
  const Model s(Rattler(1500.0));
  const auto [z0, states0] = TrainStaticState(s.tables);
  TrainStepperOptions eager, lazy;
  eager.tables.decompose_after_visits = 1;
  REQUIRE(lazy.tables.decompose_after_visits == 3);
  TrainStepper a(s.tables, eager, z0, states0), b(s.tables, lazy, z0, states0);
  double worst = 0.0, scale = 0.0;
  for (int k = 1; k <= 64; ++k) {
    const double time = 0.008 * k / 64.0;
    REQUIRE(a.Run(time));
    REQUIRE(b.Run(time));
    for (const TrainMeshTable& mt : s.tables.meshes) {
      const double te = mt.v.dot(a.state().head(s.tables.n));
      worst = std::max(worst, std::abs(te - mt.v.dot(b.state().head(s.tables.n))));
      scale = std::max(scale, std::abs(te));
    }
  }
  const TrainCacheSummary& cache = b.summary().cache;
  CHECK(b.summary().dense_pieces > 0);
  CHECK(cache.decompositions > 0);             // tuples entered three times are decomposed
  CHECK(cache.decompositions < cache.misses);  // and some never are
  CHECK(a.summary().cache.decompositions == a.summary().cache.misses);
  CHECK(a.summary().events == b.summary().events);
  INFO("worst TE difference " << worst << " m");
  CHECK(worst <= 1e-8 * scale);
}

TEST_CASE("train: a tuple's sub-step bound covers its spectral radius", "[solver][train]") {
  // substep = 1/(2 rho~) with rho~ = max(sqrt(lambda_max(M^-1 K)), lambda_max(M^-1 C)) >= rho(A)
  // (Rayleigh quotients of the symmetric pencil); checked against the general eigensolver of
  // the dynamic block for every contact state of the rattler, and not loose by more than the
  // damping term (rho~ <= rho + lambda_max(M^-1 C)).
  const Model s(Rattler(1500.0));
  TrainSystemCache cache(s.tables, {});
  TupleKey key(static_cast<size_t>(cache.KeyWords()));
  const ContactState all[3] = {ContactState::kBack, ContactState::kFree, ContactState::kDrive};
  const int n = s.tables.n;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const TrainSystem& sys = cache.Get({5, 2}, {all[a], all[b]}, key);
      const double rho = sys.A.topLeftCorner(2 * n, 2 * n).eigenvalues().cwiseAbs().maxCoeff();
      if (a == 1 && b == 1) {  // all free: only the engine order's exosystem turns, at w
        const double w = s.tables.HighestExcitationFrequency();
        REQUIRE(w > 0.0);
        CHECK(sys.rho == w);
        CHECK(sys.substep == std::min(0.5 / w, TrainSystem::kMaxDenseStepNorm / sys.rate));
        continue;
      }
      const double bound = 0.5 / sys.substep;
      // Tolerance: the general eigensolver's error in |lambda| is ~ eps |A| / |lambda| (|A| ~
      // |M^-1 K| ~ 1e9 s^-2, |lambda| ~ 4e4 s^-1: ~1e-11 relative); 1e-9 leaves room for that.
      CHECK(rho <= bound * (1.0 + 1e-9));
      CHECK(sys.rate == ScaledRowNorm(sys.A, BalancingScale(sys.A, n, sys.w_ref)));
      CHECK(sys.rate * sys.substep <= TrainSystem::kMaxDenseStepNorm * (1.0 + 1e-15));
      if (sys.rate * sys.substep < 0.999 * TrainSystem::kMaxDenseStepNorm) {
        // Set by the Rayleigh bound: not loose by more than the damping term.
        const double damping = (-sys.A.block(n, n, n, n)).eigenvalues().cwiseAbs().maxCoeff();
        CHECK(bound <= rho + damping + 1e-9 * bound);
      }
    }
  }
}

TEST_CASE("train: the dense path's 20-term Taylor polynomial is within its remainder bound",
          "[solver][train]") {
  // ||S (T_20(A d) - e^{A d}) S^-1||_inf <= e^q q^21 / 21! with q = ||S A S^-1|| d <= 1.5
  // (below 4.4e-16), so the difference is the rounding of the two evaluations: 1e-13 bounds it (the
  // balanced Pade's rounding, ~1e3 eps at these norms).
  const Model s(Rattler(1500.0));
  TrainSystemCache cache(s.tables, {});
  TupleKey key(static_cast<size_t>(cache.KeyWords()));
  const ContactState all[3] = {ContactState::kBack, ContactState::kFree, ContactState::kDrive};
  const int n = s.tables.n, m = s.tables.m;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const TrainSystem& sys = cache.Get({5, 2}, {all[a], all[b]}, key);
      const Eigen::VectorXd& scale = sys.balance;
      const double d = sys.substep;
      Eigen::MatrixXd taylor = Eigen::MatrixXd::Identity(m, m), term = taylor;
      for (int p = 1; p <= TrainStepper::kTaylorTerms; ++p) {
        term = (sys.A * term * (d / p)).eval();
        taylor += term;
      }
      const Eigen::MatrixXd error = scale.asDiagonal() *
                                    (taylor - BalancedExpm(sys.A, d, n, sys.w_ref)) *
                                    scale.cwiseInverse().asDiagonal();
      const double worst = error.cwiseAbs().rowwise().sum().maxCoeff();
      INFO("states " << a << ", " << b << ": q = " << sys.rate * d << ", error " << worst);
      CHECK(worst <= 1e-13);
    }
  }
}

TEST_CASE("train tables: a decomposition with the free bodies split off reproduces expm(A t)",
          "[solver][train]") {
  // Every contact state of the rattler (a free mesh leaves the loose gear, or every body, free:
  // those coordinates join the zero cluster in closed form) against the dense balanced Pade
  // exponential of the same generator, an independent method. Tolerance: the decomposition's
  // error is bounded by cond(S) eps (cond(S) <= max_condition = 1e6: 2e-10) of the balanced
  // state, Pade's by a few eps; 1e-8 of each block's largest entry leaves room for the
  // balancing between positions and velocities.
  const Model s(Rattler(1500.0));
  TrainTableOptions options;
  options.decompose_after_visits = 1;
  TrainSystemCache cache(s.tables, options);
  TupleKey key(static_cast<size_t>(cache.KeyWords()));
  const ContactState all[3] = {ContactState::kBack, ContactState::kFree, ContactState::kDrive};
  const int n = s.tables.n, m = s.tables.m;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(m);
  for (int j = 0; j < n; ++j) {
    z[j] = 1e-5 * (j + 1);
    z[n + j] = 0.3 * (j % 2 == 0 ? 1.0 : -1.0) * (j + 1);
  }
  z[s.tables.constant_slot()] = 1.0;
  z[s.tables.input_slot()] = 800.0;  // the engine order's sine state (its cosine 0)
  int spectral = 0, split = 0;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const TrainSystem& sys = cache.Get({4, 9}, {all[a], all[b]}, key);
      if (!sys.spectral) continue;
      ++spectral;
      if (static_cast<int>(sys.coupled_columns.size()) < 2 * n) ++split;
      const SpectralDecomposition& d = sys.decomposition;
      Eigen::VectorXd w = d.S_inv * z, wt(m), scratch(m);
      for (double share : {0.25, 1.0}) {
        const double t = share * s.tables.longest_segment;
        PropagateDecoupled(d, w, t, wt, scratch);
        const Eigen::VectorXd spectral_z = d.S * wt;
        const Eigen::VectorXd dense_z = BalancedExpm(sys.A, t, n, sys.w_ref) * z;
        for (int block = 0; block < 2; ++block) {
          const auto x = dense_z.segment(block * n, n);
          const double error = (spectral_z.segment(block * n, n) - x).cwiseAbs().maxCoeff();
          CHECK(error <= 1e-8 * x.cwiseAbs().maxCoeff());
        }
        CHECK(std::abs(spectral_z[s.tables.constant_slot()] - 1.0) <= 1e-12);
      }
    }
  }
  CHECK(spectral >= 8);
  CHECK(split >= 5);  // a free mesh frees the loose gear (five of the nine states)
}

TEST_CASE("train: a run past the events limit stops in the grid segment that passed it and says so",
          "[solver][train]") {
  const Model s(Rattler(1500.0));
  const TrainTables& t = s.tables;
  const double end = 0.008;  // 15+ events (see the CVODE test)
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepperOptions options;
  options.jumps = false;
  TrainStepper full(t, options, z0, states0);
  TrainRecorder recorder(t, 8, 0.0);
  recorder.KeepEvents(4096);
  REQUIRE(full.Run(end, &recorder));
  const TrainStepperSummary done = full.summary();
  CHECK(done.info == TrainStepperSummary::Info::kSuccess);
  CHECK(TrainStepperMessage(done).empty());
  CHECK(std::string(TrainStepperInfoName(done.info)) == "success");
  // An independent count of the located events per grid segment, from the event log and a walk
  // of the grid (grazing touches count towards the limit too; none here).
  REQUIRE(done.grazing == 0);
  REQUIRE(static_cast<long>(recorder.events().size()) == done.events);
  std::vector<std::pair<double, double>> segments;
  std::vector<long> counts;
  for (TrainGrid grid(t); grid.start() < end; grid.Next()) {
    segments.emplace_back(grid.start(), grid.end());
    counts.push_back(0);
  }
  for (const TrainEventRecord& e : recorder.events()) {
    size_t k = 0;
    while (k + 1 < segments.size() && e.event.time >= segments[k + 1].first) ++k;
    ++counts[k];
  }
  const long busiest = *std::max_element(counts.begin(), counts.end());
  INFO("most events in one grid segment: " << busiest);
  REQUIRE(busiest >= 2);  // a limit of busiest - 1 >= 1 is then passed
  options.max_events_per_segment = busiest - 1;
  size_t first = 0;
  while (counts[first] < busiest) ++first;
  TrainStepper limited(t, options, z0, states0);
  CHECK_FALSE(limited.Run(end));
  const TrainStepperSummary stopped = limited.summary();
  CHECK(stopped.info == TrainStepperSummary::Info::kTooManyEvents);
  CHECK(std::string(TrainStepperInfoName(stopped.info)) == "too many events");
  CHECK(stopped.event_limit == busiest - 1);
  // The same grid walk: the segment's ends to rounding of the time (a few ulps of 8 ms).
  CHECK(stopped.stopped_from == Approx(segments[first].first).epsilon(0).margin(1e-15));
  CHECK(stopped.stopped_to == Approx(segments[first].second).epsilon(0).margin(1e-15));
  const std::string message = TrainStepperMessage(stopped);
  INFO(message);
  CHECK(message.find("more than " + std::to_string(busiest - 1) + " contact events in the ") == 0);
  CHECK(message.find("grid segment starting at t = ") != std::string::npos);
}

}  // namespace
}  // namespace gearnvh
