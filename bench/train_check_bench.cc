// Time of the library work behind `check` on a ten-mesh gear train: the mesh models, the structural
// assembly, the full model's modes, every available tier and the Campbell data of tier 1 over 56
// speeds. A chain of eleven shafts (rigid, or elastic with 33 Timoshenko elements each), ten
// helical meshes. Run: cmake -S . -B build -DGEARNVH_BUILD_BENCH=ON && ninja -C build bench_train_check
// && ./build/bench/bench_train_check
#include <benchmark/benchmark.h>

#include <numbers>
#include <string>

#include "gearnvh/nvh/train_campbell.h"

namespace {

using namespace gearnvh;

TrainSpec TenMeshChain(bool elastic) {
  TrainSpec t;
  t.name = "ten-mesh chain";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  for (int i = 0; i <= 10; ++i) {
    TrainShaft s;
    s.name = "s" + std::to_string(i);
    if (elastic) {
      ShaftSpec e;
      e.material = "steel";
      e.segments = {{0.2, 0.04, 0.0}};
      e.bearings = {{0.01, 4e8, 2e8, 0.0, 500.0}, {0.19, 4e8, 0.0, 0.0, 500.0}};
      s.elastic = e;
    } else {
      s.inertia = 2e-3;
    }
    t.shafts.push_back(s);
  }
  for (int i = 0; i < 10; ++i) {
    for (int side = 0; side < 2; ++side) {
      TrainGear g;
      g.name = (side == 0 ? "a" : "b") + std::to_string(i);
      g.shaft = "s" + std::to_string(i + side);
      if (elastic) g.at = side == 0 ? 0.06 : 0.14;
      g.gear.teeth = side == 0 ? 23 + i % 3 : 31 + i % 4;
      g.gear.module = 2.5e-3;
      g.gear.pressure_angle = 20.0 * std::numbers::pi / 180.0;
      g.gear.face_width = 20e-3;
      g.gear.bore_diameter = 30e-3;
      g.gear.material = "steel";
      g.gear.helix_angle = 15.0 * std::numbers::pi / 180.0;
      g.gear.hand = side == 0 ? Hand::kRight : Hand::kLeft;
      t.gears.push_back(g);
    }
    TrainMesh m;
    m.gear_a = "a" + std::to_string(i);
    m.gear_b = "b" + std::to_string(i);
    m.mesh.backlash = 100e-6;
    t.meshes.push_back(m);
  }
  t.operating.input_shaft = "s0";
  t.operating.speed = 1500.0 * 2.0 * std::numbers::pi / 60.0;
  t.operating.loads = {{"s10", 20.0}};
  return t;
}

void BM_TrainCheck(benchmark::State& state) {
  const TrainSpec spec = TenMeshChain(state.range(0) != 0);
  ValidateTrainSpec(spec);
  const std::vector<Tier> all{Tier::kTier1, Tier::kTier2,     Tier::kTier3, Tier::kTier4,
                              Tier::kTier5, Tier::kN20Simple, Tier::kN20Mta};
  const SweepRange& sweep = spec.analysis.speed_sweep;
  std::vector<double> speeds;
  for (int i = 0; i < sweep.points; ++i) {
    speeds.push_back(sweep.from + (sweep.to - sweep.from) * i / (sweep.points - 1));
  }
  int dofs = 0;
  for (auto _ : state) {
    const GearTrain train = BuildGearTrain(spec);
    const TrainStructure structure = AssembleTrainStructure(spec, train);
    dofs = structure.dofs;
    const NaturalModes fe = FullTrainModes(structure, 10);
    std::vector<Tier> available;
    for (Tier t : all) {
      if (TrainTierAvailable(structure, t)) available.push_back(t);
    }
    const std::vector<TrainReducedModel> tiers = ReduceTrainTiers(structure, available);
    CampbellOptions options;
    options.max_frequency_hz = 3.0 * 35.0 * sweep.to / (2.0 * std::numbers::pi);
    const CampbellData campbell =
        TrainCampbell(spec, train, structure, tiers.front(), speeds, options);
    benchmark::DoNotOptimize(fe.frequencies_hz.data());
    benchmark::DoNotOptimize(campbell.critical_speeds.data());
  }
  state.counters["dofs"] = dofs;
}
BENCHMARK(BM_TrainCheck)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
