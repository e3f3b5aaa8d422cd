// Time histories of a gear train (TrainRunOptions::histories, analysis/train_operating_point.h):
// against the pair's own recording of the same gearbox (an independent solver and recorder), and
// against the train's exact statistics and its event log (two other recording paths).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "config/gearbox_loader.h"
#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/order_tracks.h"
#include "gearnvh/analysis/speed_sweep.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/analysis/train_sweep.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/reduction/reduced_model.h"
#include "loose_gear_train_yaml.h"
#include "solver/train_model.h"
#include "uff_export.h"

namespace gearnvh {
namespace {

double MaxAbs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

TEST_CASE("time histories: a one-mesh train's TE, force and spectrum are the pair's",
          "[analysis][train][histories]") {
  // The loaded pair of the train solver tests (1500 rpm, 100 N m, mesh at 500 Hz) with runout on
  // both gears, so the force and the spectrum carry shaft orders. The common period holds whole
  // revolutions of both gears, lcm(20, 30) = 60 mesh cycles: 120 recorded cycles are two periods
  // for the pair (no rounding of its cycles) and two common periods for the train.
  GearboxSpec pair = testing::LoadedTestPair();
  pair.pinion.runout = Runout{4e-6, 0.3};
  pair.wheel.runout = Runout{2e-6, -0.8};
  const long cycles = 120, transient = 60;
  const int per_cycle = 8;
  SolverOptions solver;
  solver.cycles = cycles;
  solver.transient_cycles = transient;
  solver.samples_per_cycle = per_cycle;
  solver.method = SolverMethod::kStepped;
  const ComponentModel model = BuildComponentModel(pair);
  const OperatingPointAnalysis op = AnalyseOperatingPoint(pair, model, Tier::kTier1, solver);
  REQUIRE(op.result.summary.status == SolverStatus::kSuccess);
  REQUIRE(op.solver.cycles == cycles);

  TrainRunOptions run;
  run.cycles = cycles;
  run.transient = transient;
  run.samples_per_cycle = per_cycle;
  run.histories = true;
  const TrainSpec train_spec = TrainOf(pair);
  const TrainOperatingPoint top = RunTrainOperatingPoint(train_spec, run);
  REQUIRE(top.ok());
  const TrainHistories& h = top.histories;
  const std::vector<TrajectorySample>& samples = op.result.trajectory.samples;
  REQUIRE(samples.size() == static_cast<size_t>(cycles * per_cycle));
  REQUIRE(h.te.size() == 1);
  REQUIRE(h.te[0].size() == samples.size());
  REQUIRE(h.force[0].size() == samples.size());
  CHECK_FALSE(h.truncated);

  // Two implementations of one model (ExactStepper and TrainStepper, ExactRecorder and
  // TrainRecorder): their rounding (~1e-12 of the TE and force) sits far below 1e-9 of the
  // largest value, and far above it anything a wrong sample time, flank, wall or damping term
  // would make (the runout alone moves the force by ~1e-2 of its mean).
  const double te_scale = MaxAbs(h.te[0]), force_scale = MaxAbs(h.force[0]);
  REQUIRE(force_scale > 0.0);
  double te_worst = 0.0, force_worst = 0.0, time_worst = 0.0, force_swing = 0.0;
  for (size_t k = 0; k < samples.size(); ++k) {
    const double time = h.start + static_cast<double>(k) * h.dt;
    time_worst = std::max(time_worst, std::abs(time - samples[k].time));
    te_worst = std::max(te_worst, std::abs(h.te[0][k] - samples[k].te));
    force_worst = std::max(force_worst, std::abs(h.force[0][k] - samples[k].mesh_force));
    force_swing = std::max(force_swing, std::abs(h.force[0][k] - h.force[0][0]));
    REQUIRE(h.contact[0][k] == samples[k].state);
  }
  INFO("TE " << te_worst << " m of " << te_scale << ", force " << force_worst << " N of "
             << force_scale << ", time " << time_worst << " s");
  CHECK(force_swing > 1e-3 * force_scale);  // the force varies: the comparison is not vacuous
  CHECK(time_worst <= 1e-12 * h.start);
  CHECK(te_worst <= 1e-9 * te_scale);
  CHECK(force_worst <= 1e-9 * force_scale);

  // The TE spectrum over the same window (two common periods = the pair's 120 cycles).
  REQUIRE(top.sidebands.size() == 1);
  REQUIRE(top.sidebands[0].window_cycles == op.sideband_window);
  const AmplitudeSpectrum& ts = top.sidebands[0].spectrum;
  REQUIRE_FALSE(ts.amplitude.empty());
  REQUIRE(ts.amplitude.size() == op.spectrum.amplitude.size());
  CHECK(ts.bin_hz == Approx(op.spectrum.bin_hz).epsilon(1e-12));
  const double spectrum_scale = MaxAbs(op.spectrum.amplitude);
  double spectrum_worst = 0.0;
  for (size_t b = 0; b < ts.amplitude.size(); ++b)
    spectrum_worst = std::max(spectrum_worst, std::abs(ts.amplitude[b] - op.spectrum.amplitude[b]));
  CHECK(spectrum_worst <= 1e-9 * spectrum_scale);

  // The UFF functions: the same three, in the same order and units; the train names its mesh.
  const std::vector<app::UffFunction> pair_uff = app::OperatingPointUff(pair, op);
  const std::vector<app::UffFunction> train_uff = app::TrainOperatingPointUff(train_spec, top);
  REQUIRE(pair_uff.size() == 3);
  REQUIRE(train_uff.size() == 3);
  for (size_t f = 0; f < 3; ++f) {
    INFO(train_uff[f].id1);
    CHECK(train_uff[f].id1 == pair_uff[f].id1 + ", mesh " + top.tables.meshes[0].name);
    CHECK(train_uff[f].function_type == pair_uff[f].function_type);
    CHECK(train_uff[f].response_node == 1);
    CHECK(train_uff[f].ordinate.units == pair_uff[f].ordinate.units);
    CHECK(train_uff[f].dx == Approx(pair_uff[f].dx).epsilon(1e-12));
    REQUIRE(train_uff[f].values.size() == pair_uff[f].values.size());
  }
}

TEST_CASE("time histories: a rattling train's samples agree with its exact statistics and events",
          "[analysis][train][histories]") {
  // The loose-gear train rattles from the first cycle: every mesh opens and closes many times.
  const TrainSpec spec = config::LoadAnyGearboxFromString(testing::kLooseGearTrainYaml).train;
  TrainRunOptions run;
  run.cycles = 300;
  run.transient = 50;
  run.histories = true;
  const TrainOperatingPoint op = RunTrainOperatingPoint(spec, run);
  REQUIRE(op.ok());
  const TrainHistories& h = op.histories;
  const size_t meshes = op.tables.meshes.size();
  REQUIRE(h.te.size() == meshes);
  const size_t n = h.te[0].size();
  REQUIRE(static_cast<long>(n) == op.stats.samples);
  CHECK_FALSE(h.events_truncated);
  long rattling_meshes = 0;
  for (size_t i = 0; i < meshes; ++i) {
    const TrainMeshStatistics& s = op.stats.meshes[i];
    INFO("mesh " << s.name);
    REQUIRE(h.force[i].size() == n);
    REQUIRE(h.contact[i].size() == n);
    if (s.separations > 0) ++rattling_meshes;
    // A free mesh carries no force; the samples lie within the exact extrema (the statistics
    // certify the maximum between samples; 1e-12 of it is rounding).
    long free = 0;
    double te_low = INFINITY, te_high = -INFINITY;
    for (size_t k = 0; k < n; ++k) {
      if (h.contact[i][k] == ContactState::kFree) {
        ++free;
        REQUIRE(h.force[i][k] == 0.0);
      }
      CHECK(h.force[i][k] <= s.force_max + 1e-12 * std::abs(s.force_max));
      te_low = std::min(te_low, h.te[i][k]);
      te_high = std::max(te_high, h.te[i][k]);
    }
    CHECK(te_high - te_low <= s.te_peak_to_peak * (1.0 + 1e-12));
    // The free samples' share is the exact free-time fraction up to one sample interval at each
    // end of each free interval (at most separations + 1 of them: 2 (s + 1)) and one at the
    // record's end.
    const double bound = static_cast<double>(2 * s.separations + 3) / static_cast<double>(n);
    CHECK(std::abs(static_cast<double>(free) / static_cast<double>(n) - s.free_time_fraction) <=
          bound);
    // The event log against the samples: between two samples the contact changes exactly as the
    // mesh's events in between say (none: unchanged; else the last event's state), and the log
    // holds every impact and separation the statistics count. A sample on a piece's end is the
    // next piece's (the recorder's rule, 1e-9 of a sample interval): an event at a grid
    // segment's start (a wall that moved past the state) is at the sample's time up to rounding
    // (1e-16 s seen) and already shows in it.
    std::vector<const TrainEventRecord*> events;
    for (const TrainEventRecord& e : h.events) {
      if (e.mesh == static_cast<int>(i)) events.push_back(&e);
    }
    CHECK(static_cast<long>(events.size()) == s.drive_impacts + s.back_impacts + s.separations);
    size_t next = 0;
    while (next < events.size() && events[next]->event.time <= h.start + 1e-9 * h.dt) ++next;
    long mismatched = 0;
    for (size_t k = 0; k + 1 < n; ++k) {
      const double t1 = h.start + static_cast<double>(k + 1) * h.dt;
      ContactState expected = h.contact[i][k];
      while (next < events.size() && events[next]->event.time <= t1 + 1e-9 * h.dt) {
        expected = events[next]->event.to;
        ++next;
      }
      if (h.contact[i][k + 1] != expected) ++mismatched;
    }
    CHECK(mismatched == 0);
  }
  CHECK(rattling_meshes >= 1);  // the checks above saw contact changes
}

TEST_CASE("sweep waterfall: a one-mesh train's waterfall and order tracks are the pair's",
          "[analysis][train][histories]") {
  // The pair's sweep (pinion orders) and the one-mesh train's (input-shaft orders: the same shaft)
  // take the spectrum of the same last 32 mesh cycles, 32 samples per cycle, at each of 4 speeds.
  // The pinion's runout is a line at order 1 at every speed (the pair's sweep ran one model built
  // at the file's speed and kept its runout at that speed's frequency: at 100 rad/s the line sat
  // at order 1.57 until the tables took the errors at the speed they run).
  GearboxSpec pair = testing::LoadedTestPair();
  pair.pinion.runout = Runout{4e-6, 0.3};
  pair.analysis.speed_sweep = SweepRange{100.0, 200.0, 4};
  const ComponentModel model = BuildComponentModel(pair);
  const ReducedModel reduced = ReduceModel(model, Tier::kTier1);
  SpeedSweepOptions pair_options;
  pair_options.cycles = 64;
  pair_options.transient_cycles = 16;
  pair_options.waterfall_cycles = 32;
  pair_options.method = LadderMethod::kV3;
  pair_options.threads = 1;
  const SpeedSweepResult pair_sweep = RunSpeedSweep(pair, model, reduced, pair_options);
  TrainSweepOptions train_options;
  train_options.cycles = 64;
  train_options.transient = 16;
  train_options.waterfall_cycles = 32;
  train_options.threads = 1;
  const TrainSweepResult train_sweep = RunTrainSweep(TrainOf(pair), train_options);
  REQUIRE(train_sweep.failed() == 0);
  REQUIRE(train_sweep.mesh_orders == std::vector<double>{20.0});
  CHECK(train_sweep.order_step == pair_sweep.order_step);
  REQUIRE(train_sweep.order_bins == pair_sweep.order_bins);
  REQUIRE(train_sweep.points.size() == pair_sweep.points.size());
  double scale = 0.0, worst = 0.0;
  for (size_t s = 0; s < pair_sweep.points.size(); ++s) {
    REQUIRE(pair_sweep.points[s].ok);
    const std::vector<double>& p = pair_sweep.points[s].amplitude_m;
    const std::vector<double>& t = train_sweep.points[s].waterfall.at(0);
    REQUIRE(t.size() == p.size());
    for (size_t b = 0; b < p.size(); ++b) {
      scale = std::max(scale, p[b]);
      worst = std::max(worst, std::abs(t[b] - p[b]));
    }
  }
  // Two solvers of one model (the histories test above: 1e-17 m on the TE); 1e-9 of the largest
  // line is far above their rounding and far below a wrong window, sample or order axis.
  INFO("largest difference " << worst << " m of " << scale << " m");
  CHECK(worst <= 1e-9 * scale);
  // The order tracks at mesh orders 1..3 read the same bins.
  const std::vector<OrderTrack> pair_tracks = MeshOrderTracks(PairWaterfall(pair_sweep), 20.0, 3);
  const std::vector<OrderTrack> train_tracks =
      MeshOrderTracks(MeshWaterfall(train_sweep, 0), train_sweep.mesh_orders[0], 3);
  REQUIRE(train_tracks.size() == 3);
  for (size_t k = 0; k < 3; ++k) {
    CHECK(train_tracks[k].order == pair_tracks[k].order);
    for (size_t s = 0; s < pair_sweep.points.size(); ++s) {
      CHECK(std::abs(train_tracks[k].amplitude_m[s] - pair_tracks[k].amplitude_m[s]) <=
            1e-9 * scale);
    }
  }
  CHECK(pair_tracks[0].amplitude_m[0] > 1e-3 * scale);  // the mesh order is a line, not noise
}

}  // namespace
}  // namespace gearnvh
