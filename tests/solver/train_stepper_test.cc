// The exact event-driven solver on gear trains at tier 1 (solver/train_stepper.h): closed forms,
// an independent linear periodic solution, the CVODE reference, the cache bound, allocations.
#include "gearnvh/solver/train_stepper.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <iostream>
#include <numbers>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_statistics.h"
#include "model/test_specs.h"
#include "model/test_trains.h"
#include "support/allocation_counter.h"

namespace gearnvh {
namespace {

constexpr double kPi = std::numbers::pi;

// The small rattling train and the two-stage train of tests/model/test_trains.h.
TrainSpec Rattler(double excitation) { return testing::RattlerTrain(excitation); }
TrainSpec TwoStage(double load, double excitation, double rpm) {
  return testing::TwoStageTrain(load, excitation, rpm);
}

struct Model {
  TrainSpec spec;
  GearTrain train;
  TrainTables tables;
  explicit Model(TrainSpec s, TrainTableOptions options = {})
      : spec(std::move(s)),
        train(BuildGearTrain(spec)),
        tables(BuildTrainTables(spec, train, options)) {}
};

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

TEST_CASE("train: a free loose gear under constant drag follows its parabola until it hits",
          "[solver][train]") {
  // No excitation, every mesh free at t = 0: every body moves on its own parabola
  // th_j(t) = th_j0 + w_j0 t + f_j t^2 / (2 J_j) until the first impact, and the first impact is
  // the earliest root of the piecewise quadratic gaps (e_ij is constant per mesh segment).
  const Model s(Rattler(0.0));
  const TrainTables& t = s.tables;
  const int n = t.n;
  Eigen::VectorXd z0 = Eigen::VectorXd::Zero(t.m);
  z0[t.constant_slot()] = 1.0;
  const int loose = 2;  // bodies: input, layshaft, then the loose gear g4
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
  const int n = t.n, m = t.m;
  REQUIRE(t.common_period > 0.0);
  struct Piece {
    std::vector<int> segments;
    double start, h, u;
  };
  std::vector<Piece> pieces;
  for (TrainGrid grid(t); grid.start() < t.common_period * (1.0 - 1e-12); grid.Next()) {
    const double h = grid.end() - grid.start();
    pieces.push_back({grid.segments(), grid.start(), h, t.MeanExcitation(grid.start(), h)});
  }
  const std::vector<ContactState> drive(2, ContactState::kDrive);
  std::vector<Eigen::MatrixXd> maps;
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(m, m);
  for (const Piece& p : pieces) {
    const Eigen::MatrixXd A = AssembleTrainGenerator(t, p.segments, drive);
    Eigen::MatrixXd R = Eigen::MatrixXd::Identity(m, m);  // input slot <- u (z_c = 1)
    R(t.input_slot(), t.input_slot()) = 0.0;
    R(t.input_slot(), t.constant_slot()) = p.u;
    maps.push_back(BalancedExpm(A, p.h, n, ReferenceFrequency(A, n)) * R);
    P = maps.back() * P;
  }
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(2 * n, 2 * n);
  const Eigen::VectorXd y = (I - P.topLeftCorner(2 * n, 2 * n))
                                .completeOrthogonalDecomposition()
                                .solve(P.block(0, t.constant_slot(), 2 * n, 1));
  Eigen::VectorXd z = Eigen::VectorXd::Zero(m);
  z.head(2 * n) = y;
  z[t.constant_slot()] = 1.0;

  TrainStepper stepper(t, {}, z, drive);
  double te_scale = 0.0;
  double worst = 0.0;
  Eigen::VectorXd reference = z;
  for (size_t k = 0; k < pieces.size(); ++k) {
    reference = maps[k] * reference;
    REQUIRE(stepper.Run(pieces[k].start + pieces[k].h));
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

TEST_CASE("train: the stepping loop does not allocate once the cache holds the tuples",
          "[solver][train][allocation]") {
  const Model s(Rattler(1500.0));
  const auto [z0, states0] = TrainStaticState(s.tables);
  TrainStepper stepper(s.tables, {}, z0, states0);
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
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

// Input (g1, 20) -> layshaft (g2, 40; g3, 20) -> output (g4, 40) with the layshaft `inertia`; or
// one of its stages alone as a one-mesh train with the same transmitted torque.
TrainSpec Stage(int which, double layshaft_inertia) {
  // No engine excitation: it is held at its mean over each grid segment, and the train's grid (the
  // union of both meshes' boundaries) is finer than a stage's own, a legitimate difference of the
  // piecewise model (first order in the segment length) this test is not about.
  TrainSpec t = TwoStage(150.0, 0.0, 600.0);
  t.operating.excitation.clear();
  t.shafts[1].inertia = layshaft_inertia;
  if (which == 1) {  // input -> layshaft, the output load carried by the layshaft
    t.shafts = {t.shafts[0], t.shafts[1]};
    t.gears = {t.gears[0], t.gears[1]};
    t.meshes = {t.meshes[0]};
    t.operating.loads = {{"layshaft", 75.0}};  // the same power at half the output ratio
  } else if (which == 2) {  // the layshaft as the input, turning at its nominal speed
    t.shafts = {t.shafts[1], t.shafts[2]};
    t.gears = {t.gears[2], t.gears[3]};
    t.meshes = {t.meshes[1]};
    t.operating.input_shaft = "layshaft";
    t.operating.speed *= 0.5;
    t.operating.excitation.clear();
  }
  return t;
}

TEST_CASE("train: two meshes decoupled by a massive layshaft reproduce one-mesh trains",
          "[solver][train]") {
  // With a massive layshaft the first stage is the input turning against a layshaft at nominal
  // speed, the second the layshaft (as an input without excitation) driving the output. What
  // couples them is the layshaft's motion under the other stage's force fluctuation dT:
  // r_b dT t^2 / (2 J_lay) < 0.04 m * 10 N m * (0.05 s)^2 / 2e8 kg m^2 = 5e-12 m with
  // J_lay = 1e8 kg m^2. Both stages run in permanent contact (no chaos amplifies differences).
  const double j_lay = 1e8;
  const Model full(Stage(0, j_lay)), first(Stage(1, j_lay)), second(Stage(2, j_lay));
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
  TrainStepper a(s.tables, {}, z0, states0), b(s.tables, dense, z0, states0);
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
  CHECK(b.summary().dense_pieces > 0);
  CHECK(b.summary().cache.ill_conditioned == b.summary().cache.misses);
  CHECK(a.summary().events == b.summary().events);
  CHECK(a.summary().events >= 10);
  INFO("worst TE difference " << worst << " m");
  CHECK(worst <= 1e-8 * scale);
}

}  // namespace
}  // namespace gearnvh
