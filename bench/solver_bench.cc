// Exact-solver cost per tier at a mesh frequency of ~3.9 kHz (issue 9: comparable with the
// preprint, whose 1282 us/cycle at 0.20x real time implies a 256 us mesh period). Run: cmake -S .
// -B build-bench -DGEARNVH_BUILD_BENCH=ON && cmake --build build-bench --target bench_solver &&
// ./build-bench/bench/bench_solver Counters: ns per segment step, matvec per cycle, events per
// cycle, real-time ratio.
#include <benchmark/benchmark.h>

#include <numbers>
#include <string>

#include "config/gearbox_loader.h"
#include "gearnvh/solver/exact_solver.h"

namespace {

using namespace gearnvh;

// The example with its speed set so that the mesh frequency is 3.9 kHz.
GearboxSpec At3900Hz(const std::string& example) {
  GearboxSpec spec = config::LoadGearboxFile(std::string(GEARNVH_EXAMPLES_DIR) + "/" + example);
  spec.operating.speed = 2.0 * std::numbers::pi * 3900.0 / spec.pinion.teeth;
  return spec;
}

void RunSolver(benchmark::State& state, const std::string& example, Tier tier, SolverMethod method,
               EventMethod events) {
  const GearboxSpec spec = At3900Hz(example);
  const OperatingPointModel op = BuildOperatingPointModel(spec, tier);
  const SegmentTables& tables = op.tables;
  const auto [z0, s0] = StaticInitialState(tables);
  SolverOptions opt;
  opt.method = method;
  opt.events = events;
  opt.cycles = 2000;
  opt.transient_cycles = 200;
  opt.record_trajectory = false;
  SolverSummary last;
  for (auto _ : state) {
    const SolverResult r = SimulateExact(tables, z0, s0, opt);
    last = r.summary;
    benchmark::DoNotOptimize(r.final_state.data());
  }
  const double cycles = static_cast<double>(last.mesh_cycles);
  state.counters["ns_per_step"] = last.wall_s * 1e9 / (cycles * tables.segments());
  state.counters["us_per_cycle"] = last.wall_s * 1e6 / cycles;
  state.counters["matvec_per_cycle"] = last.matvec_per_cycle;
  state.counters["events_per_cycle"] = last.events_per_cycle;
  state.counters["real_time"] = last.real_time_ratio;
  state.counters["state_dim"] = tables.m;
}

void Register() {
  struct Case {
    const char* name;
    const char* example;
    Tier tier;
    SolverMethod method;
    EventMethod events;
  };
  const Case cases[] = {
      {"rattle/tier1/taylor", "idle_rattle.yaml", Tier::kTier1, SolverMethod::kStepped,
       EventMethod::kTaylor},
      {"rattle/tier1/v1", "idle_rattle.yaml", Tier::kTier1, SolverMethod::kStepped,
       EventMethod::kDyadic},
      {"rattle/tier1/v3", "idle_rattle.yaml", Tier::kTier1, SolverMethod::kStepped,
       EventMethod::kSpectral},
      {"rattle/tier1/fused", "idle_rattle.yaml", Tier::kTier1, SolverMethod::kFused,
       EventMethod::kSpectral},
      {"rattle/tier2/taylor", "idle_rattle.yaml", Tier::kTier2, SolverMethod::kStepped,
       EventMethod::kTaylor},
      {"rattle/tier3/taylor", "idle_rattle.yaml", Tier::kTier3, SolverMethod::kStepped,
       EventMethod::kTaylor},
      {"whine/tier1/stepped", "industrial_whine.yaml", Tier::kTier1, SolverMethod::kStepped,
       EventMethod::kTaylor},
      {"whine/tier1/fused", "industrial_whine.yaml", Tier::kTier1, SolverMethod::kFused,
       EventMethod::kTaylor},
      {"whine/tier3/fused", "industrial_whine.yaml", Tier::kTier3, SolverMethod::kFused,
       EventMethod::kTaylor},
      {"flexible/tier4/fused", "flexible_shafts.yaml", Tier::kTier4, SolverMethod::kFused,
       EventMethod::kTaylor},
      {"flexible/N40full/stepped", "flexible_shafts.yaml", Tier::kTier5, SolverMethod::kStepped,
       EventMethod::kTaylor},
      {"flexible/N40full/fused", "flexible_shafts.yaml", Tier::kTier5, SolverMethod::kFused,
       EventMethod::kTaylor},
      {"flexible/N20simple/fused", "flexible_shafts.yaml", Tier::kN20Simple, SolverMethod::kFused,
       EventMethod::kTaylor},
      {"flexible/N20MTA/fused", "flexible_shafts.yaml", Tier::kN20Mta, SolverMethod::kFused,
       EventMethod::kTaylor},
  };
  for (const Case& c : cases) {
    benchmark::RegisterBenchmark(
        c.name, [c](benchmark::State& s) { RunSolver(s, c.example, c.tier, c.method, c.events); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Register();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
