#include "orbits_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "atlas_command.h"
#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/orbit_scan.h"
#include "output_folder.h"
#include "simulate_command.h"
#include "train_command_options.h"
#include "train_orbits_command.h"

namespace gearnvh::app {

namespace {

nlohmann::json PointJson(const OrbitScanPoint& p) {
  const PeriodicOrbit& o = p.orbit;
  nlohmann::json mu = nlohmann::json::array();
  for (const auto& m : o.multipliers) mu.push_back(MultiplierJson(m));
  const bool found = !p.start.empty();
  return {{"value", p.value},
          {"ok", p.ok},
          {"found", found},
          {"start", p.start},
          {"message", p.message},
          {"info", PeriodicOrbitInfoName(o.info)},
          {"iterations", o.iterations},
          {"residual", o.residual},
          {"stable", found && o.stable},
          {"spectral_radius", o.spectral_radius},
          {"multipliers", mu},
          {"nearest_boundary", StabilityBoundaryName(o.nearest_boundary)},
          {"boundary_distance", FiniteOrNull(o.boundary_distance)},
          {"grazing_margin", FiniteOrNull(o.grazing_margin)},
          {"drive_impacts_per_period", o.drive_impacts},
          {"back_impacts_per_period", o.back_impacts},
          {"separation_fraction", o.separation_fraction}};
}

std::string OrbitsCsv(const std::vector<OrbitScanPoint>& points, const std::string& parameter,
                      const DisplayAxis& axis) {
  std::ostringstream os;
  os.precision(12);
  os << parameter << (axis.unit.empty() ? "" : " [" + axis.unit + "]")
     << ",found,stable,spectral_radius,nearest_boundary,boundary_distance,"
     << "grazing_margin,drive_impacts_per_period,back_impacts_per_period,separation_fraction\n";
  for (const OrbitScanPoint& p : points) {
    const PeriodicOrbit& o = p.orbit;
    const bool found = !p.start.empty();
    os << p.value * axis.scale << ',' << (found ? 1 : 0) << ',' << (found && o.stable ? 1 : 0)
       << ',' << o.spectral_radius << ',' << StabilityBoundaryName(o.nearest_boundary) << ','
       << o.boundary_distance << ',' << o.grazing_margin << ',' << o.drive_impacts << ','
       << o.back_impacts << ',' << o.separation_fraction << '\n';
  }
  return os.str();
}

}  // namespace

nlohmann::json MultiplierJson(std::complex<double> mu) {
  return {{"re", mu.real()}, {"im", mu.imag()}, {"abs", std::abs(mu)}};
}

std::string NoStableOrbitText(int period, bool swept) {
  return fmt::format(
      "  No stable period-{} orbit exists at {} (none found by shooting from the settled motion "
      "and continuation).",
      period, swept ? "any point of the sweep" : "this operating point");
}

std::function<void(int, int)> OrbitsTerminalProgress(bool swept) {
  if (!swept || ::isatty(STDERR_FILENO) == 0) return {};
  return [](int done, int total) {
    fmt::print(stderr, "\rorbits: {:3d}% ({}/{} points)", 100 * done / total, done, total);
  };
}

int ReportFailedOrbitPoints(int failed, size_t total) {
  if (failed == 0) return 0;
  std::cerr << "error: " << failed << " of " << total
            << " points could not be computed (listed in the output)\n";
  return 1;
}

void RequireOrbitPeriod(int period, const std::string& field) {
  if (period < 1 || period > kMaxOrbitPeriod) {
    throw InputError(field, 0, std::to_string(period),
                     "must be in [1, " + std::to_string(kMaxOrbitPeriod) + "]");
  }
}

int RunOrbits(const OrbitsCommandOptions& options) {
  return RunReportingErrors(options.file, [&](config::SourceLocations& where) -> int {
    const config::LoadedGearbox loaded = config::LoadAnyGearboxFile(options.file);
    where = loaded.locations;
    if (loaded.schema == 2) return OrbitsTrain(options, loaded.train);
    const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", false);
    const GearboxSpec& spec = *loaded.pair;
    OrbitScanOptions scan;
    scan.input_error_message = UserWording(PairTierNames(options.tier), PairAxisValueText(spec));
    scan.tier = options.tier ? ParseTier(*options.tier) : spec.analysis.tier;
    scan.period = options.period;
    scan.transient_cycles = options.transient.value_or(spec.analysis.transient_cycles);
    scan.events = EventMethodOf(options.method);
    std::optional<AtlasAxis> sweep;
    if (options.sweep) {
      sweep = config::ParseAxisOption(*options.sweep, "--sweep");
      RequirePairAxisOption(spec, *sweep, *options.sweep, "--sweep");
    }
    // The transient, then at least one cycle per base period of the --period searched.
    RequireRunLengthOfOptions(loaded.train, LowestInputSpeed(loaded.train, sweep), options.period,
                              scan.transient_cycles, std::nullopt, options.transient);
    scan.Validate();
    const OrbitScanProgress progress = OrbitsTerminalProgress(sweep.has_value());
    const std::vector<OrbitScanPoint> points = ScanPeriodicOrbits(spec, sweep, scan, progress);
    if (progress) fmt::print(stderr, "\n");
    const std::string parameter = sweep ? sweep->parameter : "operating point";
    const DisplayAxis axis = DisplayAxisFor(parameter, spec);
    nlohmann::json list = nlohmann::json::array();
    int stable = 0, failed = 0;
    for (const OrbitScanPoint& p : points) {
      list.push_back(PointJson(p));
      stable += (!p.start.empty() && p.orbit.stable) ? 1 : 0;
      failed += p.ok ? 0 : 1;
    }
    nlohmann::json doc = {{"name", spec.name},
                          {"file", options.file},
                          {"period", options.period},
                          {"period_mesh_cycles", points.front().orbit.period_cycles},
                          {"period_s", points.front().orbit.period_s},
                          {"parameter", parameter},
                          {"points", list},
                          {"stable_points", stable},
                          {"failed_points", failed}};
    RequireFinite(doc, "orbits");
    if (out) {
      out->Write("orbits.csv", OrbitsCsv(points, parameter, axis));
      out->Write("orbits.json", doc.dump(1) + "\n");
      out->Commit();
    }
    if (options.json) {
      std::cout << doc.dump(1) << "\n";
    } else {
      fmt::print("{}  ({}): period-{} orbits ({}, {:.4g} s per period) at {}, {}\n", spec.name,
                 options.file, options.period,
                 Count(points.front().orbit.period_cycles, "mesh cycle", "mesh cycles"),
                 points.front().orbit.period_s,
                 Format(spec.operating.speed, spec.operating.speed_unit), TorqueText(spec));
      for (const OrbitScanPoint& p : points) {
        const std::string where =
            sweep ? fmt::format("{} = {:.6g} {}: ", parameter, p.value * axis.scale, axis.unit)
                  : "";
        if (!p.ok) {
          fmt::print("  {}failed: {}\n", where, p.message);
          continue;
        }
        if (p.start.empty()) {
          fmt::print("  {}{}\n", where, p.message);
          continue;
        }
        const PeriodicOrbit& o = p.orbit;
        fmt::print(
            "  {}{} (max |mu| = {:.6g}), nearest boundary {} at {:.3g}; impacts per period "
            "{} drive / {} back; from {}\n",
            where, o.stable ? "stable" : "UNSTABLE", o.spectral_radius,
            StabilityBoundaryName(o.nearest_boundary), o.boundary_distance, o.drive_impacts,
            o.back_impacts, p.start);
      }
      if (stable == 0) fmt::print("{}\n", NoStableOrbitText(options.period, sweep.has_value()));
    }
    return ReportFailedOrbitPoints(failed, points.size());
  });
}

}  // namespace gearnvh::app
