#include "gearnvh/analysis/train_operating_point.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/train_atlas.h"
#include "gearnvh/analysis/train_load_warnings.h"
#include "gearnvh/analysis/train_transient.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/train_reduced_tables.h"

namespace gearnvh {
namespace {

// The train's model warnings and errors that may unload tooth pairs (the pair's warning, per
// mesh), said once per run.
std::vector<std::string> TrainWarnings(const GearTrain& train, const TrainTables& tables) {
  std::vector<std::string> out = train.warnings;
  for (size_t i = 0; i < static_cast<size_t>(tables.gear_meshes); ++i) {
    const MeshErrorExcitation& errors = tables.meshes[i].errors;
    const TrainMeshModel& mm = train.meshes[i];
    if (!errors.active() || !(mm.stiffness.max > 0.0)) continue;
    const double pair_deflection = mm.cycle.load / mm.stiffness.max;
    if (errors.largest_pair_deviation() > pair_deflection) {
      out.push_back(fmt::format(
          "meshes[{}] ({}): pitch deviations differ by up to {:.3g} µm, more than the loaded "
          "deflection of the mesh ({:.3g} µm at its transmitted torque): they can unload tooth "
          "pairs, which the model does not follow (the loaded pairs of the error-free mesh carry "
          "the errors' mean)",
          i, mm.name, errors.largest_pair_deviation() * 1e6, pair_deflection * 1e6));
    }
  }
  return out;
}

// The shaft-order sources of the spectra: the input shaft ("fin") when an engine order acts on it
// or its gears carry errors, and every other body an engine order acts on or whose gears carry
// runout or pitch errors ("f_<body>"), at its nominal rotation frequency.
std::vector<ShaftOrderSource> ShaftOrderSources(const TrainSpec& spec, const GearTrain& train,
                                                const TrainTables& tables) {
  const TrainTopology& topo = train.topology;
  std::vector<bool> carries(topo.bodies.size(), false);
  for (size_t g = 0; g < spec.gears.size(); ++g) {
    const GearSpec& gear = spec.gears[g].gear;
    const bool runout = gear.runout && gear.runout->amplitude > 0.0;
    const bool pitch = std::any_of(gear.pitch_errors.begin(), gear.pitch_errors.end(),
                                   [](double f) { return f != 0.0; });
    if (runout || pitch) carries[static_cast<size_t>(topo.gear_body[g])] = true;
  }
  // And the shafts the engine orders act on (orders of their own speeds).
  for (size_t i = 0; i < spec.operating.excitation.size(); ++i)
    carries[static_cast<size_t>(ExcitationBody(spec, topo, i))] = true;
  const double to_hz = 1.0 / (2.0 * std::numbers::pi);
  std::vector<ShaftOrderSource> sources;
  if (carries[static_cast<size_t>(topo.input_body)])
    sources.push_back({"fin", tables.input_speed * to_hz});
  for (size_t b = 0; b < topo.bodies.size(); ++b) {
    if (!carries[b] || static_cast<int>(b) == topo.input_body) continue;
    sources.push_back({"f_" + topo.bodies[b].name, std::abs(topo.bodies[b].speed) * to_hz});
  }
  return sources;
}

// The spectrum window on the recorder's sample grid t_k = start + k dt: the last W whole common
// periods inside [start, end].
struct SpectrumWindow {
  long periods = 0;             // W
  long samples_per_period = 0;  // common period / dt (a whole number)
  double from_time = 0.0;       // the window's first sample
  std::string note;             // why there is no window
};

SpectrumWindow PlanWindow(const TrainTables& t, double dt, double start, double end,
                          long max_samples, long first_mesh_cycles) {
  SpectrumWindow w;
  if (t.common_period <= 0.0) {
    w.note =
        "no spectrum: the meshes and engine orders have no common period within 1000 input "
        "revolutions, so no window holds whole periods of every line";
    return w;
  }
  const double per_period = t.common_period / dt;
  w.samples_per_period = std::llround(per_period);
  // The common period is a whole number of cycles of the fastest mesh, dt a whole fraction of it.
  if (w.samples_per_period < 1 ||
      std::abs(per_period - static_cast<double>(w.samples_per_period)) > 1e-6) {
    w.note = "no spectrum: the common period is not a whole number of samples";
    return w;
  }
  const long in_record =
      static_cast<long>(std::floor((end - start) / t.common_period * (1 + 1e-12)));
  w.periods = std::min(in_record, max_samples / w.samples_per_period);
  const long period_cycles = std::llround(t.common_period / t.meshes.front().period);
  if (w.periods == 0) {
    w.note = in_record == 0
                 ? fmt::format(
                       "no spectrum: the record ({} cycles of {}) is shorter than the "
                       "common period of the train ({} cycles); record at least that many",
                       first_mesh_cycles, t.meshes.front().name, period_cycles)
                 : fmt::format(
                       "no spectrum: one common period ({} cycles of {}) needs more "
                       "samples than the {} kept per mesh",
                       period_cycles, t.meshes.front().name, max_samples);
    return w;
  }
  const long last = static_cast<long>(std::floor((end - start) / dt));
  const long first = std::max(0L, last - w.periods * w.samples_per_period);
  w.from_time = start + static_cast<double>(first) * dt;
  return w;
}

// The uniform samples a run keeps per mesh: from the sample at `from` (s) to the record's end, at
// most `count`. The sideband window, the waterfall's tail and the time histories are parts of it.
struct KeptSamples {
  double from = 0.0;
  long count = 0;
};

KeptSamples PlanKeptSamples(const TrainRunOptions& options, const SpectrumWindow& window,
                            double start, double end, double dt) {
  // Samples at start + k dt before the record's end (the last piece's end, less the recorder's
  // 1e-9 dt); one more at the front keeps a rounded first index inside.
  const long record = static_cast<long>(std::ceil((end - start) / dt - 1e-9));
  if (options.histories) return {start, std::min(record, options.max_history_samples)};
  long first = record;
  if (window.periods > 0)
    first = std::min<long>(first, std::llround((window.from_time - start) / dt));
  if (options.waterfall_samples > 0)
    first = std::min(first, std::max(0L, record - options.waterfall_samples - 1));
  return {start + static_cast<double>(first) * dt, std::max(0L, record - first)};
}

// Per coupling two rows on z: its twist (B_a - B_b) x, B the bodies' angle rows, and its torque
// k_1 twist + c twist' plus the force of each stage after the first (its contact terms).
std::pair<Eigen::MatrixXd, std::vector<TrainRecorder::ContactTerm>> CouplingRows(
    const GearTrain& train, const TrainTables& t) {
  Eigen::MatrixXd rows =
      Eigen::MatrixXd::Zero(2 * static_cast<Eigen::Index>(train.couplings.size()), t.m);
  for (size_t c = 0; c < train.couplings.size(); ++c) {
    const TrainCouplingModel& coupling = train.couplings[c];
    const Eigen::RowVectorXd twist =
        t.body_angles.row(coupling.body_a) - t.body_angles.row(coupling.body_b);
    const auto r = static_cast<Eigen::Index>(2 * c);
    rows.block(r, 0, 1, t.n) = twist;
    rows.block(r + 1, 0, 1, t.n) = coupling.stiffness * twist;
    rows.block(r + 1, t.n, 1, t.n) = coupling.damping * twist;
  }
  std::vector<TrainRecorder::ContactTerm> terms;
  for (size_t i = static_cast<size_t>(t.gear_meshes); i < t.meshes.size(); ++i) {
    terms.push_back({2 * static_cast<Eigen::Index>(t.meshes[i].coupling) + 1, static_cast<int>(i)});
  }
  return {rows, terms};
}

// The couplings' twist and torque from the statistics of CouplingRows (TrackOutputs).
std::vector<TrainCouplingResponse> CouplingResponses(const GearTrain& train,
                                                     const TrainStatistics& stats) {
  std::vector<TrainCouplingResponse> out;
  for (size_t c = 0; c < train.couplings.size(); ++c) {
    out.push_back({train.couplings[c].name, stats.outputs[2 * c], stats.outputs[2 * c + 1], {}});
    for (const TrainCouplingStageStatistics& s : stats.coupling_stages) {
      if (s.coupling == static_cast<int>(c)) out.back().stages.push_back(s);
    }
  }
  return out;
}

// The index in a series of samples dt apart from `series_from` of the sample at `from`, when the
// series holds `length` samples from there; nullopt otherwise.
std::optional<size_t> SliceStart(size_t series_size, double series_from, double dt, double from,
                                 long length) {
  const long first = std::llround((from - series_from) / dt);
  if (first < 0 || length <= 0 || first + length > static_cast<long>(series_size)) return {};
  return static_cast<size_t>(first);
}

// What the run keeps that grows with the record (TrainOperatingPoint::memory): `kept` samples per
// mesh (and bearing force row), the sideband window's spectrum, and with histories the event log,
// every mesh's spectrum and the couplings' twist and torque samples, with a waterfall every mesh's
// tail spectrum.
RunMemory TrainRunMemory(const TrainRunOptions& options, size_t meshes, long kept,
                         long window_samples, size_t bearing_rows, size_t couplings) {
  RunMemory memory{{{"TE samples", TrainRecorder::SeriesBytes(meshes, kept, options.histories)},
                    {"TE spectrum", SpectrumBytes(window_samples)}},
                   kept};
  if (options.bearing_forces && bearing_rows > 0) {
    // With histories each row's window spectrum is kept too (its amplitudes).
    const size_t spectra =
        options.histories
            ? bearing_rows * static_cast<size_t>(window_samples / 2 + 1) * sizeof(double)
            : 0;
    memory.parts.push_back({"bearing force samples",
                            TrainRecorder::SeriesBytes(0, kept, false, bearing_rows) + spectra});
    memory.bearing_rows = bearing_rows;
  }
  if (options.histories && couplings > 0) {
    memory.parts.push_back(
        {"coupling samples", TrainRecorder::SeriesBytes(0, kept, false, 2 * couplings)});
  }
  if (options.histories) {
    memory.parts.push_back(
        {"event log", static_cast<size_t>(options.max_logged_events) * sizeof(TrainEventRecord)});
    memory.parts.push_back({"TE spectra of every mesh",
                            meshes * static_cast<size_t>(window_samples / 2 + 1) * sizeof(double)});
  }
  if (options.waterfall_samples > 0) {
    memory.parts.push_back(
        {"waterfall spectra",
         SpectrumBytes(options.waterfall_samples) +
             meshes * static_cast<size_t>(options.waterfall_samples / 2 + 1) * sizeof(double)});
  }
  return memory;
}

}  // namespace

void TrainRunOptions::Validate() const {
  if (cycles < 1)
    throw InputError("TrainRunOptions.cycles", 0, std::to_string(cycles), "must be >= 1");
  if (transient < 0) {
    throw InputError("TrainRunOptions.transient", 0, std::to_string(transient), "must be >= 0");
  }
  if (samples_per_cycle < 4) {
    throw InputError("TrainRunOptions.samples_per_cycle", 0, std::to_string(samples_per_cycle),
                     "must be >= 4");
  }
  if (max_spectrum_samples < 1) {
    throw InputError("TrainRunOptions.max_spectrum_samples", 0,
                     std::to_string(max_spectrum_samples), "must be >= 1");
  }
  if (max_history_samples < 0) {
    throw InputError("TrainRunOptions.max_history_samples", 0, std::to_string(max_history_samples),
                     "must be >= 0");
  }
  if (max_logged_events < 0) {
    throw InputError("TrainRunOptions.max_logged_events", 0, std::to_string(max_logged_events),
                     "must be >= 0");
  }
  if (waterfall_samples < 0) {
    throw InputError("TrainRunOptions.waterfall_samples", 0, std::to_string(waterfall_samples),
                     "must be >= 0");
  }
}

TrainOperatingPoint RunTrainOperatingPoint(const TrainSpec& spec, const TrainRunOptions& options,
                                           const TrainProgress& progress) {
  options.Validate();
  GearTrain train = BuildGearTrain(spec);
  TrainTableOptions table_options;
  table_options.cancel = options.cancel;
  TrainTables tables = BuildTrainTablesAtTier(spec, train, options.tier, table_options);
  return RunTrainOperatingPoint(spec, std::move(train), std::move(tables), options, progress);
}

namespace {

// Each mesh's TE spectrum over the sideband window and its lines (TrainOperatingPoint::sidebands).
void MeshSidebands(const TrainSpec& spec, const TrainRunOptions& options,
                   const SpectrumWindow& window, const TrainRecorder& recorder, double kept_from,
                   bool ok, TrainOperatingPoint& op) {
  const TrainTables& tables = op.tables;
  // Shaft-order content comes from the engine orders (orders of the shafts they act on, up to the
  // highest written) and from the runout and pitch errors of gears (orders of the bodies that
  // carry them). The common period holds whole revolutions of both, so their lines sit on bins.
  op.sideband_options.shaft_order_sources = !tables.excitation.empty() || tables.error_inputs > 0;
  for (const ExcitationOrder& e : spec.operating.excitation) {
    op.sideband_options.orders =
        std::max(op.sideband_options.orders, static_cast<int>(std::ceil(e.order)));
  }
  const std::vector<ShaftOrderSource> sources = ShaftOrderSources(spec, op.train, tables);
  op.sidebands.resize(static_cast<size_t>(tables.gear_meshes));
  const long window_samples = window.periods * window.samples_per_period;
  const double dt = recorder.sample_interval();
  const std::vector<std::vector<double>>& series = recorder.te_series();
  const std::optional<size_t> first =
      ok && window.periods > 0 && !series.empty()
          ? SliceStart(series.front().size(), kept_from, dt, window.from_time, window_samples)
          : std::nullopt;
  if (first) {
    // Only a window the spectrum was taken over: a stopped run has none (0).
    op.sideband_window_common_periods = window.periods;
    SpectrumAnalyzer analyzer(static_cast<int>(window_samples));
    std::vector<double> window_te;
    for (size_t i = 0; i < op.sidebands.size(); ++i) {
      ThrowIfCancelled(options.cancel);  // an FFT of up to 2^21 samples per mesh
      const TrainMeshTable& mt = tables.meshes[i];
      const auto from = series[i].begin() + static_cast<long>(*first);
      window_te.assign(from, from + window_samples);
      AmplitudeSpectrum spectrum = analyzer.Analyze(window_te, 1.0 / dt);
      op.sidebands[i].window_cycles =
          std::llround(static_cast<double>(window.periods) * tables.common_period / mt.period);
      SidebandOptions mesh_options = op.sideband_options;
      mesh_options.scale = mt.half_backlash;
      op.sidebands[i].rows = SidebandTable(spectrum, 1.0 / mt.period, sources, mesh_options);
      if (options.histories) op.sidebands[i].spectrum = std::move(spectrum);
    }
  } else if (!window.note.empty()) {
    op.sideband_notes.push_back(window.note);
  } else if (ok && op.histories.truncated) {
    op.sideband_notes.push_back(
        "no spectrum: the time histories hold fewer samples than the record (max_history_samples)");
  } else {
    op.sideband_notes.push_back("no spectrum: the run stopped before the end of the record");
  }
  op.sideband_notes.push_back(
      !op.sideband_options.shaft_order_sources
          ? "the train has no runout, pitch error or engine order: no shaft-order line or "
            "sideband can arise, so only each mesh's harmonics are listed"
          : "shaft-order lines and sidebands come from the engine orders (orders of the shaft "
            "each acts on: j fin on the input shaft, j f_<shaft> on another) and the gears' runout "
            "and pitch errors (orders of the bodies that carry them, f_<body>); every mesh lists "
            "the lines of every source");
  op.sideband_notes.push_back(SidebandListingNote(op.sideband_options) +
                              " (rounding of the exact solution lies near -300 dB)");
}

// Each mesh's TE spectrum over the record's last options.waterfall_samples samples
// (TrainOperatingPoint::waterfall); none when the run stopped or the samples are not all kept.
void TailSpectra(const TrainRunOptions& options, const TrainRecorder& recorder, bool ok,
                 TrainOperatingPoint& op) {
  const long n = options.waterfall_samples;
  const std::vector<std::vector<double>>& series = recorder.te_series();
  if (!ok || n <= 0 || series.empty() || static_cast<long>(series.front().size()) < n) return;
  if (op.histories.truncated) return;  // the kept samples stop before the record's end
  SpectrumAnalyzer analyzer(static_cast<int>(n));
  std::vector<double> tail;
  for (const std::vector<double>& te : series) {
    ThrowIfCancelled(options.cancel);
    tail.assign(te.end() - n, te.end());
    op.waterfall.push_back(analyzer.Analyze(tail, 1.0 / recorder.sample_interval()));
  }
}

// The tier against the full FE model at the run's speed: mesh m's modes up to 3x its mesh frequency
// (the pair's limit); a miss is warned with the mesh that sees the mode.
void AssessTier(const TrainSpec& spec, const TrainRunOptions& options, TrainOperatingPoint& op) {
  ThrowIfCancelled(options.cancel);
  const TrainStructure structure = AssembleTrainStructure(spec, op.train);
  std::vector<double> limits_hz;
  for (int i = 0; i < op.tables.gear_meshes; ++i)
    limits_hz.push_back(3.0 / op.tables.meshes[static_cast<size_t>(i)].period);
  TierAdequacyOptions adequacy;
  adequacy.max_frequency_hz = *std::max_element(limits_hz.begin(), limits_hz.end());
  const TrainReducedModel reduced = ReduceTrain(structure, options.tier);
  ThrowIfCancelled(options.cancel);
  const MeshModes full = FullModelMeshModes(structure, limits_hz, adequacy);
  ThrowIfCancelled(options.cancel);
  op.adequacy = AssessTierAdequacy(structure, reduced, full, adequacy);
  op.adequacy_options = adequacy;
  if (const std::string warning = op.adequacy.Warning(MeshNames(spec)); !warning.empty()) {
    op.warnings.push_back(warning);
  }
}

// Each bearing's force (TrainOperatingPoint::bearing_forces): the exact statistics of its rows,
// and with spectra the sideband window's bins at every mesh's harmonics 1..3.
void BearingForces(const SpectrumWindow& window, const TrainRecorder& recorder, double kept_from,
                   const TrainRunOptions& options, TrainOperatingPoint& op) {
  const TrainTables& tables = op.tables;
  const std::vector<TrainOutputSummary>& exact = op.stats.bearing_forces;
  if (!op.ok() || exact.size() != 3 * tables.bearings.size()) return;
  // The bearing force rows come first among the tracked rows.
  const std::vector<std::vector<double>>& series = recorder.tracked_series();
  const long window_samples = window.periods * window.samples_per_period;
  const double dt = recorder.sample_interval();
  std::optional<size_t> first;
  if (options.spectra && !series.empty() && window.periods > 0) {
    first = SliceStart(series.front().size(), kept_from, dt, window.from_time, window_samples);
  }
  std::optional<SpectrumAnalyzer> analyzer;
  if (first) analyzer.emplace(static_cast<int>(window_samples));
  std::vector<double> slice;
  for (size_t b = 0; b < tables.bearings.size(); ++b) {
    TrainBearingForce f;
    f.bearing = tables.bearings[b];
    std::array<AmplitudeSpectrum, 3> spectra;
    for (size_t d = 0; d < 3; ++d) {
      const TrainOutputSummary& row = exact[3 * b + d];
      f.mean[d] = row.mean;
      f.rms[d] = row.rms;
      f.min[d] = row.min;
      f.max[d] = row.max;
      if (!first) continue;
      const auto from = series[3 * b + d].begin() + static_cast<long>(*first);
      slice.assign(from, from + window_samples);
      spectra[d] = analyzer->Analyze(slice, 1.0 / dt);
    }
    for (size_t i = 0; first && i < static_cast<size_t>(tables.gear_meshes); ++i) {
      const TrainMeshTable& mt = tables.meshes[i];
      for (int h = 1; h <= 3; ++h) {
        TrainBearingForce::Line line{
            "mesh " + mt.name + " " + std::to_string(h) + "x", h / mt.period, {}};
        for (size_t d = 0; d < 3; ++d) {
          const auto k = static_cast<size_t>(std::llround(line.frequency_hz / spectra[d].bin_hz));
          line.amplitude[d] = k < spectra[d].amplitude.size() ? spectra[d].amplitude[k] : 0.0;
        }
        f.lines.push_back(std::move(line));
      }
    }
    if (first && options.histories) f.spectrum = std::move(spectra);
    op.bearing_forces.push_back(std::move(f));
  }
}

// What the run's record gives after it: the histories (moved out of the recorder), the tail,
// sideband and bearing spectra.
void TakeRecord(const TrainSpec& spec, const TrainRunOptions& options, const SpectrumWindow& window,
                double kept_from, bool ok, TrainRecorder& recorder, TrainOperatingPoint& op) {
  TrainHistories& h = op.histories;
  if (options.histories) {
    const std::vector<std::vector<double>>& te = recorder.te_series();
    h.start = recorder.start_time();
    h.dt = recorder.sample_interval();
    h.truncated = (te.empty() ? 0L : static_cast<long>(te.front().size())) < op.stats.samples;
    h.events = recorder.events();
    h.events_truncated = recorder.window_events() > static_cast<long>(h.events.size());
    h.contact_names.clear();
    for (const TrainMeshTable& mt : op.tables.meshes) h.contact_names.push_back(mt.name);
  }
  TailSpectra(options, recorder, ok, op);
  if (options.spectra) MeshSidebands(spec, options, window, recorder, kept_from, ok, op);
  if (options.bearing_forces) BearingForces(window, recorder, kept_from, options, op);
  if (!options.histories) return;
  std::vector<std::vector<double>> tracked;
  recorder.TakeSeries(h.te, h.force, h.contact, tracked);
  if (tracked.empty()) return;  // no sample kept
  // The tracked rows: the bearing force rows (with bearing_forces), then CouplingRows's two per
  // coupling.
  const size_t bearing_rows = tracked.size() - 2 * op.train.couplings.size();
  for (size_t r = 0; r < tracked.size(); ++r) {
    std::vector<std::vector<double>>& into =
        r < bearing_rows ? h.bearing_force
                         : ((r - bearing_rows) % 2 == 0 ? h.coupling_twist : h.coupling_torque);
    into.push_back(std::move(tracked[r]));
  }
}

}  // namespace

TrainOperatingPoint RunTrainOperatingPoint(const TrainSpec& spec, GearTrain train,
                                           TrainTables tables_at_tier,
                                           const TrainRunOptions& options,
                                           const TrainProgress& progress) {
  options.Validate();
  if (tables_at_tier.tier != options.tier) {
    throw std::logic_error("RunTrainOperatingPoint: the tables are not at options.tier");
  }
  TrainOperatingPoint op;
  op.tier = options.tier;
  op.train = std::move(train);
  op.tables = std::move(tables_at_tier);
  op.warnings = TrainWarnings(op.train, op.tables);
  for (const std::string& w : TrainLoadWarnings(spec, op.train.topology)) op.warnings.push_back(w);
  const TrainTables& tables = op.tables;
  // cycles and transient count cycles of the first mesh in the file.
  const double period = tables.meshes.front().period;
  const double start = static_cast<double>(options.transient) * period;
  const double end = start + static_cast<double>(options.cycles) * period;

  if (options.transient_warning) {
    const std::string transient =
        TransientDecayWarning(tables, start, options.transient, options.names("transient"));
    if (!transient.empty()) op.warnings.push_back(transient);
  }
  op.cost = EstimateRunCost(tables, end, &spec);
  if (const std::string slow = CheckRunCost(op.cost, options.allow_slow, "the run", options.names);
      !slow.empty()) {
    op.warnings.push_back(slow);
    if (options.before_run_warning) options.before_run_warning(slow);
  }
  const auto [z0, states0] = TrainStaticState(tables);
  op.solver.events = options.events;
  op.solver.jumps = options.jumps;
  TrainStepperOptions stepper_options = op.solver;  // op.solver keeps no flag beyond this call
  stepper_options.cancel = options.cancel;
  TrainStepper stepper(tables, stepper_options, z0, states0);
  TrainRecorder recorder(tables, options.samples_per_cycle, start);
  if (options.bearing_forces) recorder.TrackBearingForces();
  if (!op.train.couplings.empty()) {
    const auto [rows, terms] = CouplingRows(op.train, tables);
    recorder.TrackOutputs(rows, terms);
  }
  const double dt = recorder.sample_interval();
  SpectrumWindow window;
  if (options.spectra) {
    window = PlanWindow(tables, dt, start, end, options.max_spectrum_samples, options.cycles);
  }
  const KeptSamples kept = PlanKeptSamples(options, window, start, end, dt);
  op.memory = TrainRunMemory(options, static_cast<size_t>(tables.gear_meshes), kept.count,
                             window.periods * window.samples_per_period,
                             static_cast<size_t>(tables.bearing_force_rows.rows()),
                             op.train.couplings.size());
  if (options.before_run_memory) {
    if (const std::string warning = options.before_run_memory(op.memory); !warning.empty()) {
      op.warnings.push_back(warning);
      if (options.before_run_warning) options.before_run_warning(warning);
    }
  }
  // After the cost and memory checks: a refused run does not pay for the full model's modes.
  if (options.tier_adequacy) AssessTier(spec, options, op);
  if (kept.count > 0) {
    // The bearing rows come first: without histories only they are kept (their spectra).
    const Eigen::Index bearing_rows = options.bearing_forces ? tables.bearing_force_rows.rows() : 0;
    const auto coupling_rows = static_cast<Eigen::Index>(2 * op.train.couplings.size());
    recorder.KeepSeries(kept.from, kept.count, options.histories,
                        options.histories ? bearing_rows + coupling_rows : bearing_rows);
  }
  if (options.histories) recorder.KeepEvents(options.max_logged_events);
  const auto wall_start = std::chrono::steady_clock::now();
  // The run goes in chunks of at most 1 % (progress is reported at every 1 %) and kChunkCycles
  // cycles: a chunk's end bounds the fused runs and the fusion-table decision, so the cap (once
  // cancellation's latency) is kept to keep the results. The stepper polls cancellation itself.
  constexpr int kProgressSteps = 100;
  constexpr double kChunkCycles = 64.0;
  const double chunk = std::min(end / kProgressSteps, kChunkCycles * period);
  const long chunks = static_cast<long>(std::ceil(end / chunk));
  bool ok = true;
  long reported = 0;
  for (long c = 1; c <= chunks && ok; ++c) {
    ok = stepper.Run(c == chunks ? end : std::min(end, chunk * static_cast<double>(c)), &recorder);
    const long step = static_cast<long>(kProgressSteps * stepper.time() / end);
    if (progress && (step > reported || c == chunks || !ok)) {
      reported = step;
      progress(stepper.time(), end);
    }
  }
  op.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  op.summary = stepper.summary();
  op.stats = recorder.Result();
  if (ok) op.couplings = CouplingResponses(op.train, op.stats);
  TakeRecord(spec, options, window, kept.from, ok, recorder, op);
  return op;
}

}  // namespace gearnvh
