#include "train_operating_point.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include "config/gearbox_loader.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/reduction/train_reduction.h"
#include "gearnvh/solver/train_rate_bound.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "simulate_command.h"
#include "train_load_warnings.h"

namespace gearnvh::app {
namespace {

// The train's model warnings and errors that may unload tooth pairs (the pair's warning, per
// mesh), said once per run.
std::vector<std::string> TrainWarnings(const GearTrain& train, const TrainTables& tables) {
  std::vector<std::string> out = train.warnings;
  for (size_t i = 0; i < tables.meshes.size(); ++i) {
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

// The shaft-order sources of the spectra: the input shaft ("fin") when the file has engine orders
// or its gears carry errors, and every other body whose gears carry runout or pitch errors
// ("f_<body>"), at its nominal rotation frequency.
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
  const double to_hz = 1.0 / (2.0 * std::numbers::pi);
  std::vector<ShaftOrderSource> sources;
  if (!tables.excitation.empty() || carries[static_cast<size_t>(topo.input_body)])
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

}  // namespace

const char* RateTermName(RateTerm term) {
  switch (term) {
    case RateTerm::kStiffness:
      return "stiffness (the highest undamped mode)";
    case RateTerm::kDamping:
      return "damping";
    case RateTerm::kGyroscopic:
      return "gyroscopic moments";
    case RateTerm::kFriction:
      return "tooth friction";
  }
  return "";
}

namespace {

// The node whose disk spins fastest against its own tilt inertia: |w_in G(th_x, th_y)| / I_d, the
// nutation rate a gyroscopic moment drives there, and its body.
void GyroscopicCause(const TrainSpec& spec, RunCostEstimate& out) {
  const GearTrain train = BuildGearTrain(spec);
  const TrainStructure s = AssembleTrainStructure(spec, train);
  const Eigen::MatrixXd G(s.G), M(s.M);
  double best = 0.0;
  for (size_t node = 0; node < s.nodes.size(); ++node) {
    const int x = TrainStructure::Dof(static_cast<int>(node), kThx);
    const int y = TrainStructure::Dof(static_cast<int>(node), kThy);
    const double ip = std::abs(G(x, y));
    const double id = std::min(M(x, x), M(y, y));
    if (!(ip > 0.0) || !(id > 0.0)) continue;
    const double rate = std::abs(spec.operating.speed) * ip / id;
    if (rate <= best) continue;
    best = rate;
    const int body = s.node_body[node];
    out.cause_body = body;
    out.cause_body_name = train.topology.bodies[static_cast<size_t>(body)].name;
    // G is per unit input speed: spin w_b / w_in times I_p.
    const double spin =
        train.topology.bodies[static_cast<size_t>(body)].speed / spec.operating.speed;
    out.cause_body_inertia = spin != 0.0 ? ip / std::abs(spin) : 0.0;
    out.cause_nutation_rate = rate;
  }
}

}  // namespace

RunCostEstimate EstimateRunCost(const TrainTables& t, double simulated_s, const TrainSpec* spec) {
  RunCostEstimate out;
  out.tier = t.tier;
  out.state_dim = t.m;
  out.simulated_s = simulated_s;
  if (t.n == 0) return out;
  for (const TrainMeshTable& mt : t.meshes)
    out.fastest_mesh_hz = std::max(out.fastest_mesh_hz, 1.0 / mt.period);
  // The tuple the run starts in with every mesh in drive: segment 0 of every mesh at t = 0.
  const std::vector<int> segments(t.meshes.size(), 0);
  const std::vector<ContactState> drive(t.meshes.size(), ContactState::kDrive);
  const TuplePencil pencil = AssembleTuplePencil(t, segments, drive);
  const double damping = DampingRateBound(t, pencil.C);
  const TupleRateBound bound = BoundTupleRate(t, pencil, damping);
  out.mode_hz = bound.stiffness_frequency / (2.0 * std::numbers::pi);
  out.rho = bound.rho;
  out.substep_s = bound.rho > 0.0 ? 0.5 / bound.rho : 0.0;
  // rho's terms (BoundTupleRate): w, the symmetric damping, the skew (gyroscopic) part of C_0 and
  // friction's share.
  const double gyroscopic = GyroscopicRateBound(t);
  const std::pair<RateTerm, double> terms[] = {{RateTerm::kStiffness, bound.stiffness_frequency},
                                               {RateTerm::kDamping, damping - gyroscopic},
                                               {RateTerm::kGyroscopic, gyroscopic},
                                               {RateTerm::kFriction, bound.friction_rate}};
  for (const auto& [term, rate] : terms) {
    if (rate > out.dominant_rate) {
      out.dominant = term;
      out.dominant_rate = rate;
    }
  }
  // The body that moves most in that mode: its eigenvector of M^-1/2 K M^-1/2, back to angles.
  const Eigen::VectorXd scale = t.inertia.cwiseSqrt().cwiseInverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scale.asDiagonal() * pencil.K *
                                                           scale.asDiagonal());
  if (eig.info() != Eigen::Success) {
    RunCostEstimate failed;
    failed.simulated_s = simulated_s;
    return failed;
  }
  const Eigen::VectorXd x = scale.cwiseProduct(eig.eigenvectors().col(t.n - 1));
  Eigen::Index body = 0;
  (t.body_angles * x).cwiseAbs().maxCoeff(&body);
  out.body = static_cast<int>(body);
  out.cause_body = out.body;
  out.cause_body_name = t.body_names[static_cast<size_t>(body)];
  out.cause_body_inertia = t.body_inertia[body];
  if (out.dominant == RateTerm::kGyroscopic && spec != nullptr) GyroscopicCause(*spec, out);
  if (out.substep_s > 0.0) {
    out.substeps = simulated_s / out.substep_s;
    const double m = static_cast<double>(t.m);
    out.wall_s = out.substeps * kSubstepSecondsPerState2 * m * m;
  }
  return out;
}

RunCostEstimate CombineRunCosts(const std::vector<RunCostEstimate>& runs, int parallel) {
  if (runs.empty()) return {};
  const auto costliest = std::max_element(
      runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.wall_s < b.wall_s; });
  RunCostEstimate out = *costliest;
  out.simulated_s = out.substeps = out.wall_s = 0.0;
  out.runs = 0;
  for (const RunCostEstimate& r : runs) {
    out.simulated_s += r.simulated_s;
    out.substeps += r.substeps;
    out.wall_s += r.wall_s;
    out.runs += r.runs;
  }
  out.wall_s /= std::max(1, std::min(parallel, out.runs));
  return out;
}

namespace {

std::string Duration(double s) {
  if (s < 120.0) return fmt::format("{:.3g} s", s);
  if (s < 3600.0) return fmt::format("{:.3g} min", s / 60.0);
  if (s < 2.0 * 86400.0) return fmt::format("{:.3g} h", s / 3600.0);
  if (s < 2.0 * 365.25 * 86400.0) return fmt::format("{:.3g} days", s / 86400.0);
  return fmt::format("{:.3g} years", s / (365.25 * 86400.0));
}

}  // namespace

std::string RunCostText(const RunCostEstimate& c, const std::string& what) {
  std::string cause;
  switch (c.dominant) {
    case RateTerm::kStiffness:
    case RateTerm::kDamping:
    case RateTerm::kFriction:
      cause = fmt::format(
          "{}: the highest mode of the train is {:.4g} Hz, {:.0f}x the fastest mesh frequency "
          "({:.4g} Hz), mostly body {}{}",
          RateTermName(c.dominant), c.mode_hz,
          c.fastest_mesh_hz > 0.0 ? c.mode_hz / c.fastest_mesh_hz : 0.0, c.fastest_mesh_hz,
          c.cause_body_name,
          c.cause_body_inertia > 0.0
              ? fmt::format(", inertia {:.3g} kg m² (a tiny inertia on stiff meshes makes a very "
                            "high mode; check the inertias)",
                            c.cause_body_inertia)
              : "");
      break;
    case RateTerm::kGyroscopic:
      cause = c.cause_body_name.empty()
                  ? std::string("gyroscopic moments of the bodies at their speeds")
                  : fmt::format(
                        "gyroscopic moments: body {} (polar inertia {:.3g} kg m²) spins at "
                        "{:.3g} rad/s against its own tilt inertia (a nutation of |w| I_p / I_d; "
                        "check its inertias)",
                        c.cause_body_name, c.cause_body_inertia, c.cause_nutation_rate);
      break;
  }
  return fmt::format(
      "{} would take about {} ({:.3g} dense sub-steps of at most {:.3g} s for the {:.4g} s "
      "simulated, state dimension {}; estimated at {:g} s per sub-step per squared state "
      "dimension); the sub-step is half the inverse of the bound on the generator's spectral "
      "radius ({:.4g} 1/s), dominated by {}",
      what, Duration(c.wall_s), c.substeps, c.substep_s, c.simulated_s, c.state_dim,
      kSubstepSecondsPerState2, c.rho, cause);
}

std::string CheckRunCost(const RunCostEstimate& cost, bool allow_slow, const std::string& what,
                         const TrainOptionNames& names) {
  if (!(cost.wall_s > kSlowRunWarnSeconds)) return {};
  const std::string text = RunCostText(cost, what);
  if (cost.wall_s > kSlowRunRefuseSeconds && !allow_slow) {
    throw InputError(names("allow-slow"), 0, "",
                     fmt::format("not given, and {}; refused: more than {} without {} (fewer "
                                 "cycles, a lower tier or a corrected inertia make it shorter)",
                                 text, Duration(kSlowRunRefuseSeconds), names("allow-slow")));
  }
  return text;
}

double LowestInputSpeed(const TrainSpec& spec, const std::optional<AtlasAxis>& x,
                        const std::optional<AtlasAxis>& y) {
  double lowest = spec.operating.speed;
  bool varied = false;
  for (const std::optional<AtlasAxis>* axis : {&x, &y}) {
    if (!*axis || (*axis)->parameter != "operating.speed") continue;
    const double low = std::min((*axis)->range.from, (*axis)->range.to);
    lowest = varied ? std::min(lowest, low) : low;
    varied = true;
  }
  return lowest;
}

void RequireAxisWithinPitchLineLimit(const TrainSpec& spec, const AtlasAxis& axis,
                                     const std::string& text, const std::string& field,
                                     const std::string& mesh) {
  if (axis.parameter != "operating.speed") return;
  const FastestMesh fastest = FastestPitchLine(spec, AnalyseTrainTopology(spec));
  const double speed = std::max(std::abs(axis.range.from), std::abs(axis.range.to));
  RequirePitchLineVelocity(field, speed, config::SpeedUnitOfAxisOption(text),
                           fastest.velocity_per_speed, mesh.empty() ? fastest.name : mesh);
}

void RequireCycleCounts(long cycles, long min_cycles, long transient,
                        const TrainOptionNames& names) {
  if (cycles < min_cycles) {
    throw InputError(names("cycles"), 0, std::to_string(cycles),
                     "must be >= " + std::to_string(min_cycles));
  }
  if (transient < 0) {
    throw InputError(names("transient"), 0, std::to_string(transient), "must be >= 0");
  }
}

void RequireRunLengthOfOptions(const TrainSpec& spec, double lowest_speed, long cycles,
                               long transient, const std::optional<long>& cycles_option,
                               const std::optional<long>& transient_option,
                               const TrainOptionNames& names) {
  if (!cycles_option && !transient_option) return;
  const double hz = FirstMeshFrequency(spec, AnalyseTrainTopology(spec), lowest_speed);
  const double seconds = static_cast<double>(cycles + transient) / hz;
  if (seconds <= GearboxLimits::kMaxSimulatedSeconds) return;
  const bool transient_named = transient_option.has_value();
  throw InputError(
      names(transient_named ? "transient" : "cycles"), 0,
      std::to_string(transient_named ? *transient_option : *cycles_option),
      fmt::format("makes the {} cycles of the first mesh ({}, {}, cycles + transient) last "
                  "{:.3g} s of simulated time at {} (mesh frequency {:.3g} Hz); the limit is {} "
                  "s, as for analysis.cycles + transient_cycles",
                  cycles + transient, "meshes[0]", spec.meshes.front().Name(), seconds,
                  InUnit(lowest_speed, spec.operating.speed_unit), hz,
                  GearboxLimits::kMaxSimulatedSeconds));
}

TrainCommandSettings CheckTrainCommandOptions(const std::optional<std::string>& tier_option,
                                              const TrainSpec& spec, LadderMethod method,
                                              const std::optional<std::string>& uff,
                                              const TrainOptionNames& names) {
  const Tier tier = tier_option ? ParseTier(*tier_option, names("tier")) : spec.analysis.tier;
  if (tier != Tier::kTier1 &&
      !TrainTierAvailable(AssembleTrainStructure(spec, BuildGearTrain(spec)), tier)) {
    throw InputError(tier_option ? names("tier") : "analysis.tier", 0,
                     tier_option ? *tier_option : TierName(tier),
                     "tiers 4, 5, N20 simple and N20 MTA need an elastic shaft in the train");
  }
  if (uff)
    throw InputError(names("uff"), 0, *uff, "UFF export is not available for gear trains yet");
  return {tier, EventMethodOf(method)};
}

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
  SpectrumWindow window;
  if (options.spectra) {
    window = PlanWindow(tables, recorder.sample_interval(), start, end,
                        options.max_spectrum_samples, options.cycles);
  }
  const long kept = window.periods * window.samples_per_period;
  op.memory = {{{"TE samples", TrainRecorder::TeSeriesBytes(tables.meshes.size(), kept)},
                {"TE spectrum", SpectrumBytes(kept)}},
               kept};
  if (options.before_run_memory) {
    if (const std::string warning = options.before_run_memory(op.memory); !warning.empty()) {
      op.warnings.push_back(warning);
      if (options.before_run_warning) options.before_run_warning(warning);
    }
  }
  if (kept > 0) recorder.KeepTeSeries(window.from_time, kept);
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
  if (!options.spectra) return op;

  // Shaft-order content comes from the engine orders (orders of the input shaft, up to the
  // highest) and from the runout and pitch errors of gears (orders of the bodies that carry
  // them). The common period holds whole revolutions of both, so their lines sit on bins.
  const bool errors = tables.error_inputs > 0;
  op.sideband_options.shaft_order_sources = !tables.excitation.empty() || errors;
  for (const ExcitationOrder& e : tables.excitation) {
    op.sideband_options.orders =
        std::max(op.sideband_options.orders, static_cast<int>(std::ceil(e.order)));
  }
  const std::vector<ShaftOrderSource> sources = ShaftOrderSources(spec, op.train, tables);
  op.sideband_window_common_periods = window.periods;
  op.sidebands.resize(tables.meshes.size());
  const long window_samples = window.periods * window.samples_per_period;
  const bool complete = ok && window.periods > 0 &&
                        static_cast<long>(recorder.te_series().front().size()) == window_samples;
  if (complete) {
    SpectrumAnalyzer analyzer(static_cast<int>(window_samples));
    const double rate = 1.0 / recorder.sample_interval();
    for (size_t i = 0; i < tables.meshes.size(); ++i) {
      ThrowIfCancelled(options.cancel);  // an FFT of up to 2^21 samples per mesh
      const TrainMeshTable& mt = tables.meshes[i];
      const AmplitudeSpectrum spectrum = analyzer.Analyze(recorder.te_series()[i], rate);
      op.sidebands[i].window_cycles =
          std::llround(static_cast<double>(window.periods) * tables.common_period / mt.period);
      SidebandOptions mesh_options = op.sideband_options;
      mesh_options.scale = mt.half_backlash;
      op.sidebands[i].rows = SidebandTable(spectrum, 1.0 / mt.period, sources, mesh_options);
    }
  } else if (!window.note.empty()) {
    op.sideband_notes.push_back(window.note);
  } else {
    op.sideband_notes.push_back("no spectrum: the run stopped before the end of the record");
  }
  op.sideband_notes.push_back(
      !op.sideband_options.shaft_order_sources
          ? "the train has no runout, pitch error or engine order: no shaft-order line or "
            "sideband can arise, so only each mesh's harmonics are listed"
          : "shaft-order lines and sidebands come from the engine orders (orders j fin of the "
            "input shaft) and the gears' runout and pitch errors (orders of the bodies that carry "
            "them, f_<body>); every mesh lists the lines of every source");
  op.sideband_notes.push_back(fmt::format(
      "lines are listed when {:g} dB above the median of the {} bins around them and above {:g} "
      "dB relative to the strongest bin (rounding of the exact solution lies near -300 dB)",
      op.sideband_options.prominence_db, 2 * op.sideband_options.background_bins,
      op.sideband_options.rounding_floor_db));
  return op;
}

nlohmann::json TrainSidebandsJson(const std::vector<SidebandRow>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const SidebandRow& r : rows) {
    out.push_back({{"label", r.label},
                   {"frequency_hz", r.frequency_hz},
                   {"amplitude_m", r.amplitude},
                   {"db_re_1um", r.db_re_1um},
                   {"background_m", r.background}});
  }
  return out;
}

nlohmann::json TrainMeshesJson(const TrainOperatingPoint& op) {
  const TrainStatistics& stats = op.stats;
  const TrainTables& tables = op.tables;
  nlohmann::json meshes = nlohmann::json::array();
  for (size_t i = 0; i < stats.meshes.size(); ++i) {
    const TrainMeshStatistics& m = stats.meshes[i];
    const double mesh_cycles = stats.recorded_time / tables.meshes[i].period;
    nlohmann::json mesh = {
        {"name", m.name},
        {"mesh_period_s", tables.meshes[i].period},
        {"te",
         {{"mean", m.te_mean},
          {"rms", m.te_rms},
          {"peak_to_peak", m.te_peak_to_peak},
          {"half_backlash", tables.meshes[i].half_backlash}}},
        {"mesh_force", {{"mean", m.force_mean}, {"max", m.force_max}}},
        {"rattle",
         {{"drive_impacts", m.drive_impacts},
          {"back_impacts", m.back_impacts},
          {"separations", m.separations},
          {"grazing", m.grazing},
          {"drive_impacts_per_cycle", mesh_cycles > 0 ? m.drive_impacts / mesh_cycles : 0.0},
          {"back_impacts_per_cycle", mesh_cycles > 0 ? m.back_impacts / mesh_cycles : 0.0},
          {"separation_fraction", m.free_time_fraction},
          {"impact_velocity_rms", m.impact_velocity_rms},
          {"impact_velocity_max", m.impact_velocity_max}}}};
    if (i < op.sidebands.size()) {
      mesh["sidebands"] = TrainSidebandsJson(op.sidebands[i].rows);
      mesh["sideband_window_cycles"] = op.sidebands[i].window_cycles;
    }
    meshes.push_back(mesh);
  }
  return meshes;
}

nlohmann::json TrainLooseGearsJson(const std::vector<TrainLooseGearStatistics>& gears) {
  nlohmann::json loose = nlohmann::json::array();
  for (const TrainLooseGearStatistics& g : gears) {
    loose.push_back({{"name", g.name},
                     {"rank", g.rank},
                     {"rattle_index", g.rattle_index},
                     {"impacts", g.impacts}});
  }
  return loose;
}

}  // namespace gearnvh::app
