// Temporary outputs are removed on every exit path: normal return and exceptions (RAII owners
// call Forget/remove themselves), and SIGINT, SIGTERM, SIGHUP: InstallSignalCleanup() blocks those
// signals in every thread and a dedicated thread waits for them, removes every registered path and
// then lets the signal kill the process as usual (so the parent sees "killed by SIGTERM").
#pragma once

#include <filesystem>

namespace gearnvh::app {

// Call first thing in main(), before any thread is started (threads inherit the signal mask).
void InstallSignalCleanup();

// Paths removed (recursively) if a signal ends the process.
void RemoveOnSignal(const std::filesystem::path& path);
void ForgetOnSignal(const std::filesystem::path& path);

}  // namespace gearnvh::app
