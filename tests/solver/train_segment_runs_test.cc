// Segment-run fusion on gear trains (solver/train_segment_runs.h, TrainStepperOptions::
// fusion_levels): fused runs equal V3 stepping on a loaded reducer with and without a strong
// engine order, a rattling train's certificate refuses what it must, recording is untouched, and
// a fused run does not allocate once its tables are held.
#include "gearnvh/solver/train_segment_runs.h"

#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>

#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/train_cycle_map.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"
#include "support/allocation_counter.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;

struct Outcome {
  TrainStepperSummary summary;
  Eigen::VectorXd state;
  std::vector<ContactState> states;
};

// From the static state to `end` (s), no jumps (they would skip what fusion is compared on),
// fusion with `levels` (0: stepped).
Outcome RunTrain(const TrainTables& t, int levels, double end) {
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepperOptions options;
  options.jumps = false;
  options.fusion_levels = levels;
  options.fusion_min_periods = 1;  // these runs are a few periods long
  TrainStepper stepper(t, options, z0, states0);
  REQUIRE(stepper.Run(end));
  return {stepper.summary(), stepper.state(), stepper.states()};
}

// The largest difference of every mesh's TE (v^T x) over the TE scale, and of the elastic
// velocities over their norm (the free rotation's removed: nothing damps its rounding).
struct Difference {
  double te = 0.0, velocity = 0.0;
};
Difference Compare(const TrainTables& t, const Outcome& a, const Outcome& b) {
  Difference d;
  const int n = t.n;
  double scale = 0.0;
  for (const TrainMeshTable& mt : t.meshes)
    scale = std::max(scale, std::abs(mt.v.dot(a.state.head(n))));
  for (const TrainMeshTable& mt : t.meshes) {
    d.te = std::max(d.te, std::abs(mt.v.dot(a.state.head(n) - b.state.head(n))) / scale);
    d.velocity =
        std::max(d.velocity, std::abs(mt.v.dot(a.state.segment(n, n) - b.state.segment(n, n))) /
                                 (mt.v.norm() * a.state.segment(n, n).norm() + 1e-300));
  }
  return d;
}

// Stepped and fused from the static state to `end`, compared; `what` describes the comparison.
struct Comparison {
  Outcome stepped, fused;
  Difference d;
  std::string what;
};
Comparison FuseAndStep(const TrainTables& t, double end) {
  Comparison c{RunTrain(t, 0, end), RunTrain(t, 5, end), {}, {}};
  c.d = Compare(t, c.stepped, c.fused);
  const TrainStepperSummary& f = c.fused.summary;
  c.what = fmt::format(
      "fused {} of {} grid segments in {} runs, {} refusals; TE {:.3e}, velocity {:.3e}",
      f.fused_grid_segments, f.grid_segments, f.fused_runs, f.fusion_refusals, c.d.te,
      c.d.velocity);
  return c;
}

TEST_CASE("train segment runs: a loaded two-stage reducer fused equals it stepped",
          "[solver][train]") {
  // Meshes in permanent drive contact, a small engine order (the reducer of the jump tests).
  const Model s(testing::TwoStageTrain(300.0, 100.0, 300.0));
  const TrainTables& t = s.tables;
  REQUIRE(t.common_period > 0.0);
  const Comparison c = FuseAndStep(t, 3.0 * t.common_period);
  const Outcome &stepped = c.stepped, &fused = c.fused;
  INFO(c.what);
  CHECK(stepped.summary.fused_grid_segments == 0);
  CHECK(stepped.summary.events == 0);
  CHECK(fused.summary.events == 0);
  CHECK(fused.summary.grid_segments == stepped.summary.grid_segments);
  // Most of the run is fused once the start's transient has decayed below the margins.
  CHECK(fused.summary.fused_grid_segments > stepped.summary.grid_segments / 4);
  CHECK(fused.summary.fusion_tables > 0);
  CHECK(fused.summary.fusion_bytes > 0);
  const Difference& d = c.d;
  // Tolerance: both sides apply the same propagators, the fused one as products of up to 32
  // balanced-Pade expm against one closed-form piece per grid segment; each differs from the
  // exact map by ~cond(S) eps relative, summed over ~10^3 grid segments and damped. Measured
  // 5.6e-13 (AVX-512 FMA build) and 1.1e-12 (a build without -march=native, the sanitizer's);
  // 1e-11 leaves room for other CPUs' rounding and is far below a modelling difference (a wrong
  // input or a skipped grid segment moves the TE by > 1e-6).
  CHECK(d.te <= 1e-11);
  CHECK(d.velocity <= 1e-10);
  CHECK(fused.states == stepped.states);
}

TEST_CASE("train segment runs: a strong engine order, fused and stepped, recorded alike",
          "[solver][train]") {
  const Model s(testing::TwoStageTrain(300.0, 3000.0, 600.0));
  const TrainTables& t = s.tables;
  REQUIRE(t.common_period > 0.0);
  const double end = 4.0 * t.common_period;
  const Comparison c = FuseAndStep(t, end);
  INFO(c.what);
  CHECK(c.fused.summary.fused_grid_segments > 0);
  CHECK(c.fused.summary.events == c.stepped.summary.events);
  const Difference& d = c.d;
  // The strong order's pieces are closer to the condition limit: measured 7.6e-12, within the
  // spread of V3 and V2 stepping (see "every run certified under a strong engine order"); 3e-11.
  CHECK(d.te <= 3e-11);
  CHECK(d.velocity <= 1e-10);
  // Recorded from the third period: fusion only before it, the recorded window is stepped.
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepperOptions on, off;
  on.jumps = off.jumps = false;
  on.fusion_min_periods = 1;
  off.fusion_levels = 0;
  TrainStepper a(t, off, z0, states0), b(t, on, z0, states0);
  TrainRecorder ra(t, 32, 2.0 * t.common_period), rb(t, 32, 2.0 * t.common_period);
  REQUIRE(a.Run(end, &ra));
  REQUIRE(b.Run(end, &rb));
  CHECK(b.summary().fused_grid_segments > 0);
  const TrainStatistics sa = ra.Result(), sb = rb.Result();
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    const double pp = sa.meshes[i].te_peak_to_peak;
    CHECK(pp > 0.0);
    // The recorded window starts from states equal to 3e-11 of the TE (above).
    CHECK(std::abs(sa.meshes[i].te_rms - sb.meshes[i].te_rms) <= 1e-9 * pp);
    CHECK(std::abs(sa.meshes[i].te_peak_to_peak - pp) <= 1e-9 * pp);
  }
}

// Every run certified along a stepped walk from the static state over `segments` grid segments,
// checked against the same grid segments stepped (CheckSegmentRuns, train_segment_runs.h): no
// event (or grazing) may occur in them, and the fused state must equal the stepped one.
SegmentRunCheck CheckEveryRun(const TrainTables& t, long segments,
                              EventMethod method = EventMethod::kSpectral) {
  const auto [z0, states0] = TrainStaticState(t);
  const SegmentRunCheck check = CheckSegmentRuns(t, t, z0, states0, segments, method);
  REQUIRE_FALSE(check.stopped);
  return check;
}

TEST_CASE("train segment runs: every run certified on a rattling train steps without an event",
          "[solver][train]") {
  // A loose gear rattles: its mesh switches every few grid segments. (Fused and stepped runs of
  // a rattle cannot be compared end to end: the rattle amplifies any rounding difference tenfold
  // per millisecond, measured here, so each certified run is checked from the stepped state.)
  const Model s(testing::RattlerTrain(1500.0));
  const TrainTables& t = s.tables;
  REQUIRE(t.common_period > 0.0);
  const SegmentRunCheck check = CheckEveryRun(t, 3000);
  INFO("events " << check.events << "; runs " << check.runs << " (" << check.fused
                 << " grid segments); refusals " << check.refusals << "; TE " << check.worst_te);
  REQUIRE(check.events > 100);
  CHECK(check.runs > 0);
  CHECK(check.refusals > 0);
  CHECK(check.runs_with_event == 0);
  // Products of up to 32 propagators against as many closed-form pieces from one state:
  // measured 1.1e-12 of the TE; 3e-11 as under the strong engine order below.
  CHECK(check.worst_te <= 3e-11);
}

TEST_CASE(
    "train segment runs: every run certified under a strong engine order steps without an "
    "event",
    "[solver][train]") {
  const Model s(testing::TwoStageTrain(100.0, 20000.0, 600.0));
  const TrainTables& t = s.tables;
  REQUIRE(t.common_period > 0.0);
  const SegmentRunCheck check = CheckEveryRun(t, 3000);
  const SegmentRunCheck taylor = CheckEveryRun(t, 3000, EventMethod::kTaylor);
  INFO("events " << check.events << "; runs " << check.runs << " (" << check.fused
                 << " grid segments); refusals " << check.refusals << "; TE " << check.worst_te
                 << "; against V2 " << taylor.worst_te);
  CHECK(check.runs > 0);
  CHECK(check.runs_with_event == 0);
  CHECK(taylor.runs > 0);
  CHECK(taylor.runs_with_event == 0);
  // Tolerance: each V3 piece carries up to cond(S) eps of the state (cond(S) <= max_condition,
  // 1e6), the V2 pieces their Taylor rounding; measured 1.3e-11 (fused against V3) and 4.9e-12
  // (against V2): the fused run lies within the two exact steppers' own spread. 3e-11 keeps
  // that with room for other compilers; a wrong input column or length moves the TE by > 1e-6.
  CHECK(check.worst_te <= 3e-11);
  CHECK(taylor.worst_te <= 3e-11);
}

TEST_CASE("train segment runs: a fused run does not allocate once its tables are held",
          "[solver][train][allocation]") {
  const Model s(testing::TwoStageTrain(300.0, 100.0, 300.0));
  const TrainTables& t = s.tables;
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepperOptions options;
  options.jumps = false;
  options.fusion_min_periods = 1;
  // Every tuple decomposed at its first entry: a tuple entered once or twice by the first run
  // would be decomposed (allocating) in the counted one (which runs depend on rounding: a build
  // without FMA certifies other runs).
  options.tables.decompose_after_visits = 1;
  TrainStepper stepper(t, options, z0, states0);
  const double end = 2.0 * t.common_period;
  REQUIRE(stepper.Run(end));  // builds the tuples and the runs
  stepper.Reset(z0, states0);
  testing::AllocationCounter counter;
  REQUIRE(stepper.Run(end));
  CHECK(counter.count() == 0);
  CHECK(stepper.summary().fused_grid_segments > 0);
}

TEST_CASE("train segment runs: the options' rules", "[solver][train]") {
  TrainStepperOptions options;
  options.fusion_levels = 17;
  CHECK_THROWS_AS(options.Validate(), InputError);
  options.fusion_levels = -1;
  CHECK_THROWS_AS(options.Validate(), InputError);
  options.fusion_levels = 0;
  options.fusion_limit_bytes = 0;
  CHECK_THROWS_AS(options.Validate(), InputError);
  options.fusion_limit_bytes = 1;
  options.fusion_min_periods = 0;
  CHECK_THROWS_AS(options.Validate(), InputError);
}

}  // namespace
}  // namespace gearnvh
