// Cancellation of the app's long calls (the flag the Python module sets on Ctrl-C): a train's
// operating point, a train sweep and both validation ladders end within a second of the flag,
// whatever phase they are in (table build, stepping, CVODE reference, fused-run checks).
// Tolerance: testing::kCancelBoundSeconds (support/cancel_latency.h) from the set to the end.
// Each call runs for far longer uncancelled (stated per case); the polled steps last at most
// ~0.1 s, the rest is margin for a loaded CI machine.
#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <optional>
#include <thread>

#include "config/gearbox_loader.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/analysis/train_sweep.h"
#include "gearnvh/analysis/train_validation.h"
#include "gearnvh/analysis/validation_ladder.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "support/cancel_latency.h"
#include "support/paths.h"

namespace gearnvh::app {
namespace {

TrainSpec TwoStageReducerExample() {
  return config::LoadAnyGearboxFile(testing::kExamples + "/two_stage_helical_reducer.yaml").train;
}

TEST_CASE("cancelling a train's operating point at tier 5 ends it within a second",
          "[app][train][cancel]") {
  // The reducer at tier 5 decomposes a new tuple at most grid segments of its transient: a
  // 64-cycle chunk took 5-40 s, and the run polled the flag only between chunks (39 s measured
  // from Python before the stepper was given the flag).
  TrainRunOptions run;
  run.tier = Tier::kTier5;
  run.cycles = 10;
  run.transient = 200000;
  run.allow_slow = true;
  const TrainSpec spec = TwoStageReducerExample();
  const double delay = GENERATE(0.2, 3.0);  // in the table build; in the stepping
  INFO("flag set " << delay << " s after the start");
  const double seconds = testing::SecondsToCancel(delay, [&](const std::atomic<bool>* cancel) {
    TrainRunOptions cancellable = run;
    cancellable.cancel = cancel;
    RunTrainOperatingPoint(spec, cancellable);
  });
  CHECK(seconds < testing::kCancelBoundSeconds);
}

TEST_CASE("cancelling a train sweep ends it within a second, every speed cancelled",
          "[app][train][sweep][cancel]") {
  // Five speeds of 200000 transient cycles at tier 5 on one thread: hours uncancelled.
  TrainSweepOptions options;
  options.tier = Tier::kTier5;
  options.cycles = 10;
  options.transient = 200000;
  options.threads = 1;
  options.allow_slow = true;
  const TrainSpec spec = TwoStageReducerExample();
  std::atomic<bool> flag{false};
  options.cancel = &flag;
  std::chrono::steady_clock::time_point set_at;
  std::thread setter([&] {
    std::this_thread::sleep_for(std::chrono::seconds(2));
    set_at = std::chrono::steady_clock::now();
    flag.store(true);
  });
  // Cancelled while the sweep's cost is estimated (its tier-5 tables, slow in the instrumented
  // build), the sweep throws RunCancelled; later, every speed reports "cancelled".
  std::optional<TrainSweepResult> result;
  try {
    result = RunTrainSweep(spec, options);
  } catch (const RunCancelled&) {
  } catch (...) {
    setter.join();
    throw;
  }
  const auto ended = std::chrono::steady_clock::now();
  setter.join();
  CHECK(std::chrono::duration<double>(ended - set_at).count() < testing::kCancelBoundSeconds);
  if (result) {
    REQUIRE_FALSE(result->points.empty());
    for (const TrainSweepPoint& p : result->points) {
      CHECK_FALSE(p.ok);
      CHECK(p.message == "cancelled");
    }
  }
}

TEST_CASE("cancelling a train's validation ladder ends it within a second in every stage",
          "[app][train][validate][cancel]") {
  // 9.5 s uncancelled on the reducer: the window run (0.4 s), the two CVODE references (to 6.3 s),
  // V2 and V1 (to 6.6 s), the fused-run check (3 s). CVODE's steps and the fused runs' table
  // builds were not polled before; the last stage is cancelled on its own below, as a late flag
  // could miss it on a faster machine.
  const TrainSpec spec = TwoStageReducerExample();
  SECTION("the ladder, in its CVODE references") {
    const double delay = GENERATE(0.5, 3.0);
    INFO("flag set " << delay << " s after the start");
    const double seconds = testing::SecondsToCancel(delay, [&](const std::atomic<bool>* cancel) {
      TrainValidationOptions options;
      options.cancel = cancel;
      RunTrainValidationLadder(spec, options);
    });
    CHECK(seconds < testing::kCancelBoundSeconds);
  }
  SECTION("its fused-run check") {
    const TrainTables tables =
        BuildTrainTablesAtTier(spec, BuildGearTrain(spec), spec.analysis.tier);
    const auto start = TrainStaticState(tables);
    const double seconds = testing::SecondsToCancel(0.5, [&](const std::atomic<bool>* cancel) {
      CompareFusionWithStepping(tables, tables, start.first, start.second, cancel);
    });
    CHECK(seconds < testing::kCancelBoundSeconds);
  }
}

TEST_CASE("cancelling a pair's validation ladder ends it within a second",
          "[app][validate][cancel]") {
  // Uncancelled on the idle-rattle example (CVODE over 10 cycles, the three locators, tables at up
  // to 32 times the segments) the ladder took 1.8 s on an AMD EPYC build but 0.6-1.0 s on an
  // Intel Xeon AVX-512 one, where a flag at 0.6 s once came after its end. The flags at 0.1 and
  // 0.3 s leave a margin of two at the faster machine's quickest.
  const GearboxSpec spec = config::LoadGearboxFile(testing::kExamples + "/idle_rattle.yaml");
  const double delay = GENERATE(0.1, 0.3);
  INFO("flag set " << delay << " s after the start");
  const double seconds = testing::SecondsToCancel(
      delay, [&](const std::atomic<bool>* cancel) { RunValidationLadder(spec, cancel); });
  CHECK(seconds < testing::kCancelBoundSeconds);
}

}  // namespace
}  // namespace gearnvh::app
