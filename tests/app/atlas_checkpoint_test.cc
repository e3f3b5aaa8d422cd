// The atlas checkpoint's restore (app/src/atlas_checkpoint.h): which logged cells a resume keeps.
#include "atlas_checkpoint.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "atlas_documents.h"
#include "support/run_command.h"
#include "train_atlas_command.h"

namespace gearnvh::app {
namespace {

TEST_CASE("atlas checkpoint: a resume keeps the logged cells inside the grid and redoes the rest",
          "[cli][resume]") {
  const testing::TempDir dir;
  AtlasCheckpoint cp{dir.path() / ".atlas-checkpoint", "{\"settings\":1}", 3, 2};
  const AtlasCellCheck pair_cell = [](const nlohmann::json& j) { (void)AtlasCellFromJson(j); };
  REQUIRE(PrepareAtlasCheckpoint(cp, /*resume=*/false, pair_cell).empty());  // a fresh one
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
  const std::vector<nlohmann::json> restored =
      PrepareAtlasCheckpoint(cp, /*resume=*/true, pair_cell);
  REQUIRE(restored.size() == 2);
  CHECK(AtlasCellFromJson(restored[0]).ix == 2);
  CHECK(AtlasCellFromJson(restored[0]).iy == 1);
  CHECK(AtlasCellFromJson(restored[1]).ix == 0);
  CHECK(AtlasCellFromJson(restored[1]).iy == 0);
}

TEST_CASE("atlas checkpoint: a train's cells round-trip, and a line its reader refuses is redone",
          "[cli][resume]") {
  const testing::TempDir dir;
  AtlasCheckpoint cp{dir.path() / ".atlas-checkpoint", "{\"settings\":2}", 2, 2};
  const AtlasCellCheck train_cell = [](const nlohmann::json& j) {
    (void)TrainAtlasCellFromJson(j);
  };
  REQUIRE(PrepareAtlasCheckpoint(cp, /*resume=*/false, train_cell).empty());
  TrainAtlasCell c;
  c.ix = 1;
  c.iy = 1;
  c.x = 0.1 + 0.2;  // not a short decimal: the JSON must carry every bit
  c.y = 1.0 / 3.0;
  c.point.ok = true;
  c.point.lyapunov_per_s = -12.345678901234567;
  c.point.lyapunov_per_forcing_cycle = -0.1;
  c.point.lyapunov_standard_error = 0.01;
  c.point.regime = RattleRegime::kDoubleSided;
  c.point.meshes = {{"a-b", 0.5, 0.25, 0.3, 1e-3, RattleRegime::kDoubleSided},
                    {"c-d", 0.0, 0.0, 0.0, 0.0, RattleRegime::kNoImpact}};
  c.point.loose_gears = {{"f", 123.4, 42, 1, 1e-3 / 7.0}};
  c.point.wall_s = 0.5;
  nlohmann::json pair_line = nlohmann::json::parse(
      "{\"ix\": 0, \"iy\": 0, \"ok\": true}");  // ok and inside, but not a train cell
  {
    std::ofstream log(cp.dir / "cells-rank-1.jsonl");
    log << TrainAtlasCellJson(c).dump() << "\n" << pair_line.dump() << "\n";
  }
  const std::vector<nlohmann::json> restored =
      PrepareAtlasCheckpoint(cp, /*resume=*/true, train_cell);
  REQUIRE(restored.size() == 1);
  const TrainAtlasCell back = TrainAtlasCellFromJson(restored[0]);
  CHECK(TrainAtlasCellJson(back) == TrainAtlasCellJson(c));
  CHECK(back.x == c.x);  // bit for bit
  CHECK(back.y == c.y);
  CHECK(back.point.lyapunov_per_s == c.point.lyapunov_per_s);
  REQUIRE(back.point.meshes.size() == 2);
  CHECK(back.point.meshes[0].regime == RattleRegime::kDoubleSided);
  CHECK(back.point.meshes[1].regime == RattleRegime::kNoImpact);
  REQUIRE(back.point.loose_gears.size() == 1);
  CHECK(back.point.loose_gears[0].impacts == 42);
  CHECK(back.point.loose_gears[0].rank == 1);
  CHECK(back.point.loose_gears[0].impact_energy_per_second == 1e-3 / 7.0);
}

}  // namespace
}  // namespace gearnvh::app
