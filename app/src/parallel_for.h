// Runs body(i) for i = 0 .. count-1 on `threads` threads (0: all hardware threads), each index
// once, the calling thread taking part. `body` must be safe to call concurrently for different i.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace gearnvh::app {

template <typename Body>
void ParallelFor(size_t count, int threads, Body&& body) {
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int used =
      std::min<int>(threads > 0 ? threads : hardware, static_cast<int>(std::max<size_t>(count, 1)));
  std::atomic<size_t> next{0};
  auto worker = [&]() {
    for (size_t i = next++; i < count; i = next++) body(i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < used; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
}

}  // namespace gearnvh::app
