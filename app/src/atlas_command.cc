#include "atlas_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "atomic_file.h"
#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/atlas.h"
#include "simulate_command.h"

namespace gearnvh::app {

namespace {

nlohmann::json AxisJson(const AtlasAxis& a) {
  nlohmann::json values = nlohmann::json::array();
  for (int i = 0; i < a.range.points; ++i) values.push_back(AxisValue(a, i));
  return {{"parameter", a.parameter},
          {"from", a.range.from},
          {"to", a.range.to},
          {"points", a.range.points},
          {"values_si", values}};
}

nlohmann::json CellJson(const AtlasCell& c) {
  return {{"ix", c.ix},
          {"iy", c.iy},
          {"x", c.x},
          {"y", c.y},
          {"ok", c.ok},
          {"message", c.message},
          {"lyapunov_per_s", c.lyapunov_per_s},
          {"lyapunov_per_forcing_cycle", c.lyapunov_per_forcing_cycle},
          {"lyapunov_standard_error", c.lyapunov_standard_error},
          {"drive_impacts_per_cycle", c.drive_impacts_per_cycle},
          {"back_impacts_per_cycle", c.back_impacts_per_cycle},
          {"rattle_index_j", c.rattle_index},
          {"impact_velocity_rms", c.impact_velocity_rms},
          {"separation_fraction", c.separation_fraction},
          {"regime", c.regime},
          {"wall_s", c.wall_s}};
}

}  // namespace

std::string AtlasCsv(const AtlasResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "ix,iy," << r.x.parameter << ',' << r.y.parameter
     << ",ok,lyapunov_per_s,lyapunov_per_forcing_cycle,lyapunov_standard_error,"
        "drive_impacts_per_cycle,back_impacts_per_cycle,rattle_index_j,impact_velocity_rms,"
        "separation_fraction,regime,message\n";
  for (const AtlasCell& c : r.cells) {
    std::string message = c.message;
    for (char& ch : message) {
      if (ch == '"' || ch == '\n') ch = '\'';
    }
    os << c.ix << ',' << c.iy << ',' << c.x << ',' << c.y << ',' << (c.ok ? 1 : 0) << ','
       << c.lyapunov_per_s << ',' << c.lyapunov_per_forcing_cycle << ','
       << c.lyapunov_standard_error << ',' << c.drive_impacts_per_cycle << ','
       << c.back_impacts_per_cycle << ',' << c.rattle_index << ',' << c.impact_velocity_rms << ','
       << c.separation_fraction << ',' << c.regime << ",\"" << message << "\"\n";
  }
  return os.str();
}

namespace {

char RegimeLetter(const AtlasCell& c) {
  if (!c.ok) return 'X';
  if (c.regime == "chaotic") return 'C';
  if (c.regime == "double-sided") return 'D';
  if (c.regime == "single-sided") return 'S';
  return '.';
}

}  // namespace

nlohmann::json AtlasJson(const AtlasResult& r, const AtlasOptions& o) {
  nlohmann::json cells = nlohmann::json::array();
  std::map<std::string, int> regimes;
  for (const AtlasCell& c : r.cells) {
    cells.push_back(CellJson(c));
    ++regimes[c.ok ? c.regime : "failed"];
  }
  return {{"x", AxisJson(r.x)},
          {"y", AxisJson(r.y)},
          {"cells", cells},
          {"regime_counts", regimes},
          {"failed_cells", r.Failed()},
          {"cycles_per_cell", o.cycles},
          {"transient_cycles", o.transient_cycles},
          {"chaos_threshold_per_forcing_cycle", o.chaos_threshold},
          {"method", o.method},
          {"threads", r.threads},
          {"wall_s", r.wall_s}};
}

int RunAtlas(const AtlasCommandOptions& options) {
  return RunReportingErrors(options.file, [&]() -> int {
    const GearboxSpec spec = config::LoadGearboxFile(options.file);
    AtlasOptions atlas;
    atlas.tier = options.tier ? ParseTier(*options.tier) : spec.analysis.tier;
    atlas.cycles = options.cycles.value_or(atlas.cycles);
    atlas.transient_cycles = options.transient.value_or(atlas.transient_cycles);
    atlas.threads = options.jobs;
    atlas.method = options.method == "fused" ? "v3" : options.method;
    std::optional<AtlasAxis> x = spec.analysis.atlas_x, y = spec.analysis.atlas_y;
    if (options.x) x = config::ParseAxisOption(*options.x, "--x");
    if (options.y) y = config::ParseAxisOption(*options.y, "--y");
    if (!x || !y) {
      throw InputError("analysis.atlas", 0, "(missing)",
                       "an atlas needs two axes: analysis.atlas.x and .y in the file, or --x "
                       "and --y");
    }
    if (x->parameter == y->parameter) {
      throw InputError("--y", 0, y->parameter, "must differ from the x parameter");
    }
    atlas.Validate();
    const bool on_terminal = ::isatty(STDERR_FILENO) != 0;
    AtlasProgress progress;
    if (on_terminal) {
      progress = [](int done, int total) {
        fmt::print(stderr, "\ratlas: {:3d}% ({}/{} cells)", 100 * done / total, done, total);
      };
    }
    const AtlasResult result = RunChaosAtlas(spec, *x, *y, atlas, progress);
    if (on_terminal) fmt::print(stderr, "\n");
    nlohmann::json doc = AtlasJson(result, atlas);
    doc["name"] = spec.name;
    doc["file"] = options.file;
    if (options.out) {
      std::filesystem::create_directories(*options.out);
      const std::filesystem::path dir(*options.out);
      WriteFileAtomically((dir / "atlas.csv").string(), AtlasCsv(result));
      WriteFileAtomically((dir / "atlas.json").string(), doc.dump(1) + "\n");
    }
    if (options.json) {
      std::cout << doc.dump(1) << "\n";
    } else {
      fmt::print("{}  ({}): chaos atlas, {} x {} cells, {} cycles each, {} threads, {:.1f} s\n",
                 spec.name, options.file, x->range.points, y->range.points, atlas.cycles,
                 result.threads, result.wall_s);
      fmt::print("  rows: {} from {:g} to {:g} (SI); columns: {} from {:g} to {:g} (SI)\n",
                 y->parameter, y->range.to, y->range.from, x->parameter, x->range.from,
                 x->range.to);
      fmt::print("  . no impact  S single-sided  D double-sided  C chaotic  X failed\n");
      for (int iy = y->range.points - 1; iy >= 0; --iy) {
        std::string row;
        for (int ix = 0; ix < x->range.points; ++ix) {
          row += RegimeLetter(result.cells[static_cast<size_t>(iy * x->range.points + ix)]);
        }
        fmt::print("  {}\n", row);
      }
      for (const AtlasCell& c : result.cells) {
        if (!c.ok) fmt::print("  cell ({}, {}) failed: {}\n", c.ix, c.iy, c.message);
      }
    }
    if (result.Failed() > 0) {
      std::cerr << "error: " << result.Failed() << " of " << result.cells.size()
                << " atlas cells failed (listed in the output)\n";
      return 1;
    }
    return 0;
  });
}

}  // namespace gearnvh::app
