// A gear train built for the solver tests: spec, model and tier-1 tables in one object.
#pragma once

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "gearnvh/solver/train_tables.h"
#include "model/test_specs.h"

namespace gearnvh::testing {

struct TrainModel {
  TrainSpec spec;
  GearTrain train;
  TrainTables tables;
  explicit TrainModel(TrainSpec s, TrainTableOptions options = {})
      : spec(std::move(s)),
        train(BuildGearTrain(spec)),
        tables(BuildTrainTables(spec, train, options)) {}
};

// The path and rule ValidateTrainSpec refuses `spec` with; {"accepted", ""} when it does not.
inline std::pair<std::string, std::string> ValidationError(const TrainSpec& spec) {
  try {
    ValidateTrainSpec(spec);
  } catch (const InputError& e) {
    return {e.path(), e.rule()};
  }
  return {"accepted", ""};
}

// The transmission error of one mesh in the stepper's current state.
inline double MeshTe(const TrainTables& t, const TrainStepper& s, int mesh) {
  return t.meshes[static_cast<size_t>(mesh)].v.dot(s.state().head(t.n));
}

// The loaded, dynamic pair of the one-mesh-train tests: 20/30 teeth, 1500 rpm (mesh at 500 Hz),
// 100 N m, no engine orders; and its recorded run: 120 cycles (two revolutions of the wheel,
// three of the pinion), 8 samples per cycle, no transient.
inline GearboxSpec LoadedTestPair() {
  GearboxSpec pair = StandardPair(20, 30, 3e-3, 20e-3);
  pair.operating.speed = 1500.0 * 2.0 * std::numbers::pi / 60.0;
  pair.operating.torque = 100.0;
  pair.operating.excitation.clear();
  return pair;
}

inline SolverOptions LoadedTestPairRun() {
  SolverOptions options;
  options.cycles = 120;
  options.transient_cycles = 0;
  options.samples_per_cycle = 8;
  return options;
}

// The linear periodic steady state of a train held in drive contact on every mesh, the reference
// of the permanent-contact tests: the grid segments of one common period, their propagators
// expm(A h) R from dense Pade of an independent assembly (train_reference.h; R sets the engine
// orders' states to their values at the segment's start, as the stepper does), the period map P,
// and its fixed
// point by a complete-orthogonal solve of (I - P) y = p on the full elastic block (the free
// rotation's position is its one null direction and moves no TE).
struct LinearPeriodicState {
  struct Piece {
    double start = 0.0, h = 0.0;
    Eigen::MatrixXd map;  // expm(A h) R
  };
  std::vector<Piece> pieces;  // one common period from t = 0
  Eigen::MatrixXd period_map;
  Eigen::VectorXd z;  // the orbit's state at a period start (constant slot 1)
};

inline LinearPeriodicState DriveContactPeriodicState(const TrainTables& t) {
  const int n = t.n, m = t.m;
  const std::vector<ContactState> drive(t.meshes.size(), ContactState::kDrive);
  LinearPeriodicState out;
  out.period_map = Eigen::MatrixXd::Identity(m, m);
  for (TrainGrid grid(t); grid.start() < t.common_period * (1.0 - 1e-12); grid.Next()) {
    const double h = grid.end() - grid.start();
    // R sets the orders' states to their values at the segment's start (times the constant).
    Eigen::MatrixXd R = Eigen::MatrixXd::Identity(m, m);
    Eigen::VectorXd inputs = Eigen::VectorXd::Zero(m);
    t.SetExcitation(grid.start(), inputs);
    for (int q = 0; q < t.excitation_states(); ++q) {
      const int slot = t.ExcitationSlot(0) + q;
      R(slot, slot) = 0.0;
      R(slot, t.constant_slot()) = inputs[slot];
    }
    const Eigen::MatrixXd A = AssembleTrainGenerator(t, grid.segments(), drive);
    out.pieces.push_back({grid.start(), h, BalancedExpm(A, h, n, ReferenceFrequency(A, n)) * R});
    out.period_map = out.pieces.back().map * out.period_map;
  }
  const Eigen::MatrixXd& P = out.period_map;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(2 * n, 2 * n);
  out.z = Eigen::VectorXd::Zero(m);
  out.z.head(2 * n) = (I - P.topLeftCorner(2 * n, 2 * n))
                          .completeOrthogonalDecomposition()
                          .solve(P.block(0, t.constant_slot(), 2 * n, 1));
  out.z[t.constant_slot()] = 1.0;
  return out;
}

// A run from the static state to `end` (s) with certified jumps on or off, recorded (32 samples
// per cycle) from `record_start`: its summary, statistics and final state.
struct RecordedTrainRun {
  TrainStepperSummary summary;
  TrainStatistics stats;
  Eigen::VectorXd state;
};

inline RecordedTrainRun RunTrainFromStatic(const TrainTables& t, bool jumps, double record_start,
                                           double end) {
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepperOptions options;
  options.jumps = jumps;
  TrainStepper stepper(t, options, z0, states0);
  TrainRecorder recorder(t, 32, record_start);
  REQUIRE(stepper.Run(end, &recorder));
  return {stepper.summary(), recorder.Result(), stepper.state()};
}

// V3 (with `v3_options`) and V2 from the static state against the CVODE reference (rtol 1e-13)
// up to `end` (s): every gear mesh's TE at 16 samples per cycle of the first mesh, the largest
// differences and the largest |TE| of the reference.
struct ReferenceAgreement {
  double worst_reference = 0.0, worst_v2 = 0.0, scale = 0.0;  // m
  size_t reference_events = 0;
  long v3_events = 0, v2_events = 0;
  TrainStepperSummary v3_summary;  // its cache: decompositions, dense pieces
};

inline ReferenceAgreement AgreeWithReference(const TrainTables& t, double end,
                                             const TrainStepperOptions& v3_options = {}) {
  const auto [z0, states0] = TrainStaticState(t);
  TrainReferenceOptions ro;
  ro.end_time = end;
  ro.rtol = 1e-13;
  ro.sample_interval = t.meshes[0].period / 16.0;
  const TrainReferenceResult ref = SimulateTrainReference(t, z0, states0, ro);
  REQUIRE(ref.success);
  TrainStepperOptions v2_options;
  v2_options.events = EventMethod::kTaylor;
  TrainStepper v3(t, v3_options, z0, states0), v2(t, v2_options, z0, states0);
  ReferenceAgreement out;
  out.reference_events = ref.events.size();
  for (size_t k = 0; k < ref.sample_times.size(); ++k) {
    REQUIRE(v3.Run(ref.sample_times[k]));
    REQUIRE(v2.Run(ref.sample_times[k]));
    for (size_t i = 0; i < static_cast<size_t>(t.gear_meshes); ++i) {  // TE in m (a stage: rad)
      const double te = t.meshes[i].v.dot(v3.state().head(t.n));
      const double r = ref.te(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i));
      out.scale = std::max(out.scale, std::abs(r));
      out.worst_reference = std::max(out.worst_reference, std::abs(te - r));
      out.worst_v2 = std::max(out.worst_v2, std::abs(te - t.meshes[i].v.dot(v2.state().head(t.n))));
    }
  }
  out.v3_events = v3.summary().events;
  out.v3_summary = v3.summary();
  out.v2_events = v2.summary().events;
  return out;
}

// A rattle over a few impacts against CVODE (rtol 1e-13): V3, V2 and the reference see the same
// events, at least two, and V3's TE is within 1e-8 of the largest |TE| (the impacts' amplification,
// ~10^3 per cycle, leaves CVODE accurate to ~1e-10 over two cycles).
inline void CheckRattleFollowsReference(const ReferenceAgreement& a) {
  INFO("V3 vs CVODE: " << a.worst_reference / a.scale << " of the TE, " << a.v3_events
                       << " events");
  CHECK(a.v3_events >= 2);
  CHECK(static_cast<long>(a.reference_events) == a.v3_events);
  CHECK(a.v2_events == a.v3_events);
  CHECK(a.worst_reference <= 1e-8 * a.scale);
}

// A train in permanent contact run from its static state to 22 common periods, recording the last
// two, with certified jumps and without: the jumps were made (18 periods or more), no event, and
// every mesh's TE RMS agrees to 1e-10 of its p-p (the same orbit to rounding). Returns {stepped,
// jumped}.
inline std::pair<RecordedTrainRun, RecordedTrainRun> CheckJumpsMatchStepping(const TrainTables& t) {
  REQUIRE(t.common_period > 0.0);
  const double start = 20.0 * t.common_period, end = start + 2.0 * t.common_period;
  RecordedTrainRun stepped = RunTrainFromStatic(t, false, start, end);
  RecordedTrainRun jumped = RunTrainFromStatic(t, true, start, end);
  REQUIRE(jumped.summary.jumps == TrainStepperSummary::Jumps::kJumped);
  CHECK(jumped.summary.jumped_periods >= 18);
  CHECK(stepped.summary.events == 0);
  CHECK(jumped.summary.events == 0);
  for (size_t i = 0; i < stepped.stats.meshes.size(); ++i) {
    const double pp = stepped.stats.meshes[i].te_peak_to_peak;
    CHECK(pp > 0.0);
    CHECK(std::abs(stepped.stats.meshes[i].te_rms - jumped.stats.meshes[i].te_rms) <= 1e-10 * pp);
  }
  return {std::move(stepped), std::move(jumped)};
}

}  // namespace gearnvh::testing
