#include "report_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "cleanup_on_exit.h"
#include "command_errors.h"
#include "display_units.h"
#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/render/display.h"
#include "gearnvh/render/plots.h"
#include "mpi_context.h"
#include "output_folder.h"
#include "report_batch.h"

namespace gearnvh::app {

namespace fs = std::filesystem;

namespace {

std::string Slug(const std::string& file) {
  std::string stem = fs::path(file).stem().string(), out;
  for (char c : stem) {
    out += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::tolower(c)) : '-';
  }
  return out.empty() ? "gearbox" : out;
}

// Says on stderr which finished gearboxes had sweep speeds that failed (listed on their pages);
// true when any had: part of the work failed.
bool ReportFailedSpeeds(const std::vector<GearboxEntry>& entries) {
  bool any = false;
  for (const GearboxEntry& e : entries) {
    const int speeds = e.ok ? e.summary.value("failed_speeds", 0) : 0;
    if (speeds == 0) continue;
    std::cerr << "error: " << e.file << ": " << Count(speeds, "sweep speed", "sweep speeds")
              << " failed (listed on its page and in its results.json)\n";
    any = true;
  }
  return any;
}

}  // namespace

int RunReport(const ReportCommandOptions& o) {
  const int rank = MpiContext::Rank(), ranks = MpiContext::Size();
  int code = 0;
  try {
    if (o.files.empty()) throw InputError("FILE", 0, "(none)", "give at least one gearbox file");
    const render::ImageOptions image{o.width, o.height, o.dpi};
    try {
      image.Validate();
    } catch (const std::invalid_argument& e) {
      throw InputError("--width/--height/--dpi", 0, "", e.what());
    }
    const fs::path out = fs::absolute(o.out).lexically_normal();
    if (fs::exists(out) && fs::is_directory(out) && !fs::is_empty(out) &&
        !fs::exists(out / kReportMarker)) {
      throw IoError("--out " + o.out +
                    ": exists and is not a gearnvh report; refusing to mix results into it "
                    "(choose a new folder or an earlier report's folder)");
    }
    // Checked, locked and staged before any work (every rank learns rank 0's verdict).
    const std::unique_ptr<OutputFolder> target = OpenOutputFolder(o.out, "--out", true);
    // Images need a display: fail before any work when rank 0 has none (every rank starts its own
    // Xvfb when DISPLAY is unset; a rank without one reports its gearboxes as failed).
    const render::DisplayStatus& display = render::EnsureDisplay();
    if (MpiContext::BroadcastInt(display.ok() ? 1 : 0) == 0) {
      std::cerr << "error: " << display.message << "\n";
      return 1;
    }
    const std::string suffix = std::to_string(static_cast<long>(::getpid()));
    // Rank 0 builds the report in the output folder's staging folder; other ranks in a private
    // scratch folder whose files they send to rank 0.
    const fs::path scratch =
        fs::temp_directory_path() / ("gearnvh-report-rank" + std::to_string(rank) + "-" + suffix);
    const fs::path staging = rank == 0 ? target->staging() : scratch;
    if (rank != 0) {
      fs::remove_all(scratch);
      fs::create_directories(scratch);
      RemoveOnSignal(scratch);
    }
    std::vector<std::string> folders;
    std::set<std::string> used;
    for (const std::string& f : o.files) {
      std::string name = Slug(f);
      for (int k = 2; used.count(name) != 0; ++k) name = Slug(f) + "-" + std::to_string(k);
      used.insert(name);
      folders.push_back(name);
    }
    std::vector<size_t> mine;
    for (size_t i = 0; i < o.files.size(); ++i) {
      if (static_cast<int>(i % static_cast<size_t>(ranks)) == rank) mine.push_back(i);
    }
    const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const int jobs =
        std::max(1, std::min<int>(o.jobs > 0 ? o.jobs : hardware, static_cast<int>(mine.size())));
    const int inner = std::max(1, hardware / jobs);
    // Each gearbox in flight gets its share of the memory limit (docs/cli.md, "Memory").
    std::optional<MemoryLimit> memory_share = AvailableMemoryOnEveryRank(jobs * inner - 1);
    if (memory_share && jobs > 1) {
      memory_share->bytes /= static_cast<size_t>(jobs);
      memory_share->source += fmt::format(", shared by {} gearboxes in parallel", jobs);
    }
    std::vector<GearboxEntry> entries(o.files.size());
    std::atomic<size_t> next{0};
    std::mutex progress_mutex;
    size_t done = 0;
    const bool on_terminal = rank == 0 && ::isatty(STDERR_FILENO) != 0;
    // One gearbox: its stages and cycles on the terminal (a batch shows the gearboxes done).
    StageProgress stage;
    if (on_terminal && mine.size() == 1) {
      stage = [&progress_mutex, file = o.files[mine.front()]](const std::string& what) {
        const std::lock_guard<std::mutex> lock(progress_mutex);
        fmt::print(stderr, "\rreport: {}: {}\x1b[K", file, what);
      };
    }
    auto worker = [&]() {
      for (size_t k = next++; k < mine.size(); k = next++) {
        const size_t i = mine[k];
        if (display.ok()) {
          entries[i] =
              BuildGearboxReport(o.files[i], staging / folders[i], o, inner, stage, memory_share);
        } else {
          entries[i].file = o.files[i];
          entries[i].folder = folders[i];
          entries[i].error = display.message;
        }
        const std::lock_guard<std::mutex> lock(progress_mutex);
        ++done;
        if (on_terminal && !stage) {
          fmt::print(stderr, "\rreport: {} of {}{}", done,
                     Count(static_cast<long>(mine.size()), "gearbox", "gearboxes"),
                     ranks > 1 ? fmt::format(" on rank 0 of {}", ranks) : "");
        }
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < jobs; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (on_terminal) fmt::print(stderr, "\n");
    if (ranks > 1) {
      const std::vector<std::string> parts =
          MpiContext::GatherToRoot(rank == 0 ? std::string() : PackEntries(mine, entries, staging));
      if (rank != 0) {
        fs::remove_all(scratch);
        ForgetOnSignal(scratch);
        return MpiContext::BroadcastInt(0);
      }
      for (size_t r = 1; r < parts.size(); ++r) UnpackEntries(parts[r], entries, staging);
    }

    // A gearbox whose files could not be written (a full disk): the report cannot be written,
    // whatever the others did; one error naming DIR and the reason (exit 4).
    for (const GearboxEntry& e : entries) {
      if (!e.io_reason.empty()) throw target->WriteFailure(e.io_reason);
    }
    int failed = 0, internal = 0;
    for (const GearboxEntry& e : entries) {
      failed += e.ok ? 0 : 1;
      internal += e.internal ? 1 : 0;
      if (!e.ok) fs::remove_all(staging / e.folder);
    }
    for (const GearboxEntry& e : entries) {
      if (!e.ok) std::cerr << "error: " << e.error << "\n";
    }
    if (failed == static_cast<int>(entries.size())) {
      // Nothing new to show: DIR (an earlier report, or nothing) stays exactly as it was.
      std::cerr << "error: all " << entries.size() << " gearboxes failed; "
                << (fs::exists(out) ? out.string() + " is unchanged" : "nothing was written")
                << "\n";
      return MpiContext::BroadcastInt(internal > 0 ? kExitInternal : kExitInput);
    }
    // The batch index covers this run and keeps what an earlier report in DIR showed: a gearbox
    // that failed now keeps its earlier folder, earlier gearboxes not in this run stay listed.
    std::vector<GearboxEntry> listed = entries;
    std::set<std::string> this_run(folders.begin(), folders.end());
    for (GearboxEntry e : EarlierEntries(out)) {
      if (this_run.count(e.folder) == 0) {
        e.from_earlier = true;
        listed.push_back(e);
        continue;
      }
      for (GearboxEntry& now : listed) {
        if (!now.ok && now.folder == e.folder) now.earlier_kept = true;
      }
    }
    nlohmann::json batch = nlohmann::json::array();
    for (const GearboxEntry& e : listed) {
      batch.push_back({{"file", e.file},
                       {"folder", e.ok || e.earlier_kept ? e.folder : ""},
                       {"name", e.name},
                       {"ok", e.ok},
                       {"error", e.error},
                       {"earlier_result_kept", e.earlier_kept},
                       {"from_earlier_run", e.from_earlier},
                       {"summary", e.summary},
                       {"wall_s", e.wall_s}});
    }
    target->Write("index.html", BatchIndex(listed));
    target->Write(
        "report.json",
        nlohmann::json{{"gearboxes", batch}, {"failed", failed}, {"ranks", ranks}}.dump(1) + "\n");
    target->Write(kReportMarker, "gearnvh report\n");
    // Each gearbox folder and the index replace their earlier versions one by one, atomically.
    target->Commit();
    for (const GearboxEntry& e : entries) {
      if (e.ok) {
        fmt::print("{}: {} -> {}/index.html ({:.1f} s)\n", e.file, e.name,
                   (out / e.folder).string(), e.wall_s);
      }
    }
    fmt::print("report: {}\n", (out / "index.html").string());
    if (failed > 0) {
      std::cerr << "error: " << failed << " of "
                << Count(static_cast<long>(entries.size()), "gearbox", "gearboxes")
                << " failed (listed in the batch index)\n";
      code = internal > 0 ? kExitInternal : kExitInput;
    }
    if (ReportFailedSpeeds(entries) && code == 0) code = kExitInput;
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return ExitCodeOf(e);  // every rank sees the same input and the same error
  } catch (const MemoryLimitVariableError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitInput;  // the same error on every rank (AvailableMemoryOnEveryRank)
  } catch (const IoError& e) {
    std::cerr << "error: " << e.what() << "\n";
    code = kExitIo;
  } catch (const fs::filesystem_error& e) {
    std::cerr << "error: " << e.what() << "\n";
    code = kExitIo;
  }
  return MpiContext::BroadcastInt(code);
}

}  // namespace gearnvh::app
