#include "gearnvh/nvh/atlas.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gearbox_spec_validation.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/nvh/lyapunov.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/solver/segment_tables.h"

namespace gearnvh {

void AtlasOptions::Validate() const {
  if (transient_cycles < 0) {
    throw InputError("AtlasOptions.transient_cycles", 0, std::to_string(transient_cycles),
                     "must be >= 0");
  }
  if (cycles < 8) {
    throw InputError("AtlasOptions.cycles", 0, std::to_string(cycles), "must be >= 8");
  }
  if (threads < 0) {
    throw InputError("AtlasOptions.threads", 0, std::to_string(threads), "must be >= 0");
  }
  if (!(chaos_threshold > 0.0)) {
    throw InputError("AtlasOptions.chaos_threshold", 0, std::to_string(chaos_threshold),
                     "must be > 0");
  }
}

int AtlasResult::Failed() const {
  int failed = 0;
  for (const AtlasCell& c : cells) failed += c.ok ? 0 : 1;
  return failed;
}

double AxisValue(const AtlasAxis& axis, int i) { return axis.range.Point(i); }

AtlasCell ComputeAtlasCell(const GearboxSpec& base, const AtlasAxis& x, const AtlasAxis& y, int ix,
                           int iy, const AtlasOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  AtlasCell cell;
  cell.ix = ix;
  cell.iy = iy;
  cell.x = AxisValue(x, ix);
  cell.y = AxisValue(y, iy);
  try {
    GearboxSpec spec = base;
    SetParameter(spec, x.parameter, cell.x);
    SetParameter(spec, y.parameter, cell.y);
    ValidateGearboxSpec(spec);
    const OperatingPointModel op = BuildOperatingPointModel(spec, options.tier, options.cancel);
    const SegmentTables& tables = op.tables;
    const auto [z0, state0] = StaticInitialState(tables);
    LyapunovOptions lyapunov;
    lyapunov.solver.events = options.events;
    lyapunov.solver.cancel = options.cancel;
    lyapunov.transient_cycles = options.transient_cycles;
    lyapunov.cycles = options.cycles;
    lyapunov.alignment_cycles = std::min<long>(100, options.cycles / 4);
    // The rattle indices need the exact statistics and the logged impacts, not the samples.
    lyapunov.record = true;
    lyapunov.solver.max_trajectory_samples = 0;
    const LyapunovEstimate est = EstimateLyapunov(tables, z0, state0, lyapunov);
    if (est.info != LyapunovEstimate::Info::kSuccess) {
      cell.message = est.message;
    } else {
      const double per_excitation =
          spec.operating.excitation.empty()
              ? 0.0
              : spec.pinion.teeth / spec.operating.excitation.front().order;
      const RattleIndices rattle =
          ComputeRattleIndices(est.run, op.model.effective_mass, per_excitation, nullptr);
      cell.lyapunov_per_s = est.exponent;
      cell.lyapunov_per_forcing_cycle = est.per_forcing_cycle;
      cell.lyapunov_standard_error = est.standard_error;
      cell.drive_impacts_per_cycle = rattle.drive_impacts_per_cycle;
      cell.back_impacts_per_cycle = rattle.back_impacts_per_cycle;
      const double cycles_per_forcing = est.forcing_period / tables.mesh_period;
      cell.rattle_index = rattle.impact_energy_per_cycle * cycles_per_forcing;
      cell.impact_velocity_rms = rattle.impact_velocity_rms;
      cell.separation_fraction = rattle.separation_fraction;
      const bool chaotic = IsChaotic(est.per_forcing_cycle, est.exponent, est.standard_error,
                                     options.chaos_threshold);
      cell.regime = chaotic ? RattleRegime::kChaotic : rattle.regime;
      cell.ok = true;
    }
  } catch (const InputError& e) {
    cell.ok = false;
    cell.message =
        options.input_error_message
            ? options.input_error_message(e, {{x.parameter, cell.x}, {y.parameter, cell.y}})
            : e.what();
  } catch (const std::exception& e) {
    cell.ok = false;
    cell.message = e.what();
  }
  cell.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return cell;
}

AtlasResult RunChaosAtlas(const GearboxSpec& base, const AtlasAxis& x, const AtlasAxis& y,
                          const AtlasOptions& options, const AtlasProgress& progress,
                          const std::vector<bool>& skip, const AtlasCellCallback& on_cell) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  AtlasResult result;
  result.x = x;
  result.y = y;
  const int nx = x.range.points, ny = y.range.points;
  const int total = nx * ny;
  if (!skip.empty() && static_cast<int>(skip.size()) != total) {
    throw std::invalid_argument("RunChaosAtlas: skip must have one entry per cell");
  }
  result.cells.resize(static_cast<size_t>(total));
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  result.threads = std::max(1, std::min(options.threads > 0 ? options.threads : hardware, total));
  int done = 0;
  int to_do = total;
  if (!skip.empty()) to_do = static_cast<int>(std::count(skip.begin(), skip.end(), false));
#pragma omp parallel for schedule(dynamic, 1) num_threads(result.threads)
  for (int k = 0; k < total; ++k) {
    const int ix = k % nx, iy = k / nx;
    AtlasCell& cell = result.cells[static_cast<size_t>(k)];
    const bool cancelled = options.cancel != nullptr && options.cancel->load();
    if (cancelled || (!skip.empty() && skip[static_cast<size_t>(k)])) {
      cell.ix = ix;
      cell.iy = iy;
      cell.x = AxisValue(x, ix);
      cell.y = AxisValue(y, iy);
      cell.message = cancelled ? "cancelled" : "skipped";
      continue;
    }
    cell = ComputeAtlasCell(base, x, y, ix, iy, options);
#pragma omp critical(gearnvh_atlas_progress)
    {
      ++done;
      if (on_cell) on_cell(cell);
      if (progress) progress(done, to_do);
    }
  }
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace gearnvh
