#include "rank_gather.h"

namespace gearnvh::app {

std::vector<bool> OtherRanksItems(size_t count) {
  const int rank = MpiContext::Rank(), ranks = MpiContext::Size();
  std::vector<bool> skip(count);
  for (size_t i = 0; i < count; ++i)
    skip[i] = static_cast<int>(i % static_cast<size_t>(ranks)) != rank;
  return skip;
}

}  // namespace gearnvh::app
