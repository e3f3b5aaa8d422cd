#include "cleanup_on_exit.h"

#include <pthread.h>
#include <signal.h>

#include <csignal>
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

[[noreturn]] void WaitAndClean(sigset_t set) {
  int sig = 0;
  while (sigwait(&set, &sig) != 0) {
  }
  {
    const std::lock_guard<std::mutex> lock(g_mutex);
    for (const std::filesystem::path& p : Registered()) {
      std::error_code ec;
      std::filesystem::remove_all(p, ec);
    }
  }
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
