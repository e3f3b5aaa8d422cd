#include "cleanup_on_exit.h"

#include <fmt/core.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <mutex>
#include <set>
#include <thread>

namespace gearnvh::app {

namespace {

std::mutex g_mutex;
std::set<std::filesystem::path>& Registered() {
  static auto* paths = new std::set<std::filesystem::path>();  // outlives static destructors
  return *paths;
}

sigset_t CleanupSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

const char* SignalName(int sig) {
  switch (sig) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    default:
      return "SIGHUP";
  }
}

// Removes `path` while other threads may still write into it: renamed first (same folder, a name
// that still starts as the original, so a later run's stale-staging sweep finds it), so no new
// file can appear in it by its old name while remove_all empties it.
bool Remove(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::path doomed = path;
  doomed += ".removing";
  std::filesystem::rename(path, doomed, ec);
  if (ec) doomed = path;
  const bool removed = std::filesystem::remove_all(doomed, ec) > 0;
  return removed && !std::filesystem::exists(doomed, ec);
}

[[noreturn]] void WaitAndClean(sigset_t set) {
  int sig = 0;
  while (sigwait(&set, &sig) != 0) {
  }
  bool removed = false;
  {
    const std::lock_guard<std::mutex> lock(g_mutex);
    for (const std::filesystem::path& p : Registered()) removed = Remove(p) || removed;
  }
  // A user who pressed Ctrl-C (or whose job was killed) learns why the run ended and that no
  // output was half-written; on a terminal the progress line is cleared first.
  fmt::print(stderr, "{}gearnvh: stopped by {}{}\n", ::isatty(STDERR_FILENO) != 0 ? "\r\x1b[K" : "",
             SignalName(sig),
             removed ? ": the unfinished outputs were removed, earlier results are unchanged" : "");
  std::fflush(stderr);
  // Die of the signal itself: default action, unblocked in this thread, sent to this thread.
  std::signal(sig, SIG_DFL);
  sigset_t one;
  sigemptyset(&one);
  sigaddset(&one, sig);
  pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  raise(sig);
  std::_Exit(128 + sig);  // not reached
}

}  // namespace

void InstallSignalCleanup() {
  const sigset_t set = CleanupSignals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread(WaitAndClean, set).detach();
}

void RemoveOnSignal(const std::filesystem::path& path) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  Registered().insert(path);
}

void ForgetOnSignal(const std::filesystem::path& path) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  Registered().erase(path);
}

}  // namespace gearnvh::app
