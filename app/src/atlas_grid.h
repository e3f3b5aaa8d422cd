// The cells of one atlas over the MPI ranks, with its checkpoint (atlas_checkpoint.h), for a
// pair's atlas and a train's alike: rank 0 prepares the checkpoint and tells every rank which cells
// a resume restored; rank r computes the other cells k with k % ranks == r, logging each to the
// checkpoint as it completes; rank 0 gathers every rank's cells as JSON (the form the checkpoint
// stores) and places them, a cell no rank returned kept as lost with its reason.
#pragma once

#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "atlas_checkpoint.h"
#include "gearnvh/nvh/atlas.h"

namespace gearnvh::app {

class AtlasGrid {
 public:
  // Collective. Without a checkpoint (no --out) nothing is restored or logged.
  AtlasGrid(const AtlasAxis& x, const AtlasAxis& y, std::optional<AtlasCheckpoint> checkpoint,
            bool resume, const AtlasCellCheck& check_cell);

  int total() const { return nx_ * ny_; }
  // One entry per cell: true for the cells this rank does not compute (another rank's, restored).
  const std::vector<bool>& skip() const { return skip_; }
  size_t restored() const { return restored_.size(); }
  // Collective: runs this rank's cells, `run(skip(), on_cell)` (RunCells) returning a Result whose
  // `cells` hold one per grid cell (those skipped ignored) and calling on_cell(cell) under a lock
  // as each completes (logged to the checkpoint, flushed). Rank 0 returns the Result with every
  // cell of the grid: restored ones, every rank's computed ones, and a failed cell saying "lost"
  // and why for a cell nobody returned or whose rank failed outside any cell (its `run` threw;
  // then threads and wall time are the Result's defaults). Other ranks return their own part.
  // `to_json`/`from_json` convert a cell to and from the JSON the checkpoint stores.
  template <typename Result, typename Compute, typename ToJson, typename FromJson>
  Result RunCells(Compute run, ToJson to_json, FromJson from_json);
  // Rank 0, once the outputs are written and no cell failed: the checkpoint has served.
  void Discard();

 private:
  void Log(const nlohmann::json& cell);
  std::vector<std::string> GatherParts(const nlohmann::json& mine) const;
  int Rank() const;

  // Cell k, at its axis values, failed with `message` (a pair's cell or a train's).
  template <typename Cell>
  Cell Lost(size_t k, const std::string& message) const;

  AtlasAxis x_, y_;
  int nx_ = 0, ny_ = 0;
  std::optional<AtlasCheckpoint> checkpoint_;
  std::vector<nlohmann::json> restored_;
  std::vector<bool> skip_;
  std::ofstream log_;
};

template <typename Cell>
Cell AtlasGrid::Lost(size_t k, const std::string& message) const {
  Cell c;
  c.ix = static_cast<int>(k) % nx_;
  c.iy = static_cast<int>(k) / nx_;
  c.x = AxisValue(x_, c.ix);
  c.y = AxisValue(y_, c.iy);
  FailureMessage(c) = message;  // found by argument-dependent lookup beside the cell type
  return c;
}

template <typename Result, typename Compute, typename ToJson, typename FromJson>
Result AtlasGrid::RunCells(Compute run, ToJson to_json, FromJson from_json) {
  using Cell = typename decltype(Result::cells)::value_type;
  Result result;
  std::string failure;
  try {
    result = run(skip_, [&](const Cell& c) { Log(to_json(c)); });
  } catch (const std::exception& e) {
    failure = e.what();
  }
  nlohmann::json mine = nlohmann::json::array();
  for (size_t k = 0; k < skip_.size(); ++k) {
    if (skip_[k]) continue;
    mine.push_back(failure.empty() ? to_json(result.cells[k])
                                   : to_json(Lost<Cell>(k, "lost: rank " + std::to_string(Rank()) +
                                                               " failed: " + failure)));
  }
  const std::vector<std::string> parts = GatherParts(mine);
  if (Rank() != 0) return result;
  result.cells.assign(static_cast<size_t>(total()), Cell{});
  std::vector<bool> filled(result.cells.size(), false);
  auto place = [&](const nlohmann::json& j) {
    const auto k = static_cast<size_t>(j.at("iy").get<int>() * nx_ + j.at("ix").get<int>());
    result.cells[k] = from_json(j);
    filled[k] = true;
  };
  for (const nlohmann::json& j : restored_) place(j);
  for (const std::string& part : parts) {
    for (const auto& j : nlohmann::json::parse(part)) place(j);
  }
  for (size_t k = 0; k < result.cells.size(); ++k) {
    if (!filled[k]) result.cells[k] = Lost<Cell>(k, "lost: no rank returned this cell");
  }
  return result;
}

}  // namespace gearnvh::app
