#include "output_folder.h"

#include <fcntl.h>
#include <stdio.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "atomic_file.h"
#include "cleanup_on_exit.h"
#include "command_errors.h"
#include "mpi_context.h"

namespace gearnvh::app {

namespace fs = std::filesystem;

namespace {

// Less free space than this and the run is refused before it starts: a report or a trajectory
// needs more, and a nearly full disk is better reported now than after an hour of computing.
constexpr unsigned long long kMinFreeBytes = 1ULL << 20;

std::string Errno() { return std::strerror(errno); }

// ".<name><suffix>": the hidden names beside the target (lock, staging).
std::string Hidden(const fs::path& target, const std::string& suffix) {
  std::string name(".");
  name += target.filename().string();
  name += suffix;
  return name;
}

// Inside the target itself (its parent is not writable): ".gearnvh<suffix>".
constexpr const char* kInsideBase = "gearnvh";

bool Exists(const fs::path& p) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(p, ec));
}

// Swaps two paths atomically (both exist); false with errno set when the filesystem cannot.
bool Exchange(const fs::path& a, const fs::path& b) {
  return ::renameat2(AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0;
}

}  // namespace

OutputFolder::OutputFolder(const fs::path& target, const std::string& flag) {
  target_ = fs::absolute(target).lexically_normal();
  if (!target_.has_filename()) target_ = target_.parent_path();
  // The folder itself, not the name it was given: a symlink to DIR (or through a symlinked
  // parent) must meet the same lock and stage beside the real DIR, on its filesystem.
  std::error_code ec;
  const fs::path real = fs::weakly_canonical(target_, ec);
  if (!ec) target_ = real;
  CheckTarget(flag);
  Lock();
  try {
    RemoveStaleStaging();
    staging_ = Beside(".partial-" + std::to_string(::getpid()));
    if (::mkdir(staging_.c_str(), 0755) != 0) {
      throw IoError(named_ + ": cannot write into " + work_dir_.string() + ": " + Errno());
    }
    RemoveOnSignal(staging_);
    // Prove it: a file written, flushed and renamed (a full or read-only disk fails here).
    Write(".probe", "gearnvh\n");
    fs::remove(staging_ / ".probe");
  } catch (...) {
    if (!staging_.empty()) {
      std::error_code ec;
      fs::remove_all(staging_, ec);
      ForgetOnSignal(staging_);
    }
    Unlock();
    throw;
  }
}

OutputFolder::~OutputFolder() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
  ForgetOnSignal(staging_);
  Unlock();
}

void OutputFolder::CheckTarget(const std::string& flag) {
  named_ = flag + " " + target_.string();
  const std::string& named = named_;
  std::error_code ec;
  if (Exists(target_) && !fs::is_directory(target_, ec)) {
    throw IoError(named + ": exists and is not a directory");
  }
  const fs::path parent = target_.parent_path();
  fs::create_directories(parent, ec);
  if (ec) throw IoError(named + ": cannot create " + parent.string() + ": " + ec.message());
  const bool target_exists = Exists(target_);
  if (target_exists && ::access(target_.c_str(), W_OK | X_OK) != 0) {
    throw IoError(named + ": " + target_.string() + " is not writable: " + Errno());
  }
  // The lock and the staging folder live beside DIR; inside an existing DIR when its parent is
  // not ours to write (--out . in a home directory).
  work_dir_ = parent;
  if (::access(parent.c_str(), W_OK | X_OK) != 0) {
    if (!target_exists) {
      throw IoError(named + ": " + parent.string() + " is not writable: " + Errno());
    }
    work_dir_ = target_;
  }
  struct statvfs fs_info {};
  if (::statvfs(work_dir_.c_str(), &fs_info) == 0) {
    if ((fs_info.f_flag & ST_RDONLY) != 0) {
      throw IoError(named + ": " + work_dir_.string() + " is on a read-only filesystem");
    }
    const unsigned long long free_bytes =
        static_cast<unsigned long long>(fs_info.f_bavail) * fs_info.f_frsize;
    // A filesystem without blocks (proc, sysfs) reports no free space and is not full: the lock
    // and the staging folder below fail with the reason it refuses.
    if (fs_info.f_blocks > 0 && free_bytes < kMinFreeBytes) {
      throw IoError(named + ": the disk is full (" + std::to_string(free_bytes / 1024) +
                    " kB free, at least " + std::to_string(kMinFreeBytes / 1024) +
                    " kB needed to start)");
    }
  }
}

fs::path OutputFolder::Beside(const std::string& suffix) const {
  return work_dir_ / (work_dir_ == target_ ? Hidden(kInsideBase, suffix) : Hidden(target_, suffix));
}

void OutputFolder::Lock() {
  lock_path_ = Beside(".lock");
  for (;;) {
    const int fd = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
      throw IoError(named_ + ": cannot create the lock " + lock_path_.string() + ": " + Errno());
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      char pid[32] = {};
      const ssize_t n = ::pread(fd, pid, sizeof(pid) - 1, 0);
      ::close(fd);
      throw IoError(target_.string() + " is being written by another gearnvh run (pid " +
                    (n > 0 ? std::string(pid, static_cast<size_t>(n)) : std::string("?")) +
                    ", lock " + lock_path_.string() +
                    "); wait for it to finish or choose another --out folder");
    }
    // The holder before us may have removed the lock file after we opened it: then our lock is
    // on a deleted file and means nothing; take the lock again on the current file.
    struct stat held {
    }, current{};
    if (::fstat(fd, &held) == 0 && ::stat(lock_path_.c_str(), &current) == 0 &&
        held.st_ino == current.st_ino && held.st_dev == current.st_dev) {
      lock_fd_ = fd;
      break;
    }
    ::close(fd);
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(lock_fd_, 0) != 0 ||
      ::pwrite(lock_fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    // The lock holds without the pid; only the message of a second run is poorer.
  }
  RemoveOnSignal(lock_path_);
}

void OutputFolder::Unlock() {
  if (lock_fd_ < 0) return;
  ForgetOnSignal(lock_path_);
  ::unlink(lock_path_.c_str());
  ::close(lock_fd_);
  lock_fd_ = -1;
}

void OutputFolder::RemoveStaleStaging() const {
  const std::string partial = Beside(".partial-").filename().string();
  const std::string old = Hidden(target_, ".old-");
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(work_dir_, ec)) {
    const std::string n = entry.path().filename().string();
    if (n.rfind(partial, 0) == 0) {
      fs::remove_all(entry.path(), ec);
    } else if (n.rfind(old, 0) == 0) {
      // An earlier gearnvh moved DIR aside to swap a report in and was killed before the swap:
      // that is the last good result.
      if (!Exists(target_)) {
        fs::rename(entry.path(), target_, ec);
      } else {
        fs::remove_all(entry.path(), ec);
      }
    }
  }
}

void OutputFolder::Write(const std::string& name, const std::string& content) const {
  Write(name, [&content](std::FILE* f) { std::fwrite(content.data(), 1, content.size(), f); });
}

void OutputFolder::Write(const std::string& name,
                         const std::function<void(std::FILE*)>& write) const {
  try {
    WriteFileAtomically((staging_ / name).string(), write);
  } catch (const IoError& e) {
    throw WriteFailure(e.reason().empty() ? e.what() : e.reason());
  }
}

IoError OutputFolder::WriteFailure(const std::string& reason) const {
  // The staging folder is gone with this run: the user's folder is what to name.
  return IoError(named_ + ": cannot write the results: " + reason + "; " +
                     (Exists(target_) ? target_.string() + " is unchanged" : "nothing was written"),
                 reason);
}

void OutputFolder::Commit() {
  std::string failure;
  if (!Exists(target_)) {
    if (::rename(staging_.c_str(), target_.c_str()) == 0) {
      committed_ = true;
      ForgetOnSignal(staging_);
      return;
    }
    failure = "cannot rename " + staging_.string() + " to " + target_.string() + ": " + Errno();
  } else {
    struct Move {
      fs::path from, to;
      bool exchanged;
    };
    std::vector<Move> done;
    std::error_code ec;
    std::vector<fs::path> entries;
    for (const auto& e : fs::directory_iterator(staging_, ec)) entries.push_back(e.path());
    if (ec) failure = "cannot list " + staging_.string() + ": " + ec.message();
    for (const fs::path& from : entries) {
      if (!failure.empty()) break;
      const fs::path to = target_ / from.filename();
      const bool replace = Exists(to);
      bool ok = false;
      if (replace) {
        ok = Exchange(from, to);
        // A filesystem without RENAME_EXCHANGE: a file can still be replaced atomically.
        if (!ok && errno == EINVAL && !fs::is_directory(from)) {
          ok = ::rename(from.c_str(), to.c_str()) == 0;
          if (ok) {
            done.push_back({from, to, false});
            continue;
          }
        }
      } else {
        ok = ::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0;
      }
      if (!ok) {
        failure = "cannot move " + from.filename().string() + " into " + target_.string() + ": " +
                  Errno();
        break;
      }
      done.push_back({from, to, replace});
    }
    if (failure.empty()) {
      // The staging folder now holds the replaced old entries.
      fs::remove_all(staging_, ec);
      committed_ = true;
      ForgetOnSignal(staging_);
      return;
    }
    // Undo, newest first: the target is as it was.
    for (auto it = done.rbegin(); it != done.rend(); ++it) {
      if (it->exchanged) {
        Exchange(it->from, it->to);
      } else {
        ::rename(it->to.c_str(), it->from.c_str());
      }
    }
  }
  // Keep the complete new results where the user can see them.
  fs::path kept = staging_;
  const fs::path visible = target_.string() + ".new-" + std::to_string(::getpid());
  if (::rename(staging_.c_str(), visible.c_str()) == 0) kept = visible;
  committed_ = true;
  ForgetOnSignal(staging_);
  throw IoError(failure + "; " + target_.string() +
                " is unchanged; the complete new results are in " + kept.string());
}

std::unique_ptr<OutputFolder> OpenOutputFolder(const std::optional<std::string>& out,
                                               const std::string& flag, bool every_rank) {
  if (!out) return nullptr;
  std::unique_ptr<OutputFolder> folder;
  std::string failure;
  if (MpiContext::Rank() == 0) {
    try {
      folder = std::make_unique<OutputFolder>(*out, flag);
    } catch (const IoError& e) {
      failure = e.what();
    }
  }
  if (every_rank) failure = MpiContext::BroadcastString(failure);
  if (!failure.empty()) throw IoError(failure);
  return folder;
}

}  // namespace gearnvh::app
