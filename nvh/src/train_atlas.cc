#include "gearnvh/nvh/train_atlas.h"

#include <algorithm>
#include <chrono>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/train_lyapunov.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

void TrainAtlasOptions::Validate() const {
  if (transient_cycles < 0) {
    throw InputError("TrainAtlasOptions.transient_cycles", 0, std::to_string(transient_cycles),
                     "must be >= 0");
  }
  if (cycles < 8) {
    throw InputError("TrainAtlasOptions.cycles", 0, std::to_string(cycles), "must be >= 8");
  }
  if (!(chaos_threshold > 0.0)) {
    throw InputError("TrainAtlasOptions.chaos_threshold", 0, std::to_string(chaos_threshold),
                     "must be > 0");
  }
}

namespace {

// The statistics' samples are not used by the atlas: one per cycle of the fastest mesh.
constexpr int kSamplesPerCycle = 1;

void FillPoint(const TrainTables& tables, const TrainLyapunovSummary& lyapunov,
               const TrainStatistics& stats, double chaos_threshold, TrainAtlasPoint& p) {
  p.lyapunov_per_s = lyapunov.exponents.front();
  p.lyapunov_per_forcing_cycle = lyapunov.per_forcing_cycle.front();
  p.lyapunov_standard_error = lyapunov.standard_errors.front();
  RattleRegime worst = RattleRegime::kNoImpact;
  for (size_t i = 0; i < stats.meshes.size(); ++i) {
    const TrainMeshStatistics& m = stats.meshes[i];
    const double cycles = stats.recorded_time / tables.meshes[i].period;
    TrainAtlasMesh mesh;
    mesh.name = m.name;
    mesh.drive_impacts_per_cycle = static_cast<double>(m.drive_impacts) / cycles;
    mesh.back_impacts_per_cycle = static_cast<double>(m.back_impacts) / cycles;
    mesh.separation_fraction = m.free_time_fraction;
    mesh.impact_velocity_rms = m.impact_velocity_rms;
    mesh.regime = ImpactRegime(m.drive_impacts, m.back_impacts);
    worst = std::max(worst, mesh.regime);
    p.meshes.push_back(mesh);
  }
  for (const TrainLooseGearStatistics& g : stats.loose_gears) {
    p.loose_gears.push_back(
        {g.name, g.rattle_index, g.impacts, g.rank, g.impact_energy_per_second});
  }
  p.regime = IsChaotic(p.lyapunov_per_forcing_cycle, p.lyapunov_per_s, p.lyapunov_standard_error,
                       chaos_threshold)
                 ? RattleRegime::kChaotic
                 : worst;
}

}  // namespace

TrainAtlasPoint ComputeTrainAtlasPoint(const TrainSpec& variant, const TrainAtlasOptions& options,
                                       const TrainBuilder& build) {
  const auto start = std::chrono::steady_clock::now();
  TrainAtlasPoint p;
  try {
    options.Validate();
    ValidateTrainSpec(variant);
    const GearTrain train = build ? build(variant) : BuildGearTrain(variant);
    TrainTableOptions table_options;
    table_options.cancel = options.cancel;
    const TrainTables tables = BuildTrainTablesAtTier(variant, train, options.tier, table_options);
    TrainLyapunovOptions lyapunov;
    lyapunov.exponents = 1;
    lyapunov.transient_cycles = options.transient_cycles;
    lyapunov.cycles = options.cycles;
    lyapunov.alignment_cycles = std::min<long>(lyapunov.alignment_cycles, options.cycles / 4);
    lyapunov.stepper.events = options.events;
    lyapunov.stepper.cancel = options.cancel;
    const double recorded_from =
        static_cast<double>(options.transient_cycles) * tables.meshes.front().period;
    TrainRecorder recorder(tables, kSamplesPerCycle, recorded_from);
    lyapunov.recorder = &recorder;
    const auto [z0, states0] = TrainStaticState(tables);
    const TrainLyapunovSummary est = EstimateTrainLyapunov(tables, z0, states0, lyapunov);
    if (est.info != TrainLyapunovSummary::Info::kSuccess) {
      p.message = est.message;
    } else {
      FillPoint(tables, est, recorder.Result(), options.chaos_threshold, p);
      p.ok = true;
    }
  } catch (const std::exception& e) {
    p.ok = false;
    p.message = e.what();
  }
  p.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return p;
}

}  // namespace gearnvh
