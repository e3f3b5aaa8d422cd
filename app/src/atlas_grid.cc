#include "atlas_grid.h"

#include <exception>
#include <filesystem>
#include <stdexcept>

#include "mpi_context.h"

namespace gearnvh::app {

AtlasGrid::AtlasGrid(const AtlasAxis& x, const AtlasAxis& y,
                     std::optional<AtlasCheckpoint> checkpoint, bool resume,
                     const AtlasCellCheck& check_cell)
    : x_(x), y_(y), nx_(x.range.points), ny_(y.range.points), checkpoint_(std::move(checkpoint)) {
  const int rank = MpiContext::Rank(), ranks = MpiContext::Size();
  // Rank 0's refusal (a resume with other settings, an unwritable checkpoint) stops every rank:
  // the others would otherwise wait in this broadcast for a rank that left.
  std::string restored_text;
  std::exception_ptr refused;
  if (rank == 0) {
    try {
      if (checkpoint_) restored_ = PrepareAtlasCheckpoint(*checkpoint_, resume, check_cell);
      nlohmann::json indices = nlohmann::json::array();
      for (const nlohmann::json& c : restored_) {
        indices.push_back(c.at("iy").get<int>() * nx_ + c.at("ix").get<int>());
      }
      restored_text = indices.dump();
    } catch (...) {
      refused = std::current_exception();
    }
  }
  restored_text = MpiContext::BroadcastString(refused ? "" : restored_text);
  if (refused) std::rethrow_exception(refused);
  if (restored_text.empty()) {
    throw std::runtime_error("rank 0 could not prepare the atlas checkpoint");  // said by rank 0
  }
  skip_.assign(static_cast<size_t>(total()), false);
  for (int k = 0; k < total(); ++k) skip_[static_cast<size_t>(k)] = k % ranks != rank;
  for (const auto& k : nlohmann::json::parse(restored_text)) skip_[k.get<size_t>()] = true;
  if (checkpoint_) {
    log_.open(checkpoint_->dir / ("cells-rank-" + std::to_string(rank) + ".jsonl"), std::ios::app);
  }
}

int AtlasGrid::Rank() const { return MpiContext::Rank(); }

void AtlasGrid::Log(const nlohmann::json& cell) {
  if (log_.is_open() && cell.at("ok").get<bool>()) log_ << cell.dump() << std::endl;
}

std::vector<std::string> AtlasGrid::GatherParts(const nlohmann::json& mine) const {
  return MpiContext::GatherToRoot(mine.dump());
}

void AtlasGrid::Discard() {
  if (!checkpoint_) return;
  log_.close();
  std::filesystem::remove_all(checkpoint_->dir);
}

}  // namespace gearnvh::app
