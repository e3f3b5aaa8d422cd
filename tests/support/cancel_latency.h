// Measures how fast a computation answers its cancel flag (SolverOptions::cancel and the like).
#pragma once

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "gearnvh/solver/solver_options.h"
#include "support/sanitizer.h"

namespace gearnvh::testing {

// How soon a cancelled call must end: 1 s, 5 s in the instrumented build (ASan at -O1 runs the
// numerical code about five times slower, and a single eigenproblem or reduction is not polled
// inside).
#ifdef GEARNVH_UNDER_ASAN
inline constexpr double kCancelBoundSeconds = 5.0;
#else
inline constexpr double kCancelBoundSeconds = 1.0;
#endif

// Runs work(&flag) while another thread sets the flag `delay_s` seconds after the start. REQUIREs
// that the work throws RunCancelled (it must still be running when the flag is set: callers pick
// work that lasts far longer than the delay) and returns the seconds from the set to the throw.
template <typename Work>
double SecondsToCancel(double delay_s, Work&& work) {
  std::atomic<bool> flag{false};
  std::chrono::steady_clock::time_point set_at;
  std::thread setter([&] {
    std::this_thread::sleep_for(std::chrono::duration<double>(delay_s));
    set_at = std::chrono::steady_clock::now();
    flag.store(true);
  });
  bool cancelled = false;
  try {
    work(&flag);
  } catch (const RunCancelled&) {
    cancelled = true;
  } catch (...) {
    setter.join();  // never leave a joinable thread behind (std::terminate)
    throw;
  }
  const auto stopped = std::chrono::steady_clock::now();
  setter.join();  // set_at is read only after the join
  REQUIRE(cancelled);
  return std::chrono::duration<double>(stopped - set_at).count();
}

}  // namespace gearnvh::testing
