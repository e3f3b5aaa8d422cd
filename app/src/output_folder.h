// An output folder (--out DIR) that is never left half-written and never loses earlier results:
//  - checked before any computation: DIR is a directory or absent, its filesystem is writable and
//    not full (IoError, exit 4, otherwise, naming the flag, DIR and the system's reason; "the disk
//    is full" only when the filesystem has blocks and too few are free);
//  - DIR is taken as the folder it names (symlinks resolved): every name of one folder shares its
//    lock, staging folder and messages;
//  - one writer at a time: an advisory lock (flock) on "<parent>/.<DIR>.lock"; a second run
//    refuses at once, naming the process that holds it (lock and staging folder go inside an
//    existing DIR, as .gearnvh.lock and .gearnvh.partial-<pid>, when its parent is not writable);
//  - everything is written into a hidden staging folder "<parent>/.<DIR>.partial-<pid>" first;
//    staging folders of killed runs are removed by the next run into DIR (it holds the lock, so
//    they cannot belong to a live writer);
//  - Commit() moves each top-level entry of the staging folder into DIR, replacing an entry of the
//    same name by an atomic exchange, so every file or gearbox folder is either the old one or the
//    complete new one; entries of DIR the run did not produce stay. If a move fails, the ones
//    already made are undone, DIR is as before, and the complete new results are kept in a
//    visible folder "<DIR>.new-<pid>" that the error names.
// The staging folder and the lock are released on every exit path (destructor, and on SIGINT /
// SIGTERM / SIGHUP through cleanup_on_exit.h).
#pragma once

#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace gearnvh::app {

class IoError;  // command_errors.h

class OutputFolder {
 public:
  OutputFolder(const std::filesystem::path& target, const std::string& flag);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& staging() const { return staging_; }
  // Writes one file into the staging folder (whole or not at all); IoError WriteFailure otherwise.
  void Write(const std::string& name, const std::string& content) const;
  // The same, the content written by `write` as it goes (WriteFileAtomically).
  void Write(const std::string& name, const std::function<void(std::FILE*)>& write) const;
  // The error of a write into the staging folder that failed for `reason` (the system's: "No
  // space left on device"): names the flag, DIR and the reason, and that DIR is unchanged.
  IoError WriteFailure(const std::string& reason) const;
  void Commit();

 private:
  void CheckTarget(const std::string& flag);
  std::filesystem::path Beside(const std::string& suffix) const;
  void Lock();
  void RemoveStaleStaging() const;
  void Unlock();

  std::string named_;  // "--out DIR", the head of every error
  std::filesystem::path target_, work_dir_, staging_, lock_path_;
  int lock_fd_ = -1;
  bool committed_ = false;
};

// Opens `out` (when given) on rank 0 before any work. With `every_rank` (the commands that split
// their work under mpirun) every rank learns rank 0's verdict and throws IoError alike, so no rank
// waits for a rank that gave up. Other ranks get nullptr.
std::unique_ptr<OutputFolder> OpenOutputFolder(const std::optional<std::string>& out,
                                               const std::string& flag, bool every_rank);

}  // namespace gearnvh::app
