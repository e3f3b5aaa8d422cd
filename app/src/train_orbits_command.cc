#include "train_orbits_command.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "config/train_parameters.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/nvh/train_orbit_scan.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "output_folder.h"
#include "train_command_options.h"

namespace gearnvh::app {
namespace {

double SpectralRadius(const TrainOrbit& o) {
  return o.multipliers.size() > 0 ? std::abs(o.multipliers[0]) : 0.0;
}

nlohmann::json PointJson(const TrainOrbitScanPoint& p, double value) {
  const TrainOrbit& o = p.orbit;
  nlohmann::json mu = nlohmann::json::array();
  for (Eigen::Index i = 0; i < o.multipliers.size(); ++i)
    mu.push_back(MultiplierJson(o.multipliers[i]));
  return {{"value", value},
          {"ok", p.ok},
          {"found", p.found()},
          {"start", TrainOrbitStartText(p)},
          {"message", p.message},
          {"info", TrainOrbitInfoName(o.info)},
          {"iterations", o.iterations},
          {"residual", o.residual},
          {"stable", p.found() && o.stable},
          {"spectral_radius", SpectralRadius(o)},
          {"multipliers", mu},
          {"period_s", o.period},
          {"events_per_period", o.events_per_period}};
}

std::string OrbitsCsv(const std::vector<TrainOrbitScanPoint>& points,
                      const std::vector<double>& values, const std::string& parameter) {
  const TrainDisplayAxis d = TrainDisplayAxisFor(parameter);
  std::ostringstream os;
  os.precision(12);
  os << parameter << (d.unit.empty() ? "" : " [" + d.unit + "]")
     << ",found,stable,spectral_radius,events_per_period,iterations,residual\n";
  for (size_t i = 0; i < points.size(); ++i) {
    const TrainOrbitScanPoint& p = points[i];
    os << values[i] * d.scale << ',' << (p.found() ? 1 : 0) << ','
       << (p.found() && p.orbit.stable ? 1 : 0) << ',' << SpectralRadius(p.orbit) << ','
       << p.orbit.events_per_period << ',' << p.orbit.iterations << ',' << p.orbit.residual << '\n';
  }
  return os.str();
}

void PrintPoint(const TrainOrbitScanPoint& p, const std::string& where) {
  if (!p.ok || !p.found()) {
    fmt::print("  {}{}{}\n", where, p.ok ? "no orbit: " : "failed: ", p.message);
    return;
  }
  const TrainOrbit& o = p.orbit;
  fmt::print("  {}{} (max |mu| = {:.6g}), {} contact events per period; from {}\n", where,
             o.stable ? "stable" : "UNSTABLE", SpectralRadius(o), o.events_per_period,
             TrainOrbitStartText(p));
  std::string mu;
  for (Eigen::Index i = 0; i < o.multipliers.size(); ++i) {
    const std::complex<double> m = o.multipliers[i];
    mu += fmt::format("{}{:.6g}{:+.6g}i", i ? ", " : "", m.real(), m.imag());
  }
  fmt::print("    multipliers: {}\n", mu);
}

}  // namespace

TrainOrbitsPlan PlanTrainOrbits(const OrbitsCommandOptions& options, const TrainSpec& spec,
                                const OptionNames& names) {
  const TrainCommandSettings settings =
      CheckTrainCommandOptions(options.tier, spec, options.method, names);
  RequireOrbitPeriod(options.period, names("period"));
  TrainOrbitsPlan plan;
  TrainOrbitScanOptions& scan = plan.scan;
  scan.periods = options.period;
  scan.transient_cycles = options.transient.value_or(spec.analysis.transient_cycles);
  scan.events = settings.events;
  scan.tier = settings.tier;
  if (scan.transient_cycles < 0) {
    throw InputError(names("transient"), 0, std::to_string(scan.transient_cycles), "must be >= 0");
  }
  plan.sweep_option = names("sweep");
  plan.allow_slow = options.allow_slow;
  plan.names = names;
  if (options.sweep) {
    plan.sweep = ParseTrainAxisOption(*options.sweep, plan.sweep_option);
    TrainSpec probe = spec;  // the name's index is checked once, as a usage error
    SetTrainParameter(probe, plan.sweep->parameter, plan.sweep->range.from, plan.sweep_option);
    RequireAxisWithinPitchLineLimit(spec, *plan.sweep, *options.sweep, plan.sweep_option);
  }
  // The transient, then at least one cycle per base period of the --period searched.
  RequireRunLengthOfOptions(spec, LowestInputSpeed(spec, plan.sweep), options.period,
                            scan.transient_cycles, std::nullopt, options.transient, names);
  const int count = plan.sweep ? plan.sweep->range.points : 1;
  plan.values.assign(static_cast<size_t>(count), 0.0);
  for (int i = 0; plan.sweep && i < count; ++i)
    plan.values[static_cast<size_t>(i)] = AxisValue(*plan.sweep, i);
  return plan;
}

std::string CheckTrainOrbitsCost(const TrainSpec& spec, const TrainOrbitsPlan& plan) {
  const GearTrain train = BuildGearTrain(spec);
  const TrainTables tables = BuildTrainTablesAtTier(spec, train, plan.scan.tier);
  const double seconds =
      static_cast<double>(plan.scan.transient_cycles) * tables.meshes.front().period +
      static_cast<double>(plan.scan.periods) * tables.common_period;
  const RunCostEstimate point = EstimateRunCost(tables, seconds, &spec);
  const RunCostEstimate cost =
      CombineRunCosts(std::vector<RunCostEstimate>(plan.values.size(), point), 1);
  return CheckRunCost(cost, plan.allow_slow, fmt::format("the {} orbit points", plan.values.size()),
                      plan.names);
}

std::vector<TrainOrbitScanPoint> RunTrainOrbits(const TrainSpec& spec, const TrainOrbitsPlan& plan,
                                                const TrainOrbitScanProgress& progress) {
  return ScanTrainPeriodicOrbits(
      static_cast<int>(plan.values.size()),
      [&](int i) {
        TrainSpec variant = spec;
        if (plan.sweep) {
          const double value = plan.values[static_cast<size_t>(i)];
          SetTrainParameter(variant, plan.sweep->parameter, value, plan.sweep_option);
          ValidateTrainVariant(variant, {{plan.sweep->parameter, value}});
        }
        return variant;
      },
      plan.scan, progress);
}

nlohmann::json TrainOrbitsDocument(const std::vector<TrainOrbitScanPoint>& points,
                                   const TrainOrbitsPlan& plan, const TrainSpec& spec,
                                   const std::string& file) {
  nlohmann::json list = nlohmann::json::array();
  int stable = 0, failed = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    list.push_back(PointJson(points[i], plan.values[i]));
    stable += points[i].found() && points[i].orbit.stable ? 1 : 0;
    failed += points[i].ok ? 0 : 1;
  }
  // The train's common period: that of the first point that ran (a failed point has none; with
  // an operating.speed sweep it is the first speed's).
  const auto ran =
      std::find_if(points.begin(), points.end(), [](const TrainOrbitScanPoint& p) { return p.ok; });
  const double common_period = ran == points.end() ? 0.0 : ran->common_period;
  const int period = plan.scan.periods;
  return {{"schema", "gearnvh/2"},
          {"name", spec.name},
          {"file", file},
          {"tier", TierName(plan.scan.tier)},
          {"period", period},
          {"common_period_s", common_period},
          {"period_s", period * common_period},
          {"method", EventMethodName(plan.scan.events)},
          {"multipliers_on", DragDampsFreeRotation(spec, AnalyseTrainTopology(spec))
                                 ? "quotient by the free rotation's angle (a viscous drag damps "
                                   "its speed)"
                                 : "quotient by the free rotation (its two neutral directions "
                                   "removed)"},
          {"parameter", plan.sweep ? plan.sweep->parameter : "operating point"},
          {"points", list},
          {"stable_points", stable},
          {"failed_points", failed}};
}

int OrbitsTrain(const OrbitsCommandOptions& options, const TrainSpec& spec) {
  const TrainOrbitsPlan plan = PlanTrainOrbits(options, spec);
  if (const std::string slow = CheckTrainOrbitsCost(spec, plan); !slow.empty())
    fmt::print(stderr, "warning: {}\n", slow);
  const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", false);
  const std::optional<AtlasAxis>& sweep = plan.sweep;
  const std::vector<double>& values = plan.values;
  const TrainOrbitScanProgress progress = OrbitsTerminalProgress(sweep.has_value());
  const std::vector<TrainOrbitScanPoint> points = RunTrainOrbits(spec, plan, progress);
  if (progress) fmt::print(stderr, "\n");
  const nlohmann::json doc = TrainOrbitsDocument(points, plan, spec, options.file);
  RequireFinite(doc, "orbits");
  const auto parameter = doc["parameter"].get<std::string>();
  const auto common_period = doc["common_period_s"].get<double>();
  const auto stable = doc["stable_points"].get<int>(), failed = doc["failed_points"].get<int>();
  if (out) {
    out->Write("orbits.csv", OrbitsCsv(points, values, parameter));
    out->Write("orbits.json", doc.dump(1) + "\n");
    out->Commit();
  }
  if (options.json) {
    std::cout << doc.dump(1) << "\n";
  } else {
    fmt::print(
        "{}  ({}): gear train, period-{} orbits ({} common period{} of {:.4g} s), {}\n"
        "  multipliers on the quotient by the free rotation ({}{})\n",
        spec.name, options.file, options.period, options.period, options.period > 1 ? "s" : "",
        common_period, TierName(plan.scan.tier),
        DragDampsFreeRotation(spec, AnalyseTrainTopology(spec))
            ? "its angle, multiplier 1, removed; a viscous drag damps its speed, whose multiplier "
              "e^(-sigma T) is listed"
            : "its two neutral directions, multiplier 1 and its Jordan partner, removed",
        std::any_of(spec.shafts.begin(), spec.shafts.end(),
                    [](const TrainShaft& s) { return s.fixed; })
            ? ", and each fixed shaft's two"
            : "");
    const TrainDisplayAxis d = sweep ? TrainDisplayAxisFor(parameter) : TrainDisplayAxis{};
    for (size_t i = 0; i < points.size(); ++i) {
      const std::string where =
          sweep ? fmt::format("{} = {:.6g} {}: ", parameter, values[i] * d.scale, d.unit) : "";
      PrintPoint(points[i], where);
    }
    if (stable == 0) fmt::print("{}\n", NoStableOrbitText(options.period, sweep.has_value()));
  }
  return ReportFailedOrbitPoints(failed, points.size());
}

}  // namespace gearnvh::app
