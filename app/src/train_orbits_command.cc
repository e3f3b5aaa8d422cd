#include "train_orbits_command.h"

#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "config/train_parameters.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/nvh/train_orbit_scan.h"
#include "output_folder.h"
#include "train_operating_point.h"

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

int OrbitsTrain(const OrbitsCommandOptions& options, const TrainSpec& spec) {
  const TrainCommandSettings settings =
      CheckTrainCommandOptions(options.tier, spec, options.method, std::nullopt);
  if (options.period < 1) {
    throw InputError("--period", 0, std::to_string(options.period), "must be >= 1");
  }
  TrainOrbitScanOptions scan;
  scan.periods = options.period;
  scan.transient_cycles = options.transient.value_or(spec.analysis.transient_cycles);
  scan.events = settings.events;
  scan.tier = settings.tier;
  if (scan.transient_cycles < 0) {
    throw InputError("--transient", 0, std::to_string(scan.transient_cycles), "must be >= 0");
  }
  std::optional<AtlasAxis> sweep;
  if (options.sweep) {
    sweep = ParseTrainAxisOption(*options.sweep, "--sweep");
    TrainSpec probe = spec;  // the name's index is checked once, as a usage error
    SetTrainParameter(probe, sweep->parameter, sweep->range.from, "--sweep");
    RequireAxisWithinPitchLineLimit(spec, *sweep, *options.sweep, "--sweep");
  }
  // The transient, then at least one cycle per base period of the --period searched.
  RequireRunLengthOfOptions(spec, LowestInputSpeed(spec, sweep), options.period,
                            scan.transient_cycles, std::nullopt, options.transient);
  const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", false);
  const int count = sweep ? sweep->range.points : 1;
  std::vector<double> values(static_cast<size_t>(count), 0.0);
  for (int i = 0; sweep && i < count; ++i) values[static_cast<size_t>(i)] = AxisValue(*sweep, i);
  const TrainOrbitScanProgress progress = OrbitsTerminalProgress(sweep.has_value());
  const std::vector<TrainOrbitScanPoint> points = ScanTrainPeriodicOrbits(
      count,
      [&](int i) {
        TrainSpec variant = spec;
        if (sweep)
          SetTrainParameter(variant, sweep->parameter, values[static_cast<size_t>(i)], "--sweep");
        return variant;
      },
      scan, progress);
  if (progress) fmt::print(stderr, "\n");
  const std::string parameter = sweep ? sweep->parameter : "operating point";
  nlohmann::json list = nlohmann::json::array();
  int stable = 0, failed = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    list.push_back(PointJson(points[i], values[i]));
    stable += points[i].found() && points[i].orbit.stable ? 1 : 0;
    failed += points[i].ok ? 0 : 1;
  }
  const double common_period = points.front().common_period;
  nlohmann::json doc = {
      {"schema", "gearnvh/2"},
      {"name", spec.name},
      {"file", options.file},
      {"tier", TierName(settings.tier)},
      {"period", options.period},
      {"common_period_s", common_period},
      {"period_s", options.period * common_period},
      {"method", EventMethodName(scan.events)},
      {"multipliers_on", "quotient by the free rotation (its two neutral directions removed)"},
      {"parameter", parameter},
      {"points", list},
      {"stable_points", stable},
      {"failed_points", failed}};
  RequireFinite(doc, "orbits");
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
        "  multipliers on the quotient by the free rotation (its two neutral directions, "
        "multiplier 1 and its Jordan partner, removed)\n",
        spec.name, options.file, options.period, options.period, options.period > 1 ? "s" : "",
        common_period, TierName(settings.tier));
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
