// Train solver cost (issue 20, item 7): examples/manual_transmission_idle.yaml at idle, tier 1 —
// real-time ratio and table-cache bytes. Target of the issue: >= 50x real time on one core with the
// cache under 200 MB. Run: cmake -S . -B build -DGEARNVH_BUILD_BENCH=ON && ninja -C build
// bench_train && ./build/bench/bench_train
// Counters: real_time_ratio (simulated / wall, table building included), cache_peak_MiB, tuples
// built (misses), evictions, events per headset mesh cycle; "warm" repeats the same run with the
// cache already holding its tuples (the stepping cost alone).
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "config/gearbox_loader.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_stepper.h"

namespace {

using namespace gearnvh;

void RunTrain(benchmark::State& state, bool warm, size_t cache_limit) {
  const config::LoadedGearbox loaded = config::LoadAnyGearboxFile(
      std::string(GEARNVH_EXAMPLES_DIR) + "/manual_transmission_idle.yaml");
  const GearTrain train = BuildGearTrain(loaded.train);
  const TrainTables tables = BuildTrainTables(loaded.train, train);
  const auto [z0, s0] = TrainStaticState(tables);
  const double end = 1200.0 * tables.meshes.front().period;  // 200 transient + 1000 cycles
  TrainStepperOptions options;
  options.tables.cache_limit_bytes = cache_limit;
  TrainStepperSummary last;
  double ratio = 0.0;
  for (auto _ : state) {
    TrainStepper stepper(tables, options, z0, s0);
    if (warm) {
      stepper.Run(end);
      stepper.Reset(z0, s0);
    }
    const auto start = std::chrono::steady_clock::now();
    stepper.Run(end);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    last = stepper.summary();
    ratio = end / wall;
  }
  state.counters["real_time_ratio"] = ratio;
  state.counters["cache_peak_MiB"] = last.cache.peak_bytes / 1048576.0;
  state.counters["tuples_built"] = static_cast<double>(last.cache.misses);
  state.counters["evictions"] = static_cast<double>(last.cache.evictions);
  state.counters["dense_tuples"] = static_cast<double>(last.cache.ill_conditioned);
  state.counters["events_per_cycle"] = last.events / 1200.0;
}

void BM_ManualTransmissionIdle(benchmark::State& state) {
  RunTrain(state, false, size_t{256} << 20);
}
void BM_ManualTransmissionIdleWarm(benchmark::State& state) {
  RunTrain(state, true, size_t{4} << 30);
}
BENCHMARK(BM_ManualTransmissionIdle)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_ManualTransmissionIdleWarm)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
