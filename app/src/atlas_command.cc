#include "atlas_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "atomic_file.h"
#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/nvh/rattle.h"
#include "mpi_context.h"
#include "output_folder.h"
#include "simulate_command.h"
#include "train_atlas_command.h"
#include "train_operating_point.h"

namespace gearnvh::app {

nlohmann::json AtlasAxisJson(const AtlasAxis& a) {
  nlohmann::json values = nlohmann::json::array();
  for (int i = 0; i < a.range.points; ++i) values.push_back(AxisValue(a, i));
  return {{"parameter", a.parameter},
          {"from", a.range.from},
          {"to", a.range.to},
          {"points", a.range.points},
          {"scale", a.range.scale == AxisScale::kLog ? "log" : "linear"},
          {"values_si", values}};
}

namespace {

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
          {"regime", c.ok ? RattleRegimeName(c.regime) : ""},
          {"wall_s", c.wall_s}};
}

}  // namespace

std::string AtlasCsv(const AtlasResult& r, const GearboxSpec& spec) {
  const DisplayAxis ax = DisplayAxisFor(r.x.parameter, spec);
  const DisplayAxis ay = DisplayAxisFor(r.y.parameter, spec);
  auto header = [](const std::string& parameter, const DisplayAxis& a) {
    return a.unit.empty() ? parameter : parameter + " [" + a.unit + "]";
  };
  std::ostringstream os;
  os.precision(12);
  os << "ix,iy," << header(r.x.parameter, ax) << ',' << header(r.y.parameter, ay)
     << ",ok,lyapunov_per_s,lyapunov_per_forcing_cycle,lyapunov_standard_error,"
        "drive_impacts_per_cycle,back_impacts_per_cycle,rattle_index_j,impact_velocity_rms,"
        "separation_fraction,regime,message\n";
  for (const AtlasCell& c : r.cells) {
    os << c.ix << ',' << c.iy << ',' << c.x * ax.scale << ',' << c.y * ay.scale << ','
       << (c.ok ? 1 : 0) << ',' << c.lyapunov_per_s << ',' << c.lyapunov_per_forcing_cycle << ','
       << c.lyapunov_standard_error << ',' << c.drive_impacts_per_cycle << ','
       << c.back_impacts_per_cycle << ',' << c.rattle_index << ',' << c.impact_velocity_rms << ','
       << c.separation_fraction << ',' << (c.ok ? RattleRegimeName(c.regime) : "") << ','
       << CsvQuoted(c.message) << '\n';
  }
  return os.str();
}

std::string CsvQuoted(std::string text) {
  for (char& ch : text) {
    if (ch == '"' || ch == '\n') ch = '\'';
  }
  return '"' + text + '"';
}

char RegimeLetter(bool ok, RattleRegime regime) {
  if (!ok) return 'X';
  switch (regime) {
    case RattleRegime::kNoImpact:
      return '.';
    case RattleRegime::kSingleSided:
      return 'S';
    case RattleRegime::kDoubleSided:
      return 'D';
    case RattleRegime::kChaotic:
      return 'C';
  }
  return '?';
}

RattleRegime RegimeFromJson(const nlohmann::json& regime) {
  const std::string name = regime.get<std::string>();
  const std::optional<RattleRegime> r = RattleRegimeFromName(name);
  if (!r) throw std::runtime_error("unknown rattle regime \"" + name + "\"");
  return *r;
}

void PrintRegimeMap(int nx, int ny, const std::function<char(int)>& letter, bool legend) {
  if (legend) fmt::print("  . no impact  S single-sided  D double-sided  C chaotic  X failed\n");
  for (int iy = ny - 1; iy >= 0; --iy) {
    std::string row;
    for (int ix = 0; ix < nx; ++ix) row += letter(iy * nx + ix);
    fmt::print("  {}\n", row);
  }
}

int ReportFailedAtlasCells(int failed, size_t total) {
  if (failed == 0) return 0;
  std::cerr << "error: " << failed << " of " << total
            << " atlas cells failed (listed in the output)\n";
  return 1;
}

AtlasProgress AtlasTerminalProgress(int rank, int ranks) {
  if (rank != 0 || ::isatty(STDERR_FILENO) == 0) return {};
  return [ranks](int done, int todo) {
    fmt::print(stderr, "\ratlas: {:3d}% ({}/{} cells{})", 100 * done / std::max(todo, 1), done,
               todo, ranks > 1 ? fmt::format(" on rank 0 of {}", ranks) : "");
  };
}

nlohmann::json AtlasJson(const AtlasResult& r, const AtlasOptions& o) {
  nlohmann::json cells = nlohmann::json::array();
  std::map<std::string, int> regimes;
  for (const AtlasCell& c : r.cells) {
    cells.push_back(CellJson(c));
    ++regimes[c.ok ? RattleRegimeName(c.regime) : "failed"];
  }
  return {{"x", AtlasAxisJson(r.x)},
          {"y", AtlasAxisJson(r.y)},
          {"cells", cells},
          {"regime_counts", regimes},
          {"failed_cells", r.Failed()},
          {"cycles_per_cell", o.cycles},
          {"transient_cycles", o.transient_cycles},
          {"chaos_threshold_per_forcing_cycle", o.chaos_threshold},
          {"method", EventMethodName(o.events)},
          {"threads", r.threads},
          {"wall_s", r.wall_s}};
}

namespace {

AtlasCell CellFromJson(const nlohmann::json& j) {
  AtlasCell c;
  c.ix = j.at("ix").get<int>();
  c.iy = j.at("iy").get<int>();
  c.x = j.at("x").get<double>();
  c.y = j.at("y").get<double>();
  c.ok = j.at("ok").get<bool>();
  c.message = j.at("message").get<std::string>();
  c.lyapunov_per_s = j.at("lyapunov_per_s").get<double>();
  c.lyapunov_per_forcing_cycle = j.at("lyapunov_per_forcing_cycle").get<double>();
  c.lyapunov_standard_error = j.at("lyapunov_standard_error").get<double>();
  c.drive_impacts_per_cycle = j.at("drive_impacts_per_cycle").get<double>();
  c.back_impacts_per_cycle = j.at("back_impacts_per_cycle").get<double>();
  c.rattle_index = j.at("rattle_index_j").get<double>();
  c.impact_velocity_rms = j.at("impact_velocity_rms").get<double>();
  c.separation_fraction = j.at("separation_fraction").get<double>();
  if (c.ok) c.regime = RegimeFromJson(j.at("regime"));
  c.wall_s = j.at("wall_s").get<double>();
  return c;
}

// The checkpoint of an atlas run: DIR/.atlas-checkpoint/settings.json (what was asked; a resume
// with other settings is refused) and one cells-rank-R.jsonl per rank, one computed cell per line
// (flushed as it completes, so a killed run loses only the cells in flight).
struct Checkpoint {
  std::filesystem::path dir;
  std::string settings;
};

std::string SettingsKey(const std::string& file_text, const AtlasAxis& x, const AtlasAxis& y,
                        const AtlasOptions& o) {
  const nlohmann::json j = {{"file_hash", std::to_string(std::hash<std::string>{}(file_text))},
                            {"x", AtlasAxisJson(x)},
                            {"y", AtlasAxisJson(y)},
                            {"cycles", o.cycles},
                            {"transient", o.transient_cycles},
                            {"method", EventMethodName(o.events)},
                            {"tier", static_cast<int>(o.tier)},
                            {"chaos_threshold", o.chaos_threshold}};
  return j.dump();
}

// Rank 0: prepares the checkpoint and returns the cells already computed (resume).
std::vector<AtlasCell> PrepareCheckpoint(const Checkpoint& cp, bool resume, int total) {
  namespace fs = std::filesystem;
  std::vector<AtlasCell> done;
  const fs::path settings = cp.dir / "settings.json";
  if (resume && fs::exists(settings)) {
    std::ifstream in(settings);
    std::stringstream buffer;
    buffer << in.rdbuf();
    if (buffer.str() != cp.settings + "\n") {
      throw InputError("--resume", 0, cp.dir.string(),
                       "the checkpoint was made with other settings (file, axes, cycles, method "
                       "or tier); run without --resume to start over");
    }
    for (const auto& entry : fs::directory_iterator(cp.dir)) {
      if (entry.path().extension() != ".jsonl") continue;
      std::ifstream cells(entry.path());
      std::string line;
      while (std::getline(cells, line)) {
        try {
          const AtlasCell c = CellFromJson(nlohmann::json::parse(line));
          if (c.ok && c.ix + 0 >= 0 && c.iy >= 0) done.push_back(c);
        } catch (const std::exception&) {
          // A line cut short by the kill: that cell is computed again.
        }
      }
    }
    (void)total;
    return done;
  }
  fs::remove_all(cp.dir);
  fs::create_directories(cp.dir);
  WriteFileAtomically(settings.string(), cp.settings + "\n");
  return done;
}

}  // namespace

void RequirePairAxisOption(const GearboxSpec& spec, const AtlasAxis& axis, const std::string& text,
                           const std::string& field) {
  config::RequireVariableParameter(spec, axis.parameter, field);
  RequireAxisWithinPitchLineLimit(TrainOf(spec), axis, text, field, "the mesh");
}

int RunAtlas(const AtlasCommandOptions& options) {
  const int rank = MpiContext::Rank(), ranks = MpiContext::Size();
  int code = RunReportingErrors(options.file, [&](config::SourceLocations& where) -> int {
    const config::LoadedGearbox loaded = config::LoadAnyGearboxFile(options.file);
    where = loaded.locations;
    if (loaded.schema == 2) return AtlasTrain(options, loaded.train);
    const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", true);
    const GearboxSpec& spec = *loaded.pair;
    AtlasOptions atlas;
    atlas.input_error_message = UserWording(PairTierNames(options.tier), PairAxisValueText(spec));
    atlas.tier = options.tier ? ParseTier(*options.tier) : spec.analysis.tier;
    atlas.cycles = options.cycles.value_or(atlas.cycles);
    atlas.transient_cycles = options.transient.value_or(atlas.transient_cycles);
    atlas.threads = options.jobs;
    atlas.events = EventMethodOf(options.method);
    std::optional<AtlasAxis> x = spec.analysis.atlas_x, y = spec.analysis.atlas_y;
    if (options.x) x = config::ParseAxisOption(*options.x, "--x");
    if (options.y) y = config::ParseAxisOption(*options.y, "--y");
    if (!x || !y) {
      throw InputError("analysis.atlas", 0, "(missing)",
                       "an atlas needs two axes: analysis.atlas.x and .y in the file, or --x "
                       "and --y");
    }
    // The file's axes were checked by the loader; the options' are checked here (usage errors).
    if (options.x) RequirePairAxisOption(spec, *x, *options.x, "--x");
    if (options.y) RequirePairAxisOption(spec, *y, *options.y, "--y");
    RequireRunLengthOfOptions(loaded.train, LowestInputSpeed(loaded.train, x, y), atlas.cycles,
                              atlas.transient_cycles, options.cycles, options.transient);
    if (x->parameter == y->parameter) {
      throw InputError("--y", 0, y->parameter, "must differ from the x parameter");
    }
    if (options.resume && !options.out) {
      throw InputError("--resume", 0, "", "needs --out DIR (the checkpoint lives there)");
    }
    atlas.Validate();
    const int nx = x->range.points, ny = y->range.points, total = nx * ny;

    // Checkpoint (only with --out): rank 0 prepares it and tells every rank what is done.
    std::optional<Checkpoint> checkpoint;
    std::vector<AtlasCell> restored;
    if (options.out) {
      std::ifstream in(options.file);
      std::stringstream text;
      text << in.rdbuf();
      checkpoint = Checkpoint{std::filesystem::path(*options.out) / ".atlas-checkpoint",
                              SettingsKey(text.str(), *x, *y, atlas)};
      if (rank == 0) restored = PrepareCheckpoint(*checkpoint, options.resume, total);
    }
    std::string restored_text;
    if (rank == 0) {
      nlohmann::json indices = nlohmann::json::array();
      for (const AtlasCell& c : restored) indices.push_back(c.iy * nx + c.ix);
      restored_text = indices.dump();
    }
    restored_text = MpiContext::BroadcastString(restored_text);
    std::vector<bool> skip(static_cast<size_t>(total), false);
    for (int k = 0; k < total; ++k) skip[static_cast<size_t>(k)] = k % ranks != rank;
    for (const auto& k : nlohmann::json::parse(restored_text)) skip[k.get<size_t>()] = true;

    const AtlasProgress progress = AtlasTerminalProgress(rank, ranks);
    const bool on_terminal = static_cast<bool>(progress);
    std::ofstream log;
    if (checkpoint) {
      log.open(checkpoint->dir / ("cells-rank-" + std::to_string(rank) + ".jsonl"), std::ios::app);
    }
    AtlasCellCallback on_cell = [&](const AtlasCell& c) {
      if (log.is_open() && c.ok) log << CellJson(c).dump() << std::endl;  // flushed per cell
    };
    // This rank's cells; a rank that fails outside a cell reports its cells as lost.
    nlohmann::json mine = nlohmann::json::array();
    double wall_s = 0.0;
    int threads = 1;
    try {
      const AtlasResult part = RunChaosAtlas(spec, *x, *y, atlas, progress, skip, on_cell);
      wall_s = part.wall_s;
      threads = part.threads;
      for (int k = 0; k < total; ++k) {
        if (!skip[static_cast<size_t>(k)])
          mine.push_back(CellJson(part.cells[static_cast<size_t>(k)]));
      }
    } catch (const std::exception& e) {
      for (int k = 0; k < total; ++k) {
        if (skip[static_cast<size_t>(k)]) continue;
        AtlasCell lost;
        lost.ix = k % nx;
        lost.iy = k / nx;
        lost.x = AxisValue(*x, lost.ix);
        lost.y = AxisValue(*y, lost.iy);
        lost.message = "lost: rank " + std::to_string(rank) + " failed: " + e.what();
        mine.push_back(CellJson(lost));
      }
    }
    if (on_terminal) fmt::print(stderr, "\n");
    const std::vector<std::string> parts = MpiContext::GatherToRoot(mine.dump());
    if (rank != 0) return 0;

    AtlasResult result;
    result.x = *x;
    result.y = *y;
    result.threads = threads;
    result.wall_s = wall_s;
    result.cells.resize(static_cast<size_t>(total));
    std::vector<bool> filled(static_cast<size_t>(total), false);
    auto place = [&](const AtlasCell& c) {
      const size_t k = static_cast<size_t>(c.iy * nx + c.ix);
      result.cells[k] = c;
      filled[k] = true;
    };
    for (const AtlasCell& c : restored) place(c);
    for (const std::string& part : parts) {
      for (const auto& j : nlohmann::json::parse(part)) place(CellFromJson(j));
    }
    for (int k = 0; k < total; ++k) {
      if (!filled[static_cast<size_t>(k)]) {
        AtlasCell& c = result.cells[static_cast<size_t>(k)];
        c.ix = k % nx;
        c.iy = k / nx;
        c.x = AxisValue(*x, c.ix);
        c.y = AxisValue(*y, c.iy);
        c.message = "lost: no rank returned this cell";
      }
    }
    nlohmann::json doc = AtlasJson(result, atlas);
    doc["name"] = spec.name;
    doc["file"] = options.file;
    doc["ranks"] = ranks;
    doc["restored_cells"] = restored.size();
    RequireFinite(doc, "atlas");
    if (out) {
      out->Write("atlas.csv", AtlasCsv(result, spec));
      out->Write("atlas.json", doc.dump(1) + "\n");
      out->Commit();
      // Complete: the checkpoint has served its purpose (failed cells stay failed in the output;
      // a new run retries them).
      if (result.Failed() == 0) {
        log.close();
        std::filesystem::remove_all(checkpoint->dir);
      }
    }
    if (options.json) {
      std::cout << doc.dump(1) << "\n";
    } else {
      fmt::print(
          "{}  ({}): chaos atlas, {} x {} cells, {} each, {}{}, {:.1f} s{}\n", spec.name,
          options.file, nx, ny, Count(atlas.cycles, "mesh cycle", "mesh cycles"),
          Count(result.threads, "thread", "threads"),
          ranks > 1 ? fmt::format(" x {} ranks", ranks) : "", result.wall_s,
          restored.empty()
              ? ""
              : " (" + Count(static_cast<long>(restored.size()), "cell", "cells") + " restored)");
      const DisplayAxis ax = DisplayAxisFor(x->parameter, spec);
      const DisplayAxis ay = DisplayAxisFor(y->parameter, spec);
      fmt::print("  rows: {} from {:.4g} to {:.4g} {}; columns: {} from {:.4g} to {:.4g} {}\n",
                 y->parameter, y->range.to * ay.scale, y->range.from * ay.scale, ay.unit,
                 x->parameter, x->range.from * ax.scale, x->range.to * ax.scale, ax.unit);
      PrintRegimeMap(nx, ny, [&](int k) {
        const AtlasCell& c = result.cells[static_cast<size_t>(k)];
        return RegimeLetter(c.ok, c.regime);
      });
      for (const AtlasCell& c : result.cells) {
        if (!c.ok) fmt::print("  cell ({}, {}) failed: {}\n", c.ix, c.iy, c.message);
      }
    }
    return ReportFailedAtlasCells(result.Failed(), result.cells.size());
  });
  // Every rank exits with rank 0's verdict (an input error is seen by every rank alike).
  return MpiContext::BroadcastInt(code);
}

}  // namespace gearnvh::app
