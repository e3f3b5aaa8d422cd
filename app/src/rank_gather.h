// Work split over MPI ranks round robin (item i is rank i % ranks's) and gathered on rank 0 as
// JSON: the speeds of a pair's and a train's sweep. Outside mpirun there is one rank and nothing
// moves.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mpi_context.h"

namespace gearnvh::app {

// One entry per item: true for the items other ranks compute.
std::vector<bool> OtherRanksItems(size_t count);

// Collective: rank 0's `items` receive every other rank's own items (those its `skip` leaves to
// it), sent as JSON (`to_json`/`from_json`); an item no rank returned is `lose(item)`. Returns
// true on rank 0; the other ranks' items are left as they are.
template <typename Item, typename ToJson, typename FromJson, typename Lose>
bool GatherItemsToRoot(std::vector<Item>& items, const std::vector<bool>& skip, ToJson to_json,
                       FromJson from_json, Lose lose) {
  if (MpiContext::Size() == 1) return true;
  nlohmann::json mine = nlohmann::json::array();
  for (size_t i = 0; i < items.size(); ++i) {
    if (!skip[i]) mine.push_back({{"index", i}, {"item", to_json(items[i])}});
  }
  const std::vector<std::string> parts = MpiContext::GatherToRoot(mine.dump());
  if (MpiContext::Rank() != 0) return false;
  std::vector<bool> filled(items.size(), false);
  for (size_t i = 0; i < items.size(); ++i) filled[i] = !skip[i];  // rank 0's own
  for (size_t r = 1; r < parts.size(); ++r) {
    for (const auto& j : nlohmann::json::parse(parts[r])) {
      const auto i = j.at("index").get<size_t>();
      items.at(i) = from_json(j.at("item"));
      filled[i] = true;
    }
  }
  for (size_t i = 0; i < items.size(); ++i) {
    if (!filled[i]) lose(items[i]);
  }
  return true;
}

}  // namespace gearnvh::app
