// Time to build and reduce a finely meshed two-shaft gearbox to the flexible tiers.
// Run: cmake -S . -B build-bench -DGEARNVH_BUILD_BENCH=ON && cmake --build build-bench --target
// bench_reduction && ./build-bench/bench/bench_reduction
#include <benchmark/benchmark.h>

#include <numbers>

#include "gearnvh/reduction/reduced_model.h"

namespace {

using gearnvh::GearboxSpec;

// Two 1 m shafts (a long industrial stage) meshed with `elements` Timoshenko elements each.
GearboxSpec LongShafts(int elements) {
  GearboxSpec s;
  s.name = "bench";
  s.materials["steel"] = {206e9, 0.3, 7850.0};
  for (gearnvh::GearSpec* g : {&s.pinion, &s.wheel}) {
    g->module = 3e-3;
    g->pressure_angle = 20.0 * std::numbers::pi / 180.0;
    g->face_width = 30e-3;
    g->material = "steel";
  }
  s.pinion.teeth = 31;
  s.wheel.teeth = 47;
  s.pinion.bore_diameter = 0.035;
  s.wheel.bore_diameter = 0.045;
  s.mesh.backlash = 120e-6;
  s.operating.speed = 3000 * 2 * std::numbers::pi / 60;
  s.operating.torque = 200;
  for (int k = 0; k < 2; ++k) {
    gearnvh::ShaftSpec shaft;
    shaft.material = "steel";
    shaft.segments = {{0.4, 0.04, 0.0}, {0.2, 0.05, 0.0}, {0.4, 0.04, 0.0}};
    shaft.gear_at = 0.5;
    shaft.bearings = {{0.05, 3e8, 1e8, 0, 500}, {0.95, 3e8, 0, 0, 500}};
    shaft.inertias = {{k == 0 ? 0.0 : 1.0, 0.05, 0.02}};
    shaft.element_length = 1.0 / elements;
    (k == 0 ? s.input_shaft : s.output_shaft) = shaft;
  }
  return s;
}

void BM_ReduceToTier5(benchmark::State& state) {
  const GearboxSpec spec = LongShafts(static_cast<int>(state.range(0)));
  const gearnvh::ComponentModel model = gearnvh::BuildComponentModel(spec);
  for (auto _ : state) {
    const gearnvh::ReducedModel r = gearnvh::ReduceModel(model, gearnvh::Tier::kTier5);
    benchmark::DoNotOptimize(r.K.data());
  }
  state.counters["elements"] = 2.0 * state.range(0);
  state.counters["dofs"] = model.dofs;
}
BENCHMARK(BM_ReduceToTier5)->Arg(250)->Arg(1000)->Arg(2500)->Unit(benchmark::kMillisecond);

void BM_BuildComponentModel(benchmark::State& state) {
  const GearboxSpec spec = LongShafts(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const gearnvh::ComponentModel m = gearnvh::BuildComponentModel(spec);
    benchmark::DoNotOptimize(m.dofs);
  }
  state.counters["elements"] = 2.0 * state.range(0);
}
BENCHMARK(BM_BuildComponentModel)->Arg(2500)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
