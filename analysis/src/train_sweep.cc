#include "gearnvh/analysis/train_sweep.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "gearnvh/analysis/parallel_for.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/analysis/train_transient.h"
#include "gearnvh/analysis/written_numbers.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/train_reduced_tables.h"

namespace gearnvh {
namespace {

// `built`: the train of `base` at some speed of the sweep (GearTrainAtSpeed moves it).
TrainSweepPoint RunPoint(const TrainSpec& base, const GearTrain& built,
                         const TrainSweepOptions& options, double speed, int order_bins) {
  ThrowIfCancelled(options.cancel);  // a speed not started yet
  TrainSweepPoint p;
  p.speed_rad_s = speed;
  p.speed_rpm = Rpm(speed);
  TrainSpec spec = base;
  spec.operating.speed = speed;
  TrainRunOptions run;
  run.cycles = options.cycles;
  run.transient = options.transient;
  run.spectra = false;
  run.transient_warning = false;  // said once for the sweep (RunTrainSweep)
  run.waterfall_samples = options.WaterfallCycles() * run.samples_per_cycle;
  run.events = options.events;
  run.cancel = options.cancel;
  run.tier = options.tier;
  run.allow_slow = true;  // the sweep's cost was checked before any speed ran
  GearTrain train = GearTrainAtSpeed(built, spec);
  // A viscous drag loads the meshes more at higher speeds: the tooth-load limit at this one.
  if (DragDampsFreeRotation(spec, train.topology)) RequireTrainToothLoads(spec, train.topology);
  TrainTableOptions table_options;
  table_options.cancel = options.cancel;
  TrainTables tables = BuildTrainTablesAtTier(spec, train, options.tier, table_options);
  const TrainOperatingPoint op =
      RunTrainOperatingPoint(spec, std::move(train), std::move(tables), run);
  p.ok = op.ok();
  if (!p.ok) p.message = "the run stopped: " + TrainStepperMessage(op.summary);
  p.real_time_ratio = op.wall_s > 0.0 ? op.summary.simulated_time / op.wall_s : 0.0;
  p.recorded_s = op.stats.recorded_time;
  for (int i = 0; i < op.tables.gear_meshes; ++i)
    p.mesh_periods.push_back(op.tables.meshes[static_cast<size_t>(i)].period);
  p.meshes = op.stats.meshes;
  p.loose_gears = op.stats.loose_gears;
  p.couplings = op.couplings;
  std::sort(p.loose_gears.begin(), p.loose_gears.end(),
            [](const auto& a, const auto& b) { return a.body < b.body; });
  for (const AmplitudeSpectrum& s : op.waterfall) {
    const auto bins = std::min<size_t>(static_cast<size_t>(order_bins), s.amplitude.size());
    p.waterfall.emplace_back(s.amplitude.begin(), s.amplitude.begin() + static_cast<long>(bins));
  }
  return p;
}

}  // namespace

void TrainSweepOptions::Validate() const {
  if (cycles < 1) throw InputError(names("cycles"), 0, std::to_string(cycles), "must be >= 1");
  if (transient < 0) {
    throw InputError(names("transient"), 0, std::to_string(transient), "must be >= 0");
  }
  if (waterfall_cycles < 1) {
    throw InputError("TrainSweepOptions.waterfall_cycles", 0, std::to_string(waterfall_cycles),
                     "must be >= 1");
  }
  if (!(max_order >= 0.0)) {
    throw InputError("TrainSweepOptions.max_order", 0, std::to_string(max_order), "must be >= 0");
  }
  if (ranks < 1)
    throw InputError("TrainSweepOptions.ranks", 0, std::to_string(ranks), "must be >= 1");
}

std::vector<double> MeshOrders(const TrainSpec& spec) {
  const TrainTopology topology = AnalyseTrainTopology(spec);
  const double input = std::abs(topology.bodies[static_cast<size_t>(topology.input_body)].speed);
  std::vector<double> orders;
  for (const TrainMesh& m : spec.meshes) {
    const int a = spec.GearIndex(m.gear_a);
    const double speed =
        std::abs(topology.bodies[static_cast<size_t>(topology.gear_body[a])].speed);
    orders.push_back(AsWritten(spec.gears[static_cast<size_t>(a)].gear.teeth * speed / input));
  }
  return orders;
}

double TrainSweepPoint::ImpactsPerCycle(size_t mesh) const {
  const double cycles = recorded_s / mesh_periods[mesh];
  const TrainMeshStatistics& m = meshes[mesh];
  return cycles > 0.0 ? static_cast<double>(m.drive_impacts + m.back_impacts) / cycles : 0.0;
}

int TrainSweepResult::failed() const {
  int n = 0;
  for (const TrainSweepPoint& p : points) n += p.ok ? 0 : 1;
  return n;
}

namespace {

// The run-cost estimate of the sweep; `first` is set to the train it built at the first speed, and
// `transient` (when given) to the transient warning at the highest speed, whose transient is the
// shortest in seconds (TransientDecayWarning).
RunCostEstimate EstimateTrainSweepCost(const TrainSpec& spec, const TrainSweepOptions& options,
                                       std::optional<GearTrain>& first,
                                       std::string* transient = nullptr) {
  const SweepRange& range = spec.analysis.speed_sweep;
  std::optional<RunCostEstimate> cheapest;
  TrainTableOptions table_options;
  table_options.cancel = options.cancel;
  for (double speed : {range.Point(0), range.Point(range.points - 1)}) {
    ThrowIfCancelled(options.cancel);
    TrainSpec at = spec;
    at.operating.speed = speed;
    if (!first) first = BuildGearTrain(at);
    const GearTrain train = GearTrainAtSpeed(*first, at);
    const TrainTables tables = BuildTrainTablesAtTier(at, train, options.tier, table_options);
    const double seconds =
        static_cast<double>(options.cycles + options.transient) * tables.meshes.front().period;
    const RunCostEstimate cost = EstimateRunCost(tables, seconds, &at);
    if (!cheapest || cost.wall_s < cheapest->wall_s) cheapest = cost;
    if (transient != nullptr && speed == std::max(range.Point(0), range.Point(range.points - 1))) {
      *transient = TransientDecayWarning(
          tables, static_cast<double>(options.transient) * tables.meshes.front().period,
          options.transient, options.names("transient"));
    }
  }
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const int threads = options.threads > 0 ? options.threads : static_cast<int>(cores);
  const int share = (range.points + options.ranks - 1) / options.ranks;
  return CombineRunCosts(std::vector<RunCostEstimate>(static_cast<size_t>(share), *cheapest),
                         threads);
}

}  // namespace

RunCostEstimate EstimateTrainSweepCost(const TrainSpec& spec, const TrainSweepOptions& options) {
  std::optional<GearTrain> first;
  return EstimateTrainSweepCost(spec, options, first);
}

TrainSweepResult RunTrainSweep(const TrainSpec& spec, const TrainSweepOptions& options,
                               const TrainSweepProgress& progress, const std::vector<bool>& skip) {
  options.Validate();
  std::optional<GearTrain> first;  // at the first speed: each speed moves it (GearTrainAtSpeed)
  {
    std::string transient;
    const RunCostEstimate cost = EstimateTrainSweepCost(spec, options, first, &transient);
    if (!transient.empty() && options.before_run_warning) {
      const DisplayUnit& unit = spec.operating.speed_unit;
      const SweepRange& range = spec.analysis.speed_sweep;
      options.before_run_warning(fmt::format("at {:.6g} {} (the sweep's highest speed): {}",
                                             std::max(range.from, range.to) * unit.per_si,
                                             unit.symbol, transient));
    }
    const std::string what = options.ranks > 1
                                 ? fmt::format("each process's {} of the sweep's {} speeds",
                                               cost.runs, spec.analysis.speed_sweep.points)
                                 : fmt::format("the sweep's {} speeds", cost.runs);
    const std::string slow = CheckRunCost(cost, options.allow_slow, what, options.names);
    if (!slow.empty() && options.before_run_warning) options.before_run_warning(slow);
  }
  const SweepRange& range = spec.analysis.speed_sweep;
  std::vector<double> speeds(static_cast<size_t>(range.points));
  for (int i = 0; i < range.points; ++i) speeds[static_cast<size_t>(i)] = range.Point(i);
  TrainSweepResult result;
  for (const TrainMesh& m : spec.meshes) result.mesh_names.push_back(m.Name());
  result.speed_scale = range.scale;
  result.mesh_orders = MeshOrders(spec);
  const double fastest = *std::max_element(result.mesh_orders.begin(), result.mesh_orders.end());
  result.order_step = fastest / static_cast<double>(options.WaterfallCycles());
  const double max_order = options.max_order > 0.0 ? options.max_order : 3.5 * fastest;
  const long half = options.WaterfallCycles() * TrainRunOptions{}.samples_per_cycle / 2;
  result.order_bins =
      static_cast<int>(std::min<long>(half, static_cast<long>(max_order / result.order_step))) + 1;
  if (!skip.empty() && skip.size() != speeds.size()) {
    throw std::invalid_argument("RunTrainSweep: skip must have one entry per speed");
  }
  result.points.resize(speeds.size());
  const auto to_run = skip.empty()
                          ? speeds.size()
                          : static_cast<size_t>(std::count(skip.begin(), skip.end(), false));
  SweepProgressCounter counter(static_cast<int>(to_run), progress);
  ParallelFor(speeds.size(), options.threads, [&](size_t i) {
    TrainSweepPoint& p = result.points[i];
    if (!skip.empty() && skip[i]) {
      p.speed_rad_s = speeds[i];
      p.speed_rpm = Rpm(speeds[i]);
      p.message = "skipped";
      return;
    }
    RunSweepPoint(p, speeds[i],
                  [&] { return RunPoint(spec, *first, options, speeds[i], result.order_bins); });
    counter.Tick();
  });
  NameLooseGears(result);
  return result;
}

void NameLooseGears(TrainSweepResult& result) {
  result.loose_gear_names.clear();
  for (const TrainSweepPoint& p : result.points) {
    if (!p.ok) continue;
    for (const TrainLooseGearStatistics& g : p.loose_gears)
      result.loose_gear_names.push_back(g.name);
    break;
  }
}

}  // namespace gearnvh
