#include "train_atlas_command.h"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

#include "atlas_checkpoint.h"
#include "atlas_command.h"
#include "atlas_documents.h"
#include "atlas_grid.h"
#include "atlas_terminal.h"
#include "command_errors.h"
#include "config/train_parameters.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "mpi_context.h"
#include "output_folder.h"
#include "train_command_options.h"

namespace gearnvh::app {

nlohmann::json TrainAtlasCellJson(const TrainAtlasCell& c) {
  const TrainAtlasPoint& p = c.point;
  nlohmann::json meshes = nlohmann::json::array();
  for (const TrainAtlasMesh& m : p.meshes) {
    meshes.push_back({{"name", m.name},
                      {"drive_impacts_per_cycle", m.drive_impacts_per_cycle},
                      {"back_impacts_per_cycle", m.back_impacts_per_cycle},
                      {"separation_fraction", m.separation_fraction},
                      {"impact_velocity_rms", m.impact_velocity_rms},
                      {"regime", RattleRegimeName(m.regime)}});
  }
  nlohmann::json loose = nlohmann::json::array();
  for (const TrainAtlasLooseGear& g : p.loose_gears) {
    loose.push_back({{"name", g.name},
                     {"impact_energy_per_second", g.impact_energy_per_second},
                     {"rattle_index", g.rattle_index},
                     {"impacts", g.impacts},
                     {"rank", g.rank}});
  }
  return {{"ix", c.ix},
          {"iy", c.iy},
          {"x", c.x},
          {"y", c.y},
          {"ok", p.ok},
          {"message", p.message},
          {"lyapunov_per_s", p.lyapunov_per_s},
          {"lyapunov_per_forcing_cycle", p.lyapunov_per_forcing_cycle},
          {"lyapunov_standard_error", p.lyapunov_standard_error},
          {"regime", p.ok ? RattleRegimeName(p.regime) : ""},
          {"meshes", meshes},
          {"loose_gears", loose},
          {"wall_s", p.wall_s}};
}

TrainAtlasCell TrainAtlasCellFromJson(const nlohmann::json& j) {
  TrainAtlasCell c;
  c.ix = j.at("ix").get<int>();
  c.iy = j.at("iy").get<int>();
  c.x = j.at("x").get<double>();
  c.y = j.at("y").get<double>();
  TrainAtlasPoint& p = c.point;
  p.ok = j.at("ok").get<bool>();
  p.message = j.at("message").get<std::string>();
  p.lyapunov_per_s = j.at("lyapunov_per_s").get<double>();
  p.lyapunov_per_forcing_cycle = j.at("lyapunov_per_forcing_cycle").get<double>();
  p.lyapunov_standard_error = j.at("lyapunov_standard_error").get<double>();
  if (p.ok) p.regime = RegimeFromJson(j.at("regime"));
  for (const auto& m : j.at("meshes")) {
    p.meshes.push_back(
        {m.at("name").get<std::string>(), m.at("drive_impacts_per_cycle").get<double>(),
         m.at("back_impacts_per_cycle").get<double>(), m.at("separation_fraction").get<double>(),
         m.at("impact_velocity_rms").get<double>(), RegimeFromJson(m.at("regime"))});
  }
  for (const auto& g : j.at("loose_gears")) {
    p.loose_gears.push_back({g.at("name").get<std::string>(), g.at("rattle_index").get<double>(),
                             g.at("impacts").get<long>(), g.at("rank").get<int>(),
                             g.at("impact_energy_per_second").get<double>()});
  }
  p.wall_s = j.at("wall_s").get<double>();
  return c;
}

namespace {

// The axis's values in display units, for the map's caption and the CSV header.
std::string AxisHeader(const AtlasAxis& a) {
  const TrainDisplayAxis d = TrainDisplayAxisFor(a.parameter);
  return d.unit.empty() ? a.parameter : a.parameter + " [" + d.unit + "]";
}

void PrintTrainAtlas(const TrainAtlasResult& r, const std::string& name, const std::string& file,
                     long cycles, int ranks, size_t restored) {
  const int nx = r.x.range.points, ny = r.y.range.points;
  fmt::print(
      "{}  ({}): chaos atlas of a gear train, {} x {} cells, {} of {} each, {}{}, {:.1f} s{}\n",
      name, file, nx, ny, Count(cycles, "cycle", "cycles"), r.mesh_names.front(),
      Count(r.threads, "thread", "threads"), ranks > 1 ? fmt::format(" x {} ranks", ranks) : "",
      r.wall_s,
      restored == 0 ? ""
                    : " (" + Count(static_cast<long>(restored), "cell", "cells") + " restored)");
  const TrainDisplayAxis dx = TrainDisplayAxisFor(r.x.parameter);
  const TrainDisplayAxis dy = TrainDisplayAxisFor(r.y.parameter);
  fmt::print("  rows: {} from {} to {} {}; columns: {} from {} to {} {}\n", r.y.parameter,
             Significant(r.y.range.to * dy.scale), Significant(r.y.range.from * dy.scale), dy.unit,
             r.x.parameter, Significant(r.x.range.from * dx.scale),
             Significant(r.x.range.to * dx.scale), dx.unit);
  fmt::print(
      "  the train (chaotic from its largest Lyapunov exponent, else its most impacting "
      "mesh):\n");
  PrintRegimeMap(nx, ny, [&](int k) {
    const TrainAtlasPoint& p = r.cells[static_cast<size_t>(k)].point;
    return RegimeLetter(p.ok, p.regime);
  });
  for (size_t i = 0; i < r.mesh_names.size(); ++i) {
    fmt::print("  mesh {}:\n", r.mesh_names[i]);
    PrintRegimeMap(
        nx, ny,
        [&](int k) {
          const TrainAtlasPoint& p = r.cells[static_cast<size_t>(k)].point;
          // A failed cell has no meshes.
          return p.ok ? RegimeLetter(true, p.meshes[i].regime) : RegimeLetter(false, {});
        },
        false);
  }
  if (!r.loose_gear_names.empty()) {
    fmt::print("  loose gear that rattles most (impact energy per second):\n");
    for (const TrainAtlasCell& c : r.cells) {
      if (!c.point.ok) continue;
      if (c.point.loose_gears.empty() || c.point.loose_gears.front().rank != 1) {
        fmt::print("    cell ({}, {}): no loose gear impacts\n", c.ix, c.iy);
        continue;
      }
      const TrainAtlasLooseGear& top = c.point.loose_gears.front();
      fmt::print("    cell ({}, {}): {} {:.4g} mW\n", c.ix, c.iy, top.name,
                 top.impact_energy_per_second * 1e3);
    }
  }
  for (const TrainAtlasCell& c : r.cells) {
    if (!c.point.ok) fmt::print("  cell ({}, {}) failed: {}\n", c.ix, c.iy, c.point.message);
  }
}

}  // namespace

nlohmann::json TrainAtlasJson(const TrainAtlasResult& r, const TrainAtlasOptions& o) {
  nlohmann::json cells = nlohmann::json::array();
  std::map<std::string, int> regimes;
  for (const TrainAtlasCell& c : r.cells) {
    cells.push_back(TrainAtlasCellJson(c));
    ++regimes[c.point.ok ? RattleRegimeName(c.point.regime) : "failed"];
  }
  nlohmann::json doc = AtlasRunJson(regimes, r.Failed(), o, r.threads, r.wall_s);
  doc["schema"] = "gearnvh/2";
  doc["x"] = AtlasAxisJson(r.x);
  doc["y"] = AtlasAxisJson(r.y);
  doc["meshes"] = r.mesh_names;
  doc["loose_gears"] = r.loose_gear_names;
  doc["cells"] = cells;
  return doc;
}

std::string TrainAtlasCsv(const TrainAtlasResult& r) {
  const TrainDisplayAxis dx = TrainDisplayAxisFor(r.x.parameter);
  const TrainDisplayAxis dy = TrainDisplayAxisFor(r.y.parameter);
  std::ostringstream os;
  os.precision(12);
  os << "ix,iy," << AxisHeader(r.x) << ',' << AxisHeader(r.y)
     << ",ok,lyapunov_per_s,lyapunov_per_forcing_cycle,lyapunov_standard_error,regime";
  for (const std::string& m : r.mesh_names) {
    os << ',' << m << " drive_impacts_per_cycle," << m << " back_impacts_per_cycle," << m
       << " separation_fraction," << m << " impact_velocity_rms," << m << " regime";
  }
  for (const std::string& g : r.loose_gear_names) {
    os << ',' << g << " impact_energy_per_second," << g << " rattle_index";
  }
  os << ",message\n";
  for (const TrainAtlasCell& c : r.cells) {
    const TrainAtlasPoint& p = c.point;
    os << c.ix << ',' << c.iy << ',' << c.x * dx.scale << ',' << c.y * dy.scale << ','
       << (p.ok ? 1 : 0) << ',' << p.lyapunov_per_s << ',' << p.lyapunov_per_forcing_cycle << ','
       << p.lyapunov_standard_error << ',' << (p.ok ? RattleRegimeName(p.regime) : "");
    for (size_t i = 0; i < r.mesh_names.size(); ++i) {
      if (!p.ok) {
        os << ",,,,,";
        continue;
      }
      const TrainAtlasMesh& m = p.meshes[i];
      os << ',' << m.drive_impacts_per_cycle << ',' << m.back_impacts_per_cycle << ','
         << m.separation_fraction << ',' << m.impact_velocity_rms << ','
         << RattleRegimeName(m.regime);
    }
    for (const std::string& g : r.loose_gear_names) {
      const auto lg = std::find_if(p.loose_gears.begin(), p.loose_gears.end(),
                                   [&](const TrainAtlasLooseGear& l) { return l.name == g; });
      os << ',';
      if (lg != p.loose_gears.end()) os << lg->impact_energy_per_second;
      os << ',';
      if (lg != p.loose_gears.end()) os << lg->rattle_index;
    }
    os << ',' << CsvQuoted(p.message) << '\n';
  }
  return os.str();
}

nlohmann::json TrainAtlasDocument(const TrainAtlasResult& r, const TrainAtlasOptions& o,
                                  const TrainSpec& spec, const std::string& file, int ranks,
                                  size_t restored_cells) {
  nlohmann::json doc = TrainAtlasJson(r, o);
  doc["name"] = spec.name;
  doc["file"] = file;
  doc["tier"] = TierName(o.tier);
  doc["ranks"] = ranks;
  doc["restored_cells"] = restored_cells;
  return doc;
}

TrainAtlasPlan PlanTrainAtlas(const AtlasCommandOptions& options, const TrainSpec& spec,
                              const OptionNames& names) {
  const TrainCommandSettings settings =
      CheckTrainCommandOptions(options.tier, spec, options.method, names);
  TrainAtlasPlan plan;
  TrainAtlasOptions& atlas = plan.atlas;
  atlas.cycles = options.cycles.value_or(atlas.cycles);
  atlas.transient_cycles = options.transient.value_or(atlas.transient_cycles);
  atlas.events = settings.events;
  atlas.tier = settings.tier;
  // A cell's invalid variant is worded at the parameter with the axis's value as it is shown.
  atlas.input_error_message = [](const InputError& e, const std::vector<ParameterValue>& set) {
    return std::string(config::AtParameterValue(e, set, TrainAxisValueText).what());
  };
  RequireCycleCounts(atlas.cycles, 8, atlas.transient_cycles, names);
  if (options.jobs < 0)
    throw InputError(names("jobs"), 0, std::to_string(options.jobs), "must be >= 0");
  plan.jobs = options.jobs;
  std::optional<AtlasAxis> x = spec.analysis.atlas_x, y = spec.analysis.atlas_y;
  if (options.x) x = ParseTrainAxisOption(*options.x, names("x"));
  if (options.y) y = ParseTrainAxisOption(*options.y, names("y"));
  if (!x || !y) {
    throw InputError("analysis.atlas", 0, "(missing)",
                     "an atlas needs two axes: " + names("x") + " and " + names("y") +
                         " (or analysis.atlas.x and .y)");
  }
  plan.allow_slow = options.allow_slow;
  plan.names = names;
  if (x->parameter == y->parameter) {
    throw InputError(names("y"), 0, y->parameter, "must differ from the x parameter");
  }
  // Names and indices are checked once here (a bad name is a usage error, not a failed cell).
  {
    TrainSpec variant = spec;
    SetTrainParameter(variant, x->parameter, x->range.from,
                      options.x ? names("x") : "analysis.atlas.x.parameter");
    SetTrainParameter(variant, y->parameter, y->range.from,
                      options.y ? names("y") : "analysis.atlas.y.parameter");
  }
  if (options.x) RequireAxisWithinPitchLineLimit(spec, *x, *options.x, names("x"));
  if (options.y) RequireAxisWithinPitchLineLimit(spec, *y, *options.y, names("y"));
  if (options.x) RequireAtlasAxisRange(*x, *options.x, names("x"));
  if (options.y) RequireAtlasAxisRange(*y, *options.y, names("y"));
  RequireRunLengthOfOptions(spec, LowestInputSpeed(spec, x, y), atlas.cycles,
                            atlas.transient_cycles, options.cycles, options.transient, names);
  plan.x = *x;
  plan.y = *y;
  return plan;
}

std::string CheckTrainAtlasCost(const TrainSpec& spec, const TrainAtlasPlan& plan, int ranks) {
  const TrainAtlasOptions& a = plan.atlas;
  const long alignment = std::min(50L, a.cycles / 4);
  const TrainTables tables = BuildTrainTablesAtTier(spec, BuildGearTrain(spec), a.tier);
  const double period = tables.meshes.front().period;
  const RunCostEstimate cell = EstimateRunCost(
      tables, static_cast<double>(a.transient_cycles + alignment + a.cycles) * period, &spec);
  const int all_cells = plan.x.range.points * plan.y.range.points;
  const int cells = (all_cells + ranks - 1) / ranks;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const int threads = plan.jobs > 0 ? plan.jobs : static_cast<int>(cores);
  const RunCostEstimate cost =
      CombineRunCosts(std::vector<RunCostEstimate>(static_cast<size_t>(cells), cell), threads);
  const std::string what =
      ranks > 1 ? fmt::format("each rank's {} of the atlas's {} cells", cells, all_cells)
                : fmt::format("the atlas's {} cells", cells);
  return CheckRunCost(cost, plan.allow_slow, what, plan.names);
}

int AtlasTrain(const AtlasCommandOptions& options, const TrainSpec& spec) {
  const int rank = MpiContext::Rank(), ranks = MpiContext::Size();
  const TrainAtlasPlan plan = PlanTrainAtlas(options, spec);
  if (options.resume && !options.out) {
    throw InputError("--resume", 0, "", "needs --out DIR (the checkpoint lives there)");
  }
  if (const std::string slow = CheckTrainAtlasCost(spec, plan, ranks); !slow.empty() && rank == 0)
    fmt::print(stderr, "warning: {}\n", slow);
  std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", true);
  // Checkpoint (only with --out): rank 0 prepares it and tells every rank what is done.
  AtlasGrid grid(plan.x, plan.y,
                 AtlasCheckpointIn(options.out, options.file, plan.x, plan.y, plan.atlas),
                 options.resume, [](const nlohmann::json& j) { (void)TrainAtlasCellFromJson(j); });
  const AtlasProgress progress = AtlasTerminalProgress(rank, ranks);
  TrainAtlasResult result = grid.RunCells<TrainAtlasResult>(
      [&](const std::vector<bool>& skip, const TrainAtlasCellCallback& on_cell) {
        return RunTrainAtlas(spec, plan.x, plan.y, plan.atlas, plan.jobs, progress, skip, on_cell);
      },
      TrainAtlasCellJson, TrainAtlasCellFromJson);
  if (progress) fmt::print(stderr, "\n");
  if (rank != 0) return 0;
  result.x = plan.x;
  result.y = plan.y;
  result.mesh_names = MeshNames(spec);
  result.loose_gear_names = LooseGearNames(spec);
  nlohmann::json doc =
      TrainAtlasDocument(result, plan.atlas, spec, options.file, ranks, grid.restored());
  RequireFinite(doc, "atlas");
  if (out) {
    out->Write("atlas.csv", TrainAtlasCsv(result));
    out->Write("atlas.json", doc.dump(1) + "\n");
    out->Commit();
    out.reset();  // the lock released before the terminal output, whatever happens there
    // Complete: the checkpoint has served its purpose (failed cells stay failed in the output;
    // a new run retries them).
    if (result.Failed() == 0) grid.Discard();
  }
  if (options.json) {
    std::cout << doc.dump(1) << "\n";
  } else {
    PrintTrainAtlas(result, spec.name, options.file, plan.atlas.cycles, ranks, grid.restored());
  }
  return ReportFailedAtlasCells(result.Failed(), result.cells.size());
}

}  // namespace gearnvh::app
