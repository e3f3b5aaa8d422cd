// The atlas checkpoint's restore (app/src/atlas_checkpoint.h): which logged cells a resume keeps.
#include "atlas_checkpoint.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "atlas_documents.h"
#include "support/run_command.h"

namespace gearnvh::app {
namespace {

TEST_CASE("atlas checkpoint: a resume keeps the logged cells inside the grid and redoes the rest",
          "[cli][resume]") {
  const testing::TempDir dir;
  AtlasCheckpoint cp{dir.path() / ".atlas-checkpoint", "{\"settings\":1}", 3, 2};
  REQUIRE(PrepareAtlasCheckpoint(cp, /*resume=*/false).empty());  // a fresh checkpoint
  std::ofstream log(cp.dir / "cells-rank-0.jsonl");
  auto cell = [](int ix, int iy) {
    AtlasCell c;
    c.ix = ix;
    c.iy = iy;
    c.ok = true;
    return AtlasCellJson(c).dump();
  };
  // Inside the 3 x 2 grid; then a damaged line's indices outside it (ix = nx, iy = ny, negative),
  // which would index past the grid, and a line cut short by a kill.
  log << cell(2, 1) << "\n"
      << cell(0, 0) << "\n"
      << cell(3, 0) << "\n"
      << cell(0, 2) << "\n"
      << cell(-1, 0) << "\n"
      << "{\"ix\": 1, \"i" << std::endl;
  const std::vector<AtlasCell> restored = PrepareAtlasCheckpoint(cp, /*resume=*/true);
  REQUIRE(restored.size() == 2);
  CHECK(restored[0].ix == 2);
  CHECK(restored[0].iy == 1);
  CHECK(restored[1].ix == 0);
  CHECK(restored[1].iy == 0);
}

}  // namespace
}  // namespace gearnvh::app
