#include "atlas_command.h"

#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "atlas_checkpoint.h"
#include "atlas_documents.h"
#include "atlas_grid.h"
#include "atlas_terminal.h"
#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/gearbox_spec_validation.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/atlas.h"
#include "mpi_context.h"
#include "output_folder.h"
#include "simulate_command.h"
#include "train_atlas_command.h"
#include "train_command_options.h"

namespace gearnvh::app {

void RequirePairAxisOption(const GearboxSpec& spec, const AtlasAxis& axis, const std::string& text,
                           const std::string& field) {
  config::RequireVariableParameter(spec, axis.parameter, field);
  RequireAxisWithinPitchLineLimit(TrainOf(spec), axis, text, field, "the mesh");
}

void RequireAtlasAxisRange(const AtlasAxis& axis, const std::string& text,
                           const std::string& field) {
  const auto broken = FirstSweepRangeViolation(axis.range);
  if (!broken) return;
  const char* part = broken->part == SweepRangePart::kPoints ? "POINTS"
                     : broken->part == SweepRangePart::kTo   ? "TO"
                                                             : "FROM";
  throw InputError(field, 0, text,
                   std::string(part) + " " + broken->rule + " (the rule of analysis.atlas axes)");
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
    if (options.x) RequireAtlasAxisRange(*x, *options.x, "--x");
    if (options.y) RequireAtlasAxisRange(*y, *options.y, "--y");
    RequireRunLengthOfOptions(loaded.train, LowestInputSpeed(loaded.train, x, y), atlas.cycles,
                              atlas.transient_cycles, options.cycles, options.transient);
    if (x->parameter == y->parameter) {
      throw InputError("--y", 0, y->parameter, "must differ from the x parameter");
    }
    if (options.resume && !options.out) {
      throw InputError("--resume", 0, "", "needs --out DIR (the checkpoint lives there)");
    }
    atlas.Validate();
    const int nx = x->range.points, ny = y->range.points;

    // Checkpoint (only with --out): rank 0 prepares it and tells every rank what is done.
    AtlasGrid grid(*x, *y, AtlasCheckpointIn(options.out, options.file, *x, *y, atlas),
                   options.resume, [](const nlohmann::json& j) { (void)AtlasCellFromJson(j); });
    const AtlasProgress progress = AtlasTerminalProgress(rank, ranks);
    AtlasResult result = grid.RunCells<AtlasResult>(
        [&](const std::vector<bool>& skip, const AtlasCellCallback& on_cell) {
          return RunChaosAtlas(spec, *x, *y, atlas, progress, skip, on_cell);
        },
        AtlasCellJson, AtlasCellFromJson);
    if (progress) fmt::print(stderr, "\n");
    if (rank != 0) return 0;
    result.x = *x;
    result.y = *y;
    nlohmann::json doc = AtlasJson(result, atlas);
    doc["name"] = spec.name;
    doc["file"] = options.file;
    doc["ranks"] = ranks;
    doc["restored_cells"] = grid.restored();
    RequireFinite(doc, "atlas");
    if (out) {
      out->Write("atlas.csv", AtlasCsv(result, spec));
      out->Write("atlas.json", doc.dump(1) + "\n");
      out->Commit();
      // Complete: the checkpoint has served its purpose (failed cells stay failed in the output;
      // a new run retries them).
      if (result.Failed() == 0) grid.Discard();
    }
    if (options.json) {
      std::cout << doc.dump(1) << "\n";
    } else {
      fmt::print(
          "{}  ({}): chaos atlas, {} x {} cells, {} each, {}{}, {:.1f} s{}\n", spec.name,
          options.file, nx, ny, Count(atlas.cycles, "mesh cycle", "mesh cycles"),
          Count(result.threads, "thread", "threads"),
          ranks > 1 ? fmt::format(" x {} ranks", ranks) : "", result.wall_s,
          grid.restored() == 0
              ? ""
              : " (" + Count(static_cast<long>(grid.restored()), "cell", "cells") + " restored)");
      const DisplayAxis ax = DisplayAxisFor(x->parameter, spec);
      const DisplayAxis ay = DisplayAxisFor(y->parameter, spec);
      fmt::print("  rows: {} from {} to {} {}; columns: {} from {} to {} {}\n", y->parameter,
                 Significant(y->range.to * ay.scale), Significant(y->range.from * ay.scale),
                 ay.unit, x->parameter, Significant(x->range.from * ax.scale),
                 Significant(x->range.to * ax.scale), ax.unit);
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
