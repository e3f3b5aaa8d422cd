#include "solver/conformance_cases.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>
#include <sstream>

#include "gearnvh/solver/tangent_propagator.h"
#include "gearnvh/solver/train_stepper.h"
#include "gearnvh/solver/train_tangents.h"
#include "model/test_specs.h"
#include "model/test_trains.h"
#include "solver/train_model.h"
#include "support/allocation_counter.h"

namespace gearnvh::testing {
namespace {

// ---------------------------------------------------------------------------------------------
// The pair: ExactStepper stepping segment by segment with the locator of SolverOptions::events.

// Tier 5 needs flexible shafts: the two-shaft layout of examples/flexible_shafts.yaml at
// idle-rattle load, 8 segments per mesh cycle (keeps V1's 34 dyadic levels per segment and state at
// ~45 MB).
GearboxSpec FlexibleRattleSpec() {
  GearboxSpec spec = FlexibleShaftsPair(0.02);
  spec.operating.torque = 2.0;
  spec.operating.excitation = {{2.0, 3000.0, 0.0}};
  spec.analysis.segments_per_cycle = 8;
  return spec;
}

// Tier 1 without excitation and with constant stiffness: in the backlash the gap accelerates at
// the constant a = r_b1 (T r_b1 / r_b2) / J1 + r_b2 T / J2 towards the drive flank. Started at
// delta = 0 moving towards the back flank with |v0| = sqrt(2 a b (1 + eta)), the gap turns at
// -b (1 + eta): it crosses the back wall with |g'| = sqrt(2 a b eta), a near-grazing impact.
GearboxSpec GrazingSpec() {
  GearboxSpec spec = StandardPair(27, 43);
  spec.operating.torque = 0.3;
  spec.mesh.stiffness = FourierStiffness{2.5e8, {}, {}};
  return spec;
}
constexpr double kPairGrazingDepth = 1e-6;  // eta

// Idle rattle with a pinion runout of a fifth of the half backlash: the state carries the
// manufacturing-error input (tier 1: m = 8 with the engine order's two states), which the carried
// V3 path sets per segment.
GearboxSpec IdleRattleRunoutSpec() {
  GearboxSpec spec = IdleRattleSpec();
  spec.pinion.runout = Runout{0.2 * spec.mesh.backlash / 2.0, 0.4};
  return spec;
}

// The gap's constant acceleration in free flight of the grazing case (see GrazingSpec).
double PairGrazingAcceleration(const SolverSetup& s) {
  const double rb1 = s.model.geometry.pinion.base, rb2 = s.model.geometry.wheel.base;
  const double T = s.spec.operating.torque;
  return rb1 * (T * rb1 / rb2) / s.reduced.M(0, 0) + rb2 * T / s.reduced.M(1, 1);
}

const char* PairName(ConformanceCaseId id) {
  switch (id) {
    case ConformanceCaseId::kPairTier1:
      return "pair, tier 1 rattle";
    case ConformanceCaseId::kPairTier1Runout:
      return "pair, tier 1 rattle with runout";
    case ConformanceCaseId::kPairTier3:
      return "pair, tier 3 rattle";
    case ConformanceCaseId::kPairTier5:
      return "pair, tier 5 rattle";
    default:
      return "pair, near-grazing back impact";
  }
}

// Central differences of the map `cycles` mesh cycles ahead along the columns of the quotient
// basis Q, each step relative to the size of the block (positions or velocities) it perturbs, the
// result projected by L (the quotient by the pair's free rotation, as the tangent is).
Eigen::MatrixXd PairCentralDifference(ExactStepper& stepper, const SegmentTables& t,
                                      const Eigen::VectorXd& z, ContactState state,
                                      const Eigen::MatrixXd& Q, long cycles, double relative_step) {
  const int n = t.n;
  const Eigen::MatrixXd L = FreeRotationProjector(t).topLeftCorner(2 * n, 2 * n);
  const double position = z.head(n).norm(), velocity = z.segment(n, n).norm();
  Eigen::MatrixXd J(2 * n, Q.cols());
  for (Eigen::Index i = 0; i < Q.cols(); ++i) {
    const bool is_velocity = Q.col(i).tail(n).norm() > Q.col(i).head(n).norm();
    const double eps = relative_step * (is_velocity ? velocity : position);
    Eigen::VectorXd plus = z, minus = z;
    plus.head(2 * n) += eps * Q.col(i);
    minus.head(2 * n) -= eps * Q.col(i);
    stepper.Restart(plus, state);
    REQUIRE(stepper.Run(cycles, false));
    const Eigen::VectorXd end_plus = stepper.state();
    stepper.Restart(minus, state);
    REQUIRE(stepper.Run(cycles, false));
    J.col(i) = L * (end_plus - stepper.state()).head(2 * n) / (2.0 * eps);
  }
  return J;
}

class PairCase final : public ConformanceCase {
 public:
  explicit PairCase(ConformanceCaseId id) : id_(id) {}
  const char* name() const override { return PairName(id_); }
  int positions() const override { return PairSetup(id_).tables.n; }
  double segment_length() const override { return PairSetup(id_).tables.SegmentLength(0); }
  // Measured <= 1.5e-10 relative (V1 included, GCC) and 1.2e-9 (the rattle with runout, V3 vs V1,
  // clang with the sanitizers, once the engine order became exact: the rattle amplifies each
  // build's rounding differently): 3e-9.
  double state_bound(bool) const override { return 3e-9; }

  ConformanceOutcome Run(EventMethod method) const override {
    const PairRun run = RunPair(method, id_);
    ConformanceOutcome out;
    for (const EventRecord& e : run.events) out.events.push_back({0, e});
    const int n = positions();
    for (const Eigen::VectorXd& z : run.cycle_ends) out.cycle_ends.push_back(z.head(2 * n));
    out.drive_impacts = run.summary.drive_impacts;
    out.back_impacts = run.summary.back_impacts;
    out.separations = run.summary.separations;
    out.grazing = run.summary.grazing;
    return out;
  }

  void CheckPurpose(const ConformanceOutcome& out) const override {
    if (id_ != ConformanceCaseId::kPairGrazing) {
      CHECK(out.drive_impacts > 0);
      CHECK(out.separations > 0);
      return;
    }
    // The one near-grazing back impact with |g'| = sqrt(2 a b eta).
    const SolverSetup& s = PairSetup(id_);
    REQUIRE(!out.events.empty());
    CHECK(out.events[0].event.to == ContactState::kBack);
    const double rate =
        std::sqrt(2.0 * PairGrazingAcceleration(s) * s.tables.half_backlash * kPairGrazingDepth);
    CHECK(std::abs(out.events[0].event.gap_rate) == Approx(rate).epsilon(1e-3));
  }

  bool keeps_tables(EventMethod) const override { return true; }

  AllocationRun WarmRun(EventMethod method, bool with_tangent) const override {
    const SegmentTables& t = PairSetup(id_).tables;
    const auto [z0, state0] = StaticInitialState(t);
    SolverOptions opt;
    opt.method = SolverMethod::kStepped;
    opt.events = method;
    ExactStepper stepper(t, opt, z0, state0, 100 * 32, 1000);
    Eigen::MatrixXd tangent = Eigen::MatrixXd::Zero(t.m, 2 * t.n);
    tangent.topRows(2 * t.n).setIdentity();
    if (with_tangent) stepper.AttachTangent(&tangent);
    REQUIRE(stepper.event_method() == method);
    // Warm-up outside the counted region: the run once (V3 builds a decomposition when its
    // (segment, state) is first visited), then the same run again from the start.
    stepper.Run(35, true);
    stepper.Restart(z0, state0);
    stepper.Run(5, true);
    const long before = stepper.summary().events;
    AllocationRun out;
    {
      AllocationCounter counter;
      REQUIRE(stepper.Run(30, true));
      out.allocations = counter.count();
    }
    out.events = stepper.summary().events - before;
    return out;
  }

  TangentComparison CompareTangent(EventMethod method) const override {
    // Settled rattle; from successive cycle starts, a 3-cycle map with at least 3 contact
    // changes, none nearer grazing than |g'| = 0.3 b omega_m (near grazing an event time moves by
    // dz / g' and a finite difference loses accuracy), projected on the quotient by the free
    // rotation at both ends (the stepper recentres it at cycle ends).
    const SegmentTables& t = PairSetup(id_).tables;
    const int n = t.n;
    auto [z0, state0] = StaticInitialState(t);
    SolverOptions opt;
    opt.method = SolverMethod::kStepped;
    opt.events = method;
    opt.record_trajectory = false;
    ExactStepper walker(t, opt, z0, state0, 0, 0), probe(t, opt, z0, state0, 0, 0);
    REQUIRE(walker.Run(300, false));
    const Eigen::MatrixXd L = FreeRotationProjector(t).topLeftCorner(2 * n, 2 * n);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(L, Eigen::ComputeFullU);
    const Eigen::MatrixXd Q = svd.matrixU().leftCols(2 * n - 2);
    const double omega_m = 2.0 * std::numbers::pi / t.mesh_period;
    const long cycles = 3;
    TangentComparison out;
    for (int window = 0; window < 60 && !out.found; ++window) {
      REQUIRE(walker.Run(1, false));
      const Eigen::VectorXd z = walker.state();
      const ContactState state = walker.contact();
      Eigen::MatrixXd tangent = Eigen::MatrixXd::Zero(t.m, Q.cols());
      tangent.topRows(2 * n) = Q;
      probe.AttachTangent(&tangent);
      probe.Restart(z, state);
      REQUIRE(probe.Run(cycles, true));
      probe.AttachTangent(nullptr);
      const SolverSummary& summary = probe.summary();
      if (summary.events < 3 || summary.min_event_rate < 0.3 * t.half_backlash * omega_m) continue;
      out.found = true;
      out.tangent = Q.transpose() * tangent.topRows(2 * n);
      out.finite_difference = Q.transpose() *
                              (4.0 * PairCentralDifference(probe, t, z, state, Q, cycles, 0.5e-6) -
                               PairCentralDifference(probe, t, z, state, Q, cycles, 1e-6)) /
                              3.0;
      // Richardson-extrapolated central differences (truncation O(eps^4), rounding ~1e-16 /
      // eps): 1e-6 of each column for the exact locators (measured <= 3.2e-7). V1 computes a
      // quantised map: each event lands up to one cell D 2^-34 late, a state error up to
      // ~omega D 2^-34 relative (omega the fastest rate of the generator), which the finite
      // difference divides by its relative step 0.5e-6; that is added to V1's bound (3.9e-5
      // here, measured 4.6e-6).
      double quantisation = 0.0;
      if (method == EventMethod::kDyadic) {
        for (int j = 0; j < t.segments(); ++j) {
          const double cell = t.SegmentLength(j) / t.substeps[j] / std::ldexp(1.0, 34);
          for (const SegmentSystem& sys : t.systems[j])
            quantisation = std::max(quantisation, ReferenceFrequency(sys.A, n) * cell / 0.5e-6);
        }
      }
      out.bound = 1e-6 + quantisation;
      std::ostringstream detail;
      detail << "window " << window << ", " << summary.events << " events, quantisation "
             << quantisation;
      out.detail = detail.str();
    }
    return out;
  }

 private:
  ConformanceCaseId id_;
};

// ---------------------------------------------------------------------------------------------
// The train: TrainStepper with TrainStepperOptions::events, events logged by its recorder.

// Removes the free rotation's position drift from [x; x'] (the train recentres it only once per
// common period; r changes no gap and no force).
Eigen::VectorXd ElasticPart(const TrainTables& t, const Eigen::VectorXd& z) {
  Eigen::VectorXd out = z.head(2 * t.n);
  out.head(t.n) -= t.recenter_row.dot(out.head(t.n)) * t.rigid_rotation;
  return out;
}

// The rattler of test_trains.h: input -> layshaft (loaded) -> loose gear g4 under drag, engine
// order 2 at 1500 rad/s^2. Both meshes change contact within the first millisecond.
constexpr double kTrainExcitation = 1500.0;

// The near-grazing case: the rattler without the layshaft load and excitation, every mesh free:
// the loose gear's gap delta_1(t) = a + b t + c t^2 is a parabola whose extremum at t_a lies
// eps = 1e-6 b beyond its wall. The first event is that mesh's impact at |g'| = 2 sqrt(|c| eps),
// ~1e-6 m/s, the near-grazing crossing (a touch would be below the grazing tolerance 1e-9 m/s).
TrainSpec TrainGrazingSpec() {
  TrainSpec spec = RattlerTrain(0.0);
  spec.operating.loads = {{"g4", 0.05}};
  return spec;
}
constexpr int kLooseBody = 2;         // bodies: input, layshaft, then the loose gear g4
constexpr double kTrainDepth = 1e-6;  // eps / b

class TrainCase final : public ConformanceCase {
 public:
  explicit TrainCase(bool grazing)
      : grazing_(grazing), model_(grazing ? TrainGrazingSpec() : RattlerTrain(kTrainExcitation)) {
    const TrainTables& t = model_.tables;
    period_ = t.meshes[0].period;
    if (!grazing_) {
      std::tie(z0_, states0_) = TrainStaticState(t);
      // 2 cycles of the first mesh (7.5 ms, 12 events) for the allocation and tangent runs: rattle
      // amplifies differences about tenfold per ms (train_stepper_test, against CVODE), so longer
      // windows measure the amplification rather than the locators.
      cycles_ = 2;
      // The methods are compared over the first cycle (3.75 ms, 5 events: impacts and separations
      // of the loose gear). V1 places an event only to where the gap's change over its cell is at
      // rounding level (BelowGapRounding: up to 4 GapTolerance / |g'|; here the first event is a
      // slow separation, |g'| = v_typ / 13), and the second cycle amplified that 100-500x: V1
      // against V3 at the last of 12 events was 2.1e-9 h or 6.9e-9 h (bound 5e-9 h) depending only
      // on where V1's sub-step grid put its cells and on the build's rounding (FMA or not), with
      // V1's first-event error 4e-12 h or 7e-11 h. Over the first cycle: <= 5e-11 h either way.
      compare_cycles_ = 1;
      return;
    }
    const int n = t.n;
    REQUIRE(t.loose[kLooseBody]);
    const TrainMeshTable& mt = t.meshes[1];
    const Eigen::VectorXd acc = t.force.cwiseQuotient(t.inertia);
    curvature_ = 0.5 * mt.v.dot(acc);
    REQUIRE(std::abs(curvature_) > 1.0);  // m/s^2: the drag does curve the gap
    // t_a: the middle of the first grid segment longer than 150 us after 200 us.
    TrainGrid grid(t);
    while (grid.start() < 200e-6 || grid.end() - grid.start() < 150e-6) grid.Next();
    const double t_a = 0.5 * (grid.start() + grid.end());
    const double e = mt.error[static_cast<size_t>(grid.segments()[1])];
    depth_ = kTrainDepth * mt.half_backlash;
    // A maximum (c < 0) reaches the drive wall e + b from below, a minimum the back wall e - b.
    const double peak =
        curvature_ < 0.0 ? e + mt.half_backlash + depth_ : e - mt.half_backlash - depth_;
    z0_ = Eigen::VectorXd::Zero(t.m);
    z0_[t.constant_slot()] = 1.0;
    z0_[kLooseBody] = (peak + curvature_ * t_a * t_a) / mt.v[kLooseBody];  // delta(0)
    z0_[n + kLooseBody] = -2.0 * curvature_ * t_a / mt.v[kLooseBody];      // delta'(t_a) = 0
    states0_.assign(t.meshes.size(), ContactState::kFree);
    cycles_ = 2;
    compare_cycles_ = 2;
  }

  const char* name() const override {
    return grazing_ ? "train, near-grazing impact of the loose gear" : "train, loose-gear rattle";
  }
  int positions() const override { return model_.tables.n; }
  double segment_length() const override { return model_.tables.longest_segment; }
  // V2 against V3 measured 1.6e-13 relative: 1e-9 as on the pair. V1 ends a bisection where the
  // gap's change over the cell is at rounding level (TrainStepper::BelowGapRounding), up to
  // ~1e-12 s late here, and the loose gear's impacts amplify it: measured 5e-11 in the
  // velocities of the rattle's first cycle (2.8e-9 over two cycles; 1.3e-10 in the grazing case),
  // bound 1e-8.
  double state_bound(bool with_v1) const override { return with_v1 ? 1e-8 : 1e-9; }

  ConformanceOutcome Run(EventMethod method) const override {
    const TrainTables& t = model_.tables;
    TrainStepperOptions options;
    options.events = method;
    options.jumps = false;  // stepped, as the pair's SolverMethod::kStepped
    // The rattle's one-cycle window: V3 decomposes each tuple at its first entry, else it would
    // take the dense path (V2's) throughout and match V2 bit for bit.
    if (!grazing_) options.tables.decompose_after_visits = 1;
    TrainStepper stepper(t, options, z0_, states0_);
    TrainRecorder recorder(t, 8, 0.0);
    recorder.KeepEvents(4096);
    ConformanceOutcome out;
    for (long k = 1; k <= compare_cycles_; ++k) {
      REQUIRE(stepper.Run(static_cast<double>(k) * period_, &recorder));
      out.cycle_ends.push_back(ElasticPart(t, stepper.state()));
    }
    out.events = recorder.events();
    for (const TrainMeshStatistics& m : recorder.Result().meshes) {
      out.drive_impacts += m.drive_impacts;
      out.back_impacts += m.back_impacts;
      out.separations += m.separations;
      out.grazing += m.grazing;
    }
    REQUIRE(static_cast<long>(out.events.size()) == stepper.summary().events);
    return out;
  }

  void CheckPurpose(const ConformanceOutcome& out) const override {
    if (!grazing_) {
      // The loose gear rattles: impacts and separations on its mesh (the loaded mesh g1-g2 stays
      // in drive contact).
      long impacts = 0, separations = 0;
      for (const TrainEventRecord& e : out.events) {
        if (e.mesh != 1) continue;
        (e.event.to == ContactState::kFree ? separations : impacts) += 1;
      }
      CHECK(impacts > 0);
      CHECK(separations > 0);
      return;
    }
    REQUIRE(!out.events.empty());
    const TrainEventRecord& first = out.events[0];
    CHECK(first.mesh == 1);
    CHECK(first.event.to == (curvature_ < 0.0 ? ContactState::kDrive : ContactState::kBack));
    // |g'| = 2 sqrt(|c| eps) at the root t_a - sqrt(eps / |c|) of the parabola.
    const double rate = 2.0 * std::sqrt(std::abs(curvature_) * depth_);
    CHECK(std::abs(first.event.gap_rate) == Approx(rate).epsilon(1e-3));
  }

  // The train's V1 builds its propagators for each flagged sub-step (train_stepper.h: a train's
  // grid segments have many lengths; V1 is the validation baseline), so it allocates as it steps.
  bool keeps_tables(EventMethod method) const override { return method != EventMethod::kDyadic; }

  AllocationRun WarmRun(EventMethod method, bool with_tangent) const override {
    const TrainTables& t = model_.tables;
    TrainStepperOptions options;
    options.events = method;
    // Each tuple decomposed at its first entry: under the lazy policy a repeated run would
    // decompose tuples the first run entered only once or twice (train_stepper_test).
    options.tables.decompose_after_visits = 1;
    TrainStepper stepper(t, options, z0_, states0_);
    Eigen::MatrixXd V = Eigen::MatrixXd::Zero(t.m, 2 * t.n);
    TrainTangentPropagator tangent(t);
    tangent.Attach(&V);
    if (with_tangent) stepper.AttachTangent(&tangent);
    const double end = static_cast<double>(cycles_) * period_;
    V.topRows(2 * t.n).setIdentity();
    TrainRecorder warm(t, 32, 0.0);
    REQUIRE(stepper.Run(end, &warm));
    stepper.Reset(z0_, states0_);  // the same trajectory again: every tuple is cached
    V.setZero();
    V.topRows(2 * t.n).setIdentity();
    TrainRecorder recorder(t, 32, 0.0);
    AllocationRun out;
    {
      AllocationCounter counter;
      REQUIRE(stepper.Run(end, &recorder));
      out.allocations = counter.count();
    }
    out.events = stepper.summary().events;
    return out;
  }

  TangentComparison CompareTangent(EventMethod method) const override {
    // The window from the static start to 4 ms: impacts and separations on both meshes, within
    // the first input revolution (no recentring). Every elastic coordinate perturbed: 1e-9 rad in
    // the angles (a gap moves by ~3e-11 m, 3e-7 of the backlash: the event sequence stays the
    // same) and 1e-5 rad/s in the speeds (the same gap change over ~3e-6 s).
    const TrainTables& t = model_.tables;
    const int n = t.n, k = 2 * n;
    const double time = 4e-3;
    TrainStepperOptions options;
    options.events = method;
    options.jumps = false;
    Eigen::MatrixXd V = Eigen::MatrixXd::Zero(t.m, k);
    V.topRows(k).setIdentity();
    TrainTangentPropagator tangent(t);
    tangent.Attach(&V);
    TrainStepper stepper(t, options, z0_, states0_);
    stepper.AttachTangent(&tangent);
    REQUIRE(stepper.Run(time));
    const long events = stepper.summary().events;
    TangentComparison out;
    out.found = events >= 4;
    out.tangent = V.topRows(k);
    out.finite_difference.resize(k, k);
    const auto flow = [&](const Eigen::VectorXd& z0) {
      TrainStepper probe(t, options, z0, states0_);
      REQUIRE(probe.Run(time));
      REQUIRE(probe.summary().events == events);  // the same sequence: the flow is smooth here
      return Eigen::VectorXd(probe.state().head(k));
    };
    for (int c = 0; c < k; ++c) {
      const double h = c < n ? 1e-9 : 1e-5;
      Eigen::VectorXd d[2];
      for (int level = 0; level < 2; ++level) {
        const double step = h / (1 << level);
        Eigen::VectorXd plus = z0_, minus = z0_;
        plus[c] += step;
        minus[c] -= step;
        d[level] = (flow(plus) - flow(minus)) / (2.0 * step);
      }
      out.finite_difference.col(c) = (4.0 * d[1] - d[0]) / 3.0;
    }
    // Richardson-extrapolated central differences: truncation O(h^4), rounding ~eps |z| / h
    // (|z| ~ 4e-3 rad, h >= 5e-10: ~2e-9 of a position column, more in the small columns of the
    // speeds); 2e-6 of each column for the exact methods (measured <= 6.3e-7, on the loose gear's
    // speed). V1's quantised map adds, as on the pair, the state error of an event one cell
    // d 2^-34 late, rho(A) d 2^-34 <= 2^-35 relative (rho(A) d <= 1/2 for every sub-step), over
    // the relative step 5e-10 / |x| (2.3e-4 here), 4 of them for the window's events (measured
    // 2.1e-4 on the loose gear's speed, <= 8.4e-6 on the other columns).
    double quantisation = 0.0;
    if (method == EventMethod::kDyadic) {
      const double relative_step = 0.5e-9 / z0_.head(n).norm();
      quantisation = std::ldexp(1.0, -35) / relative_step;
    }
    out.bound = 2e-6 + 4.0 * quantisation;
    std::ostringstream detail;
    detail << events << " events, " << tangent.saltations() << " saltations, quantisation "
           << quantisation;
    out.detail = detail.str();
    return out;
  }

 private:
  bool grazing_;
  TrainModel model_;
  double period_ = 0.0;      // s: a cycle of the first mesh
  long cycles_ = 0;          // the allocation and tangent runs
  long compare_cycles_ = 0;  // Run(): the methods' comparison
  Eigen::VectorXd z0_;
  std::vector<ContactState> states0_;
  double curvature_ = 0.0, depth_ = 0.0;  // the grazing case's c (m/s^2) and eps (m)
};

}  // namespace

const SolverSetup& PairSetup(ConformanceCaseId id) {
  // Each built on its own first use (see GetConformanceCase).
  switch (id) {
    case ConformanceCaseId::kPairTier1: {
      static const SolverSetup tier1(IdleRattleSpec(), Tier::kTier1);
      return tier1;
    }
    case ConformanceCaseId::kPairTier1Runout: {
      static const SolverSetup tier1_runout(IdleRattleRunoutSpec(), Tier::kTier1);
      return tier1_runout;
    }
    case ConformanceCaseId::kPairTier3: {
      static const SolverSetup tier3(IdleRattleSpec(), Tier::kTier3);
      return tier3;
    }
    case ConformanceCaseId::kPairTier5: {
      static const SolverSetup tier5(FlexibleRattleSpec(), Tier::kTier5);
      return tier5;
    }
    default:
      break;
  }
  static const SolverSetup grazing(GrazingSpec(), Tier::kTier1);
  return grazing;
}

// Rattle cases start from a common state in developed rattle: 30 cycles of V2 from the static
// equilibrium (the first impacts come after ~10 cycles). Each comparison then covers 10 cycles.
PairStart PairStartFor(ConformanceCaseId id) {
  const SolverSetup& s = PairSetup(id);
  if (id != ConformanceCaseId::kPairGrazing) {
    const auto [z0, state0] = StaticInitialState(s.tables);
    SolverOptions settle;
    settle.method = SolverMethod::kStepped;
    settle.events = EventMethod::kTaylor;
    settle.record_trajectory = false;
    ExactStepper stepper(s.tables, settle, z0, state0, 0, 0);
    REQUIRE(stepper.Run(30, false));
    return {stepper.state(), stepper.contact(), 10L};
  }
  const double a = PairGrazingAcceleration(s), b = s.tables.half_backlash;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(s.tables.m);
  z[2 * s.tables.n] = 1.0;
  // delta' = r_b1 theta1' (theta2' = 0).
  z[s.tables.n] =
      -std::sqrt(2.0 * a * b * (1.0 + kPairGrazingDepth)) / s.model.geometry.pinion.base;
  return {z, ContactState::kFree, 4L};
}

PairRun RunPair(EventMethod method, ConformanceCaseId id, double carry_max_error) {
  const SolverSetup& s = PairSetup(id);
  const PairStart start = PairStartFor(id);
  SolverOptions opt;
  opt.method = SolverMethod::kStepped;
  opt.events = method;
  opt.carry_max_error = carry_max_error;
  opt.record_trajectory = false;
  ExactStepper stepper(s.tables, opt, start.z, start.state, 0, 4096);
  PairRun out;
  for (long k = 0; k < start.cycles; ++k) {
    REQUIRE(stepper.Run(1, true));
    out.cycle_ends.push_back(stepper.state());
  }
  out.events = stepper.trajectory().events;
  out.summary = stepper.summary();
  return out;
}

const ConformanceCase& GetConformanceCase(ConformanceCaseId id) {
  // Each built on its own first use: a test of one case does not pay for the others (the tier-5
  // reduction is seconds in the instrumented build).
  switch (id) {
    case ConformanceCaseId::kPairTier1: {
      static const PairCase tier1(ConformanceCaseId::kPairTier1);
      return tier1;
    }
    case ConformanceCaseId::kPairTier1Runout: {
      static const PairCase tier1_runout(ConformanceCaseId::kPairTier1Runout);
      return tier1_runout;
    }
    case ConformanceCaseId::kPairTier3: {
      static const PairCase tier3(ConformanceCaseId::kPairTier3);
      return tier3;
    }
    case ConformanceCaseId::kPairTier5: {
      static const PairCase tier5(ConformanceCaseId::kPairTier5);
      return tier5;
    }
    case ConformanceCaseId::kPairGrazing: {
      static const PairCase grazing(ConformanceCaseId::kPairGrazing);
      return grazing;
    }
    case ConformanceCaseId::kTrainRattle: {
      static const TrainCase rattle(false);
      return rattle;
    }
    case ConformanceCaseId::kTrainGrazing:
      break;
  }
  static const TrainCase train_grazing(true);
  return train_grazing;
}

}  // namespace gearnvh::testing
