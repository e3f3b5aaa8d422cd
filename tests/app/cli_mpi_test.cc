// Scale-out of `gearnvh atlas`, a pair's and a gear train's: mpirun -np 2 equals the
// single-process atlas, and a run killed midway completes with --resume to the same atlas.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "support/example_variant.h"
#include "support/paths.h"
#include "support/run_command.h"
#include "support/sanitizer.h"

extern char** environ;

namespace gearnvh {
namespace {

namespace fs = std::filesystem;
using testing::ReadWholeFile;
using testing::RunCommand;
using testing::TempDir;

using testing::kExe;
// mpirun on loopback (as root OpenMPI also needs --allow-run-as-root). OpenMPI itself is not
// LeakSanitizer-clean (its dlopen'ed components leak at MPI_Finalize), so the sanitizer run checks
// leaks of these processes off; the code they run is the single-process code, leak-checked there.
const std::string kMpirunOptions =
    "env ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 mpirun --allow-run-as-root --oversubscribe "
    "--mca btl self,tcp --mca btl_tcp_if_include lo --mca oob_tcp_if_include lo ";
const std::string kMpirun = kMpirunOptions + "-np 2 ";
using testing::kExamples;
// 12 cells; the instrumented build runs a third of the cycles (the same code paths: these tests
// compare how cells are shared and restored, and took 107 s CPU there at full length).
#if defined(GEARNVH_UNDER_ASAN)
const std::string kAtlasCycles = " --cycles 360 --transient 90 ";
#else
const std::string kAtlasCycles = " --cycles 1080 --transient 270 ";
#endif
const std::string kAtlas = " atlas " + kExamples +
                           "/idle_rattle.yaml --x operating.speed=700rpm:1100rpm:3"
                           " --y operating.torque=0.05Nm:0.5Nm:4" +
                           kAtlasCycles;
// The rattling three-mesh train (tests/data/loose_gear_train.yaml), 12 cells of about 0.35 s each
// in Release: its atlas runs through the same ranks and checkpoint as the pair's. The instrumented
// build runs a quarter of the cycles (at half, the three train atlas tests took 245 s CPU there).
#if defined(GEARNVH_UNDER_ASAN)
const std::string kTrainCycles = " --cycles 100 --transient 25 ";
#else
const std::string kTrainCycles = " --cycles 400 --transient 100 ";
#endif
const std::string kTrainAtlas = " atlas " + std::string(GEARNVH_TEST_DATA_DIR) +
                                "/loose_gear_train.yaml --x operating.speed=900rpm:1100rpm:3"
                                " --y operating.loads[1].torque=0.1Nm:0.3Nm:4" +
                                kTrainCycles;

// The atlas document without what legitimately differs between runs (timings, threads, ranks).
std::string Comparable(const fs::path& json) {
  nlohmann::json d = nlohmann::json::parse(ReadWholeFile(json));
  for (const char* k : {"wall_s", "threads", "ranks", "restored_cells"}) d.erase(k);
  for (auto& c : d["cells"]) c.erase("wall_s");
  return d.dump();
}

// `atlas` (atlas or kTrainAtlas) on 2 ranks equals the single-process run, cell for cell.
void CheckMpiAtlas(const std::string& atlas) {
  const TempDir dir;
  const auto single = RunCommand(kExe + atlas + "--jobs 2 --out " + (dir.path() / "one").string());
  INFO(single.err);
  REQUIRE(single.exit_code == 0);
  // Loopback only; as root OpenMPI needs --allow-run-as-root; 2 ranks on 2 cores, 1 thread each.
  const auto mpi =
      RunCommand(kMpirun + kExe + atlas + "--jobs 1 --out " + (dir.path() / "two").string());
  INFO(mpi.out << mpi.err);
  REQUIRE(mpi.exit_code == 0);
  const auto doc = nlohmann::json::parse(ReadWholeFile(dir.path() / "two" / "atlas.json"));
  CHECK(doc["ranks"] == 2);
  CHECK(Comparable(dir.path() / "one" / "atlas.json") ==
        Comparable(dir.path() / "two" / "atlas.json"));
  CHECK(ReadWholeFile(dir.path() / "one" / "atlas.csv") ==
        ReadWholeFile(dir.path() / "two" / "atlas.csv"));
  CHECK(!fs::exists(dir.path() / "two" / ".atlas-checkpoint"));  // removed once complete
}

TEST_CASE("mpi: mpirun -np 2 gives the single-process atlas", "[cli][mpi]") {
  CheckMpiAtlas(kAtlas);
}

TEST_CASE("mpi: mpirun -np 2 gives the single-process atlas of a gear train", "[cli][mpi][train]") {
  CheckMpiAtlas(kTrainAtlas);
}

TEST_CASE("mpi: mpirun -np 2 gives the single-process speed sweep", "[cli][mpi]") {
  const TempDir dir;
  const std::string sweep = " sweep " + kExamples +
                            "/industrial_whine.yaml --cycles 32 "
                            "--transient 10 --jobs 1 --out ";
  REQUIRE(RunCommand(kExe + sweep + (dir.path() / "one").string()).exit_code == 0);
  const auto mpi = RunCommand(kMpirun + kExe + sweep + (dir.path() / "two").string());
  INFO(mpi.out << mpi.err);
  REQUIRE(mpi.exit_code == 0);
  for (const char* file : {"campbell.csv", "critical_speeds.csv", "waterfall.csv"}) {
    INFO(file);
    CHECK(ReadWholeFile(dir.path() / "one" / file) == ReadWholeFile(dir.path() / "two" / file));
  }
  auto comparable = [](const fs::path& p) {
    nlohmann::json d = nlohmann::json::parse(ReadWholeFile(p));
    for (auto& point : d["waterfall"]["points"]) point.erase("real_time_ratio");
    return d.dump();
  };
  CHECK(comparable(dir.path() / "one" / "sweep.json") ==
        comparable(dir.path() / "two" / "sweep.json"));
}

TEST_CASE("mpi: mpirun -np 2 gives the single-process speed sweep of a gear train",
          "[cli][mpi][train]") {
  // The rattling three-mesh train over 5 speeds: every output (per-mesh statistics, loose gears,
  // waterfall, order tracks) equals the single-process run's, so each speed crossed between the
  // ranks whole.
  const TempDir dir;
  const auto file = dir.Write(
      "train.yaml", ReadWholeFile(fs::path(GEARNVH_TEST_DATA_DIR) / "loose_gear_train.yaml") +
                        "analysis:\n  speed_sweep: {from: 800 rpm, to: 1200 rpm, points: 5}\n");
  const std::string sweep = " sweep --cycles 64 --transient 16 --jobs 1 " + file.string() + " ";
  const auto one = RunCommand(kExe + sweep + "--uff " + (dir.path() / "one.uff").string() +
                              " --out " + (dir.path() / "one").string());
  INFO(one.err);
  REQUIRE(one.exit_code == 0);
  const auto mpi =
      RunCommand(kMpirun + kExe + sweep + "--uff " + (dir.path() / "two.uff").string() + " --out " +
                 (dir.path() / "two").string());
  INFO(mpi.out << mpi.err);
  REQUIRE(mpi.exit_code == 0);
  for (const char* f : {"meshes.csv", "loose_gears.csv", "waterfall.csv"}) {
    INFO(f);
    CHECK(ReadWholeFile(dir.path() / "one" / f) == ReadWholeFile(dir.path() / "two" / f));
  }
  auto comparable = [](const fs::path& p) {
    nlohmann::json d = nlohmann::json::parse(ReadWholeFile(p));
    REQUIRE(d["points"].size() == 5);
    for (auto& point : d["points"]) {
      CHECK(point["ok"] == true);
      point.erase("real_time_ratio");
    }
    return d.dump();
  };
  CHECK(comparable(dir.path() / "one" / "sweep.json") ==
        comparable(dir.path() / "two" / "sweep.json"));
  // The UFF files differ only in their date-and-time lines (line 5 of each dataset).
  auto without_dates = [](std::string text) {
    std::istringstream in(text);
    std::string out, line;
    while (std::getline(in, line)) {
      if (line.size() == 18 && line[2] == '-' && line[6] == '-') continue;
      out += line + "\n";
    }
    return out;
  };
  const std::string uff_one = ReadWholeFile(dir.path() / "one.uff");
  CHECK(uff_one.size() > 1000);
  CHECK(without_dates(uff_one) == without_dates(ReadWholeFile(dir.path() / "two.uff")));
}

TEST_CASE("mpi: a resume that does not fit the checkpoint is refused by every rank",
          "[cli][mpi][resume]") {
  // Rank 0 alone reads the checkpoint; its refusal must reach the other rank, which would
  // otherwise wait for rank 0's list of restored cells (a hang: `timeout` makes it a failure).
  for (const std::string& atlas : {kAtlas, kTrainAtlas}) {
    INFO(atlas);
    const TempDir dir;
    const fs::path other = dir.path() / "other";
    fs::create_directories(other / ".atlas-checkpoint");
    std::ofstream(other / ".atlas-checkpoint" / "settings.json") << "{}\n";
    const auto refused = RunCommand("timeout 120 " + kMpirun + kExe + atlas +
                                    "--jobs 1 --resume --out " + other.string());
    INFO(refused.out << refused.err);
    CHECK(refused.exit_code == 2);  // --resume does not fit: a usage error, from every rank
    CHECK(refused.err.find("other settings") != std::string::npos);
    CHECK(!fs::exists(other / "atlas.json"));
  }
}

// A short sweep of the idle-rattle example into `out`, one speed at a time per rank.
std::string IdleSweepCommand(const fs::path& out) {
  return kExe + " sweep " + kExamples + "/idle_rattle.yaml --cycles 100 --transient 0 --jobs 1 " +
         "--out " + out.string();
}

TEST_CASE("mpi: a sweep that one rank cannot hold is refused by every rank, said by rank 0",
          "[cli][mpi][memory]") {
  // Rank 0 has room, rank 1 (its own limit, MPMD) has none: before, rank 1 refused alone (its
  // stderr is /dev/null) and rank 0 waited for it in the gather for ever; the timeout turns such
  // a hang into a failure.
  const TempDir dir;
  const std::string sweep = IdleSweepCommand(dir.path() / "sweep");
  const auto r =
      RunCommand("timeout 120 " + kMpirunOptions + "-np 1 env GEARNVH_MEMORY_LIMIT=100000000000 " +
                 sweep + " : -np 1 env GEARNVH_MEMORY_LIMIT=1 " + sweep);
  INFO(r.out << r.err);
  CHECK(r.exit_code == 2);
  // The limit is shared by the 2 ranks on this node: rank 1's 1 B is 0 B each.
  CHECK(r.err.find("--cycles: on rank 1, the run would hold about 374 KiB (recorded samples 200 "
                   "KiB, event log 37.5 KiB, waterfall spectra 136 KiB), more than the 0 B of "
                   "memory available (GEARNVH_MEMORY_LIMIT, shared by 2 processes on this node)") !=
        std::string::npos);
  CHECK(r.out.empty());
  CHECK(!fs::exists(dir.path() / "sweep"));
}

TEST_CASE("mpi: a malformed memory limit on one rank stops every rank with its message",
          "[cli][mpi][memory]") {
  // Only rank 1 (MPMD) has a malformed GEARNVH_MEMORY_LIMIT: it used to throw alone while rank 0
  // went on into the next collective and waited for it for ever (the timeout turns a hang into a
  // failure).
  const TempDir dir;
  const std::string sweep = IdleSweepCommand(dir.path() / "sweep");
  const std::string report = kExe + " report " + kExamples + "/idle_rattle.yaml " + kExamples +
                             "/idle_rattle.yaml --out " + (dir.path() / "report").string();
  for (const std::string& command : {sweep, report}) {
    const auto r = RunCommand("timeout 120 " + kMpirunOptions + "-np 1 " + command +
                              " : -np 1 env GEARNVH_MEMORY_LIMIT=1GB " + command);
    INFO(command << "\n" << r.out << r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("error: the environment variable GEARNVH_MEMORY_LIMIT is '1GB': it must be a "
                     "whole number of bytes") != std::string::npos);
  }
  CHECK(!fs::exists(dir.path() / "sweep"));
  CHECK(!fs::exists(dir.path() / "report"));
}

TEST_CASE("mpi: a report batch split over 2 ranks equals the single-process report", "[cli][mpi]") {
  // Rank 1 builds the second gearbox (with its own Xvfb when there is no display) and sends the
  // files to rank 0, which alone writes the report.
  // The flexible-shaft example on 5 of its 35 sweep speeds and shorter runs: what is compared is
  // how the ranks share the batch, not the sweep (its 35 speeds took 70 s CPU per report under
  // the sanitizers).
  const TempDir dir;
  const std::string flexible =
      testing::WriteExampleVariant(dir, "flexible_shafts.yaml",
                                   {{"cycles: 500", "cycles: 100"},
                                    {"transient_cycles: 200", "transient_cycles: 50"},
                                    {"to: 9000 rpm, points: 35}", "to: 9000 rpm, points: 5}"}})
          .string();
  const std::string args = " --no-atlas --width 600 --height 400 --out ";
  const auto mpi = RunCommand(kMpirun + kExe + " report " + kExamples + "/idle_rattle.yaml " +
                              flexible + args + (dir.path() / "two").string());
  INFO(mpi.out << mpi.err);
  REQUIRE(mpi.exit_code == 0);
  const auto batch = nlohmann::json::parse(ReadWholeFile(dir.path() / "two" / "report.json"));
  CHECK(batch["ranks"] == 2);
  CHECK(batch["failed"] == 0);
  const auto one = RunCommand(kExe + " report " + flexible + args + (dir.path() / "one").string());
  REQUIRE(one.exit_code == 0);
  // The gearbox rank 1 computed: the same data as in a single process, and every image arrived.
  const fs::path a = dir.path() / "one" / "flexible-shafts",
                 b = dir.path() / "two" / "flexible-shafts";
  for (const char* file : {"mesh_cycle.csv", "campbell.csv", "waterfall.csv", "spectrum.csv"}) {
    INFO(file);
    CHECK(ReadWholeFile(a / file) == ReadWholeFile(b / file));
  }
  for (const auto& entry : fs::directory_iterator(a)) {
    INFO(entry.path().filename());
    CHECK(fs::exists(b / entry.path().filename()));
    CHECK(fs::file_size(b / entry.path().filename()) > 0);
  }
}

TEST_CASE("mpi: a gear train's report page built on rank 1 equals the single-process one",
          "[cli][mpi][train]") {
  // The rattling three-mesh train, short (100 + 25 cycles, 3 sweep speeds: what is compared is
  // how ranks share the batch), second in the batch so that rank 1 builds it and sends its files
  // to rank 0.
  const TempDir dir;
  const std::string yaml =
      ReadWholeFile(fs::path(GEARNVH_TEST_DATA_DIR) / "loose_gear_train.yaml") +
      "analysis:\n  cycles: 100\n  transient_cycles: 25\n"
      "  speed_sweep: {from: 800 rpm, to: 1200 rpm, points: 3}\n";
  const auto first = dir.Write("first.yaml", yaml);  // rank 0's
  const auto train = dir.Write("train.yaml", yaml);
  const std::string args = " --no-atlas --width 600 --height 400 --out ";
  const auto mpi = RunCommand(kMpirun + kExe + " report " + first.string() + " " + train.string() +
                              args + (dir.path() / "two").string());
  INFO(mpi.out << mpi.err);
  REQUIRE(mpi.exit_code == 0);
  const auto batch = nlohmann::json::parse(ReadWholeFile(dir.path() / "two" / "report.json"));
  CHECK(batch["ranks"] == 2);
  CHECK(batch["failed"] == 0);
  const auto one =
      RunCommand(kExe + " report " + train.string() + args + (dir.path() / "one").string());
  INFO(one.err);
  REQUIRE(one.exit_code == 0);
  const fs::path a = dir.path() / "one" / "train", b = dir.path() / "two" / "train";
  for (const char* file :
       {"meshes.csv", "loose_gears.csv", "sidebands.csv", "waterfall.csv", "order_tracks.csv"}) {
    INFO(file);
    CHECK(ReadWholeFile(a / file).size() > 0);
    CHECK(ReadWholeFile(a / file) == ReadWholeFile(b / file));
  }
  int files = 0;
  for (const auto& entry : fs::directory_iterator(a)) {
    INFO(entry.path().filename());
    CHECK(fs::exists(b / entry.path().filename()));
    CHECK(fs::file_size(b / entry.path().filename()) > 0);
    ++files;
  }
  CHECK(files >= 16);  // the page, its 10 figures, CSVs, results.json and results.uff
}

// `atlas` (12 cells) killed midway completes with --resume to the cells of an uninterrupted run.
void CheckKilledAtlasResumes(const std::string& atlas) {
  const TempDir dir;
  const fs::path out = dir.path() / "killed";
  const fs::path log = out / ".atlas-checkpoint" / "cells-rank-0.jsonl";
  // Start the run, wait until a few cells are in the checkpoint, and SIGKILL it.
  std::vector<std::string> words;
  std::istringstream command(kExe + atlas + "--jobs 1 --out " + out.string());
  for (std::string w; command >> w;) words.push_back(w);
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  REQUIRE(posix_spawn(&pid, kExe.c_str(), nullptr, nullptr, argv.data(), environ) == 0);
  auto lines = [&]() {
    std::ifstream in(log);
    return std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(), '\n');
  };
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (lines() < 3 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  REQUIRE(::kill(pid, SIGKILL) == 0);
  int status = 0;
  waitpid(pid, &status, 0);
  CHECK(WIFSIGNALED(status));
  const long done_before = lines();
  INFO("cells in the checkpoint when killed: " << done_before);
  REQUIRE(done_before >= 3);
  REQUIRE(done_before < 12);  // killed midway
  CHECK(!fs::exists(out / "atlas.json"));

  const auto resumed = RunCommand(kExe + atlas + "--jobs 1 --resume --json --out " + out.string());
  INFO(resumed.err);
  REQUIRE(resumed.exit_code == 0);
  const auto doc = nlohmann::json::parse(resumed.out);
  CHECK(doc["restored_cells"].get<long>() >= done_before - 1);  // a line cut by the kill is redone
  const auto fresh = RunCommand(kExe + atlas + "--jobs 2 --out " + (dir.path() / "fresh").string());
  REQUIRE(fresh.exit_code == 0);
  CHECK(Comparable(out / "atlas.json") == Comparable(dir.path() / "fresh" / "atlas.json"));

  // A resume with other settings is refused rather than mixed.
  const fs::path other = dir.path() / "other";
  REQUIRE(std::system(("mkdir -p " + (other / ".atlas-checkpoint").string() + " && echo '{}' > " +
                       (other / ".atlas-checkpoint" / "settings.json").string())
                          .c_str()) == 0);
  const auto refused = RunCommand(kExe + atlas + "--resume --out " + other.string());
  CHECK(refused.exit_code == 2);  // --resume does not fit: a usage error
  CHECK(refused.err.find("other settings") != std::string::npos);
}

TEST_CASE("mpi: an atlas killed midway completes with --resume to the same cells",
          "[cli][resume]") {
  CheckKilledAtlasResumes(kAtlas);
}

TEST_CASE("a gear train's atlas killed midway completes with --resume to the same cells",
          "[cli][resume][train]") {
  CheckKilledAtlasResumes(kTrainAtlas);
}

}  // namespace
}  // namespace gearnvh
