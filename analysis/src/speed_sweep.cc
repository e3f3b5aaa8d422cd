#include "gearnvh/analysis/speed_sweep.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <numbers>
#include <thread>

#include "gearnvh/analysis/parallel_for.h"
#include "gearnvh/analysis/written_numbers.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/nvh/spectrum.h"
#include "gearnvh/nvh/transmission_error.h"
#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/segment_tables.h"

namespace gearnvh {

namespace {

SolverOptions PointSolverOptions(const SpeedSweepOptions& options) {
  SolverOptions solver;
  ApplyLadderMethod(options.method, solver);
  solver.cycles = options.cycles;
  solver.transient_cycles = options.transient_cycles;
  solver.cancel = options.cancel;
  return solver;
}

SpeedPoint RunPoint(const GearboxSpec& base, const ComponentModel& model,
                    const ReducedModel& reduced, const SpeedSweepOptions& options, double speed,
                    int order_bins) {
  ThrowIfCancelled(options.cancel);  // a speed not started yet
  SpeedPoint p;
  p.speed_rad_s = speed;
  p.speed_rpm = Rpm(speed);
  GearboxSpec spec = base;
  spec.operating.speed = speed;
  const SegmentTables tables = BuildSegmentTables(model, reduced, spec, options.cancel);
  const auto [z0, state0] = StaticInitialState(tables);
  const SolverOptions solver = PointSolverOptions(options);
  const SolverResult run = SimulateExact(tables, z0, state0, solver);
  p.matvec_per_cycle = run.summary.matvec_per_cycle;
  p.real_time_ratio = run.summary.real_time_ratio;
  if (run.summary.status != SolverStatus::kSuccess) {
    p.message = run.summary.message;
    return p;
  }
  const TransmissionErrorStats te = ComputeTransmissionErrorStats(
      run.trajectory, spec.WheelTorque() / model.geometry.wheel.base, model.half_backlash);
  p.te_rms = te.rms;
  p.te_peak_to_peak = te.peak_to_peak;
  const double per_excitation = spec.operating.excitation.empty()
                                    ? 0.0
                                    : spec.pinion.teeth / spec.operating.excitation[0].order;
  const RattleIndices rattle =
      ComputeRattleIndices(run, model.effective_mass, per_excitation, nullptr);
  p.events_per_cycle = run.summary.events_per_cycle;
  p.drive_impacts_per_cycle = rattle.drive_impacts_per_cycle;
  p.back_impacts_per_cycle = rattle.back_impacts_per_cycle;
  p.regime = rattle.regime;
  const int per_cycle = solver.samples_per_cycle;
  SpectrumAnalyzer analyzer(static_cast<int>(options.waterfall_cycles * per_cycle));
  const AmplitudeSpectrum s =
      TeSpectrum(run.trajectory, tables.mesh_period, per_cycle, options.waterfall_cycles, analyzer);
  p.amplitude_m.assign(s.amplitude.begin(), s.amplitude.begin() + order_bins);
  p.ok = true;
  return p;
}

}  // namespace

int SpeedSweepResult::failed() const {
  int n = 0;
  for (const SpeedPoint& p : points) n += p.ok ? 0 : 1;
  return n;
}

RunMemory SpeedSweepMemory(const SpeedSweepOptions& options, size_t speeds) {
  const SolverOptions solver = PointSolverOptions(options);
  const RecordingReserve recorded = PlanRecording(solver);
  // A rank with no speeds (more ranks than speeds) holds nothing.
  const auto at_once =
      speeds == 0 ? size_t{0} : static_cast<size_t>(ParallelWorkers(speeds, options.threads));
  return {{{"recorded samples", at_once * recorded.sample_bytes()},
           {"event log", at_once * recorded.event_bytes()},
           {"waterfall spectra",
            at_once * SpectrumBytes(options.waterfall_cycles * solver.samples_per_cycle)}},
          recorded.samples};
}

SpeedSweepResult RunSpeedSweep(const GearboxSpec& spec, const ComponentModel& model,
                               const ReducedModel& reduced, const SpeedSweepOptions& options,
                               const SweepProgress& progress, const std::vector<bool>& skip) {
  if (options.cycles < 2) {
    throw InputError("SpeedSweepOptions.cycles", 0, std::to_string(options.cycles), "must be >= 2");
  }
  if (options.waterfall_cycles < 1 || options.waterfall_cycles > options.cycles) {
    throw InputError("SpeedSweepOptions.waterfall_cycles", 0,
                     std::to_string(options.waterfall_cycles), "must be in [1, cycles]");
  }
  const SweepRange& range = spec.analysis.speed_sweep;
  std::vector<double> speeds(static_cast<size_t>(range.points));
  for (int i = 0; i < range.points; ++i) speeds[static_cast<size_t>(i)] = range.Point(i);
  SpeedSweepResult result;
  result.speed_scale = range.scale;
  const int z1 = spec.pinion.teeth;
  result.order_step = static_cast<double>(z1) / static_cast<double>(options.waterfall_cycles);
  const double max_order = options.max_order > 0.0 ? options.max_order : 3.5 * z1;
  const long half = options.waterfall_cycles * SolverOptions{}.samples_per_cycle / 2;
  result.order_bins =
      static_cast<int>(std::min<long>(half, static_cast<long>(max_order / result.order_step))) + 1;

  // Campbell: the tier linearised in drive contact at the mean mesh stiffness; every
  // mode up to 3x the highest mesh frequency of the sweep.
  const LinearRotorModel linear = LinearisedRotor(model, reduced);
  CampbellOptions campbell;
  campbell.max_frequency_hz =
      3.0 * z1 * *std::max_element(speeds.begin(), speeds.end()) / (2.0 * std::numbers::pi);
  result.campbell = ComputeCampbell(linear, speeds, GearOrderLines(z1, spec.wheel.teeth, spec.operating.excitation), campbell);

  // Waterfall: one exact run per speed, in parallel.
  result.points.resize(speeds.size());
  const auto to_run = skip.empty()
                          ? speeds.size()
                          : static_cast<size_t>(std::count(skip.begin(), skip.end(), false));
  SweepProgressCounter counter(static_cast<int>(to_run), progress);
  ParallelFor(speeds.size(), options.threads, [&](size_t i) {
    SpeedPoint& p = result.points[i];
    if (!skip.empty() && skip[i]) {
      p.speed_rad_s = speeds[i];
      p.speed_rpm = Rpm(speeds[i]);
      p.message = "skipped";
      return;
    }
    RunSweepPoint(p, speeds[i], [&] {
      return RunPoint(spec, model, reduced, options, speeds[i], result.order_bins);
    });
    counter.Tick();
  });
  return result;
}

}  // namespace gearnvh
