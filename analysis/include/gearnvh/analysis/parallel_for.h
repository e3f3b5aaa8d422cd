// Runs body(i) for i = 0 .. count-1 on `threads` threads (0: all hardware threads), each index
// once, the calling thread taking part. `body` must be safe to call concurrently for different i.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <numbers>
#include <thread>
#include <vector>

namespace gearnvh {

// The threads ParallelFor(count, threads, ...) runs on: at most one per index.
inline int ParallelWorkers(size_t count, int threads) {
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::min<int>(threads > 0 ? threads : hardware,
                       static_cast<int>(std::max<size_t>(count, 1)));
}

template <typename Body>
void ParallelFor(size_t count, int threads, Body&& body) {
  const int used = ParallelWorkers(count, threads);
  std::atomic<size_t> next{0};
  auto worker = [&]() {
    for (size_t i = next++; i < count; i = next++) body(i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < used; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
}

// One point of a speed sweep (the pair's or a train's: both carry speed_rad_s, speed_rpm, ok and
// message): `run()` fills it; an exception becomes a failed point with its message, so a sweep
// goes on past one bad speed.
template <typename Point, typename Run>
void RunSweepPoint(Point& p, double speed, Run&& run) {
  try {
    p = run();
  } catch (const std::exception& e) {
    p.speed_rad_s = speed;
    p.speed_rpm = speed * 60.0 / (2.0 * std::numbers::pi);
    p.ok = false;
    p.message = e.what();
  }
}

// Counts finished points from several threads and reports (done, total) under a lock.
class SweepProgressCounter {
 public:
  SweepProgressCounter(int total, std::function<void(int, int)> report)
      : total_(total), report_(std::move(report)) {}
  void Tick() {
    const std::lock_guard<std::mutex> lock(mutex_);
    ++done_;
    if (report_) report_(done_, total_);
  }

 private:
  std::mutex mutex_;
  int done_ = 0;
  int total_;
  std::function<void(int, int)> report_;
};

}  // namespace gearnvh
