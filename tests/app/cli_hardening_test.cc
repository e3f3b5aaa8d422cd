// Nothing lost, nothing hangs, nothing absurd: the exit-code table, output folders that are checked
// first, locked, written whole or not at all and never lose an earlier result (a failed re-run, a
// full disk, a failed rename, a signal, kill -9, a concurrent writer), and malformed inputs.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "support/run_command.h"
#include "support/sanitizer.h"
#include "support/paths.h"

extern char** environ;

namespace gearnvh {
namespace {

namespace fs = std::filesystem;
using testing::ReadWholeFile;
using testing::RunCommand;
using testing::TempDir;

using testing::kExe;
using testing::kExamples;
const std::string kWhine = kExamples + "/industrial_whine.yaml";

// Names in `dir` that a run must never leave behind.
std::vector<std::string> Debris(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.find(".partial-") != std::string::npos || n.find(".tmp-") != std::string::npos ||
        n.find(".lock") != std::string::npos) {
      out.push_back(e.path().string());
    }
  }
  return out;
}

// An earlier gearnvh report, written by hand (a real one takes seconds to make): its files must
// come out of a failed run byte for byte.
void WriteEarlierReport(const fs::path& dir) {
  fs::create_directories(dir / "kept");
  std::ofstream(dir / ".gearnvh-report") << "gearnvh report\n";
  std::ofstream(dir / "index.html") << "<html>the earlier batch</html>\n";
  std::ofstream(dir / "kept" / "index.html") << "<html>an earlier gearbox</html>\n";
  std::ofstream(dir / "report.json") << nlohmann::json{
      {"gearboxes",
       {{{"file", "kept.yaml"},
         {"folder", "kept"},
         {"name", "kept"},
         {"ok", true},
         {"error", ""},
         {"summary", {{"tier", "1"}, {"regime", "no impact"}}},
         {"wall_s", 1.0}}}},
      {"failed", 0},
      {"ranks", 1}}.dump(1);
}

std::map<std::string, std::string> Snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = ReadWholeFile(e.path());
  }
  return files;
}

// Runs gearnvh in the background (stdout/stderr to files in `log_dir`), DISPLAY unset.
pid_t Spawn(const std::vector<std::string>& args, const fs::path& log_dir) {
  std::vector<std::string> all{kExe};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<char*> env;
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::string(*e).rfind("DISPLAY=", 0) != 0) env.push_back(*e);
  }
  env.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, (log_dir / "out.txt").c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, (log_dir / "err.txt").c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, kExe.c_str(), &actions, nullptr, argv.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

// Child processes of `parent` whose command name is `name` (from /proc).
std::vector<pid_t> Children(pid_t parent, const std::string& name) {
  std::vector<pid_t> out;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string stat = ReadWholeFile(e.path() / "stat");
    const size_t close = stat.rfind(')');
    if (close == std::string::npos) continue;
    const std::string comm = stat.substr(stat.find('(') + 1, close - stat.find('(') - 1);
    std::istringstream rest(stat.substr(close + 2));
    char state = 0;
    long ppid = 0;
    rest >> state >> ppid;
    if (ppid == parent && comm == name) out.push_back(std::stoi(e.path().filename().string()));
  }
  return out;
}

bool Alive(pid_t pid) {
  const std::string stat = ReadWholeFile("/proc/" + std::to_string(pid) + "/stat");
  const size_t close = stat.rfind(')');
  return close != std::string::npos && stat.size() > close + 2 && stat[close + 2] != 'Z';
}

template <typename Condition>
bool WaitFor(Condition condition, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return condition();
}

bool HasPartial(const fs::path& parent) {
  for (const auto& e : fs::directory_iterator(parent)) {
    if (e.path().filename().string().find(".partial-") != std::string::npos) return true;
  }
  return false;
}

// Runs `script` as root of a private user + mount namespace (so it can mount a small tmpfs);
// false when this machine does not allow that (the test then says so and checks nothing more).
bool NamespacesAvailable() {
  return RunCommand("unshare -rm sh -c 'mount -t tmpfs -o size=64k tmpfs /mnt'").exit_code == 0;
}

TEST_CASE("exit codes: missing files are input errors naming the path, usage errors are 2",
          "[cli][hardening]") {
  const TempDir dir;
  const std::string missing = (dir.path() / "typo.yaml").string();
  for (const char* command : {"check", "simulate", "sweep", "tiers", "validate", "orbits"}) {
    INFO(command);
    const auto run = RunCommand(kExe + " " + command + " " + missing);
    CHECK(run.exit_code == 1);
    CHECK(run.err.find(missing) != std::string::npos);
  }
  // An empty file name and a folder say so, not "cannot open file".
  const auto empty = RunCommand(kExe + " check ''");
  CHECK(empty.exit_code == 1);
  CHECK(empty.err.find("the file name is empty") != std::string::npos);
  CHECK(empty.err.find("cannot open") == std::string::npos);
  const auto folder = RunCommand(kExe + " check " + dir.path().string());
  CHECK(folder.exit_code == 1);
  CHECK(folder.err.find("error: " + dir.path().string() + ": ") != std::string::npos);
  CHECK(folder.err.find("is a directory, not a gearbox file") != std::string::npos);
  // Several files: each gets its verdict; the good one is still checked.
  const auto both = RunCommand(kExe + " check " + kWhine + " " + missing);
  CHECK(both.exit_code == 1);
  CHECK(both.out.find("Industrial reducer") != std::string::npos);
  CHECK(both.err.find(missing) != std::string::npos);

  const auto tier = RunCommand(kExe + " simulate " + kWhine + " --tier 0");
  CHECK(tier.exit_code == 2);
  CHECK(tier.err.find("--tier") != std::string::npos);
  const auto axis = RunCommand(kExe + " atlas " + kWhine + " --x bogus");
  CHECK(axis.exit_code == 2);
  for (const char* command : {"simulate", "sweep", "atlas", "orbits"}) {
    INFO(command);
    const auto method = RunCommand(kExe + " " + command + " " + kWhine + " --method v4");
    CHECK(method.exit_code == 2);
    CHECK(method.err.find("--method") != std::string::npos);
    CHECK(method.err.find("must be one of v1, v2, v3, fused, got v4") != std::string::npos);
  }
  CHECK(RunCommand(kExe + " simulate " + kWhine + " --no-such-flag").exit_code == 2);
  CHECK(RunCommand(kExe + " simulate " + kWhine + " --cycles 0").exit_code == 2);

  const auto version = RunCommand(kExe + " --version");
  CHECK(version.exit_code == 0);
  CHECK(version.out.find("gearnvh 0.1.0 (git ") != std::string::npos);
}

TEST_CASE("option ranges name the rule plainly and an unknown first option is named",
          "[cli][hardening]") {
  // CLI11's own wording was "Value 1.5 not in range 1 to 1000000" and "not in range 36.000000 to
  // 600.000000": the rule (an integer) and the bounds as the user writes them instead.
  const auto cycles = RunCommand(kExe + " simulate " + kWhine + " --cycles 1.5");
  CHECK(cycles.exit_code == 2);
  CHECK(cycles.err.find("--cycles: must be an integer from 1 to 1000000, got 1.5") !=
        std::string::npos);
  const auto zero = RunCommand(kExe + " simulate " + kWhine + " --cycles 0");
  CHECK(zero.exit_code == 2);
  CHECK(zero.err.find("--cycles: must be an integer from 1 to 1000000, got 0") !=
        std::string::npos);
  const auto dpi = RunCommand(kExe + " tiers " + kWhine + " --dpi 0");
  CHECK(dpi.exit_code == 2);
  CHECK(dpi.err.find("--dpi: must be a number from 36 to 600, got 0") != std::string::npos);
  CHECK(dpi.err.find("36.000000") == std::string::npos);
  const auto jobs = RunCommand(kExe + " atlas " + kWhine + " --jobs 2x");
  CHECK(jobs.exit_code == 2);
  CHECK(jobs.err.find("--jobs: must be an integer from 1 to 1024, got 2x") != std::string::npos);
  // Before any command: the unknown option is named, not "A subcommand is required".
  const auto bogus = RunCommand(kExe + " --bogus");
  CHECK(bogus.exit_code == 2);
  CHECK(bogus.err.find("unknown option '--bogus'") != std::string::npos);
  CHECK(bogus.err.find("A subcommand is required") == std::string::npos);
}

TEST_CASE("output: --out is checked before the computation and an I/O failure is exit 4",
          "[cli][hardening]") {
  const TempDir dir;
  const fs::path file = dir.path() / "a-file";
  std::ofstream(file) << "mine\n";
  // A huge run that must not start: the answer comes at once.
  const auto start = std::chrono::steady_clock::now();
  const auto run =
      RunCommand(kExe + " simulate " + kWhine + " --cycles 1000000 --out " + file.string());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(run.exit_code == 4);
  CHECK(run.err.find("not a directory") != std::string::npos);
  CHECK(seconds < 20.0);
  CHECK(ReadWholeFile(file) == "mine\n");
  CHECK(Debris(dir.path()).empty());
  // A folder no file can be made in (/proc has no blocks, so no free space) is not a full disk:
  // the error gives the system's reason.
  const auto proc = RunCommand(kExe + " simulate " + kWhine + " --out /proc/gearnvh-out");
  INFO(proc.err);
  CHECK(proc.exit_code == 4);
  CHECK(proc.err.find("error: --out /proc/gearnvh-out: ") != std::string::npos);
  CHECK(proc.err.find("disk is full") == std::string::npos);
}

TEST_CASE("output: simulate writes all its files into a new folder, nothing else is left",
          "[cli][hardening]") {
  const TempDir dir;
  const fs::path out = dir.path() / "sub" / "run";
  const auto run =
      RunCommand(kExe + " simulate " + kWhine + " --cycles 20 --transient 5 --out " + out.string());
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  for (const char* f : {"trajectory.csv", "events.csv", "results.json"}) {
    INFO(f);
    CHECK(fs::file_size(out / f) > 10);
  }
  CHECK(Debris(dir.path()).empty());
  // A second run into the same folder replaces the files and keeps what it does not write.
  std::ofstream(out / "notes.txt") << "mine\n";
  std::ofstream(out / "results.json") << "old\n";
  REQUIRE(
      RunCommand(kExe + " simulate " + kWhine + " --cycles 20 --transient 5 --out " + out.string())
          .exit_code == 0);
  CHECK(ReadWholeFile(out / "notes.txt") == "mine\n");
  CHECK(nlohmann::json::parse(ReadWholeFile(out / "results.json"))["summary"]["status"] ==
        "success");
  CHECK(Debris(dir.path()).empty());
}

TEST_CASE("output: a second writer into the same folder is refused at once", "[cli][hardening]") {
  const TempDir dir;
  const fs::path out = dir.path() / "run";
  // Another run holds the lock (this test process takes it exactly as gearnvh does).
  const int fd = ::open((dir.path() / ".run.lock").c_str(), O_RDWR | O_CREAT, 0644);
  REQUIRE(fd >= 0);
  REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
  REQUIRE(::write(fd, "4242", 4) == 4);
  const auto refused =
      RunCommand(kExe + " simulate " + kWhine + " --cycles 20 --transient 5 --out " + out.string());
  CHECK(refused.exit_code == 4);
  CHECK(refused.err.find("another gearnvh run (pid 4242") != std::string::npos);
  CHECK(!fs::exists(out));
  ::close(fd);  // released: the next run goes ahead
  CHECK(
      RunCommand(kExe + " simulate " + kWhine + " --cycles 20 --transient 5 --out " + out.string())
          .exit_code == 0);
  CHECK(Debris(dir.path()).empty());
}

#ifdef GEARNVH_HAVE_RENDER
TEST_CASE("report: a re-run whose gearboxes all fail leaves the earlier report intact",
          "[cli][hardening][report]") {
  const TempDir dir;
  const fs::path out = dir.path() / "OLD";
  WriteEarlierReport(out);
  const auto before = Snapshot(out);
  const auto run = RunCommand(kExe + " report " + (dir.path() / "typo.yaml").string() + " --out " +
                              out.string());
  CHECK(run.exit_code == 1);
  CHECK(run.err.find("typo.yaml") != std::string::npos);
  CHECK(run.err.find("is unchanged") != std::string::npos);
  CHECK(Snapshot(out) == before);
  CHECK(Debris(dir.path()).empty());
}

TEST_CASE("report: a batch replaces only the gearbox folders that succeeded",
          "[cli][hardening][report]") {
  const TempDir dir;
  const fs::path out = dir.path() / "OLD";
  WriteEarlierReport(out);
  // The earlier report also had a gearbox "broken" that was fine then.
  fs::create_directories(out / "broken");
  std::ofstream(out / "broken" / "index.html") << "<html>broken, as it was</html>\n";
  auto earlier = nlohmann::json::parse(ReadWholeFile(out / "report.json"));
  earlier["gearboxes"].push_back({{"file", "broken.yaml"},
                                  {"folder", "broken"},
                                  {"name", "broken"},
                                  {"ok", true},
                                  {"error", ""},
                                  {"summary", {{"tier", "1"}, {"regime", "no impact"}}},
                                  {"wall_s", 1.0}});
  std::ofstream(out / "report.json") << earlier.dump(1);
  const fs::path broken = dir.Write("broken.yaml", "schema: gearnvh/1\nname: broken\n");
  const auto run = RunCommand(kExe + " report " + kWhine + " " + broken.string() +
                              " --no-atlas --width 600 --height 400 --out " + out.string());
  INFO(run.err);
  CHECK(run.exit_code == 1);
  CHECK(fs::exists(out / "industrial-whine" / "campbell.png"));  // the new gearbox is in
  // The failed gearbox keeps its earlier folder; the untouched earlier gearbox stays listed.
  CHECK(ReadWholeFile(out / "broken" / "index.html") == "<html>broken, as it was</html>\n");
  CHECK(ReadWholeFile(out / "kept" / "index.html") == "<html>an earlier gearbox</html>\n");
  const std::string index = ReadWholeFile(out / "index.html");
  CHECK(index.find("the result of an earlier run is kept") != std::string::npos);
  CHECK(index.find("kept</a> (earlier run)") != std::string::npos);
  const auto batch = nlohmann::json::parse(ReadWholeFile(out / "report.json"));
  CHECK(batch["failed"] == 1);
  CHECK(batch["gearboxes"].size() == 3);
  CHECK(Debris(dir.path()).empty());
}

TEST_CASE(
    "report: a signal mid-run removes the staging folder and keeps the earlier report and "
    "stops Xvfb - after kill -9 the next run cleans up",
    "[cli][hardening][report]") {
  const TempDir dir;
  const fs::path out = dir.path() / "OLD";
  WriteEarlierReport(out);
  const auto before = Snapshot(out);
  for (const int sig : {SIGTERM, SIGKILL}) {
    INFO("signal " << sig);
    const pid_t pid =
        Spawn({"report", kWhine, "--no-atlas", "--jobs", "1", "--out", out.string()}, dir.path());
    REQUIRE(pid > 0);
    // Running: its staging folder exists and its own Xvfb is up.
    std::vector<pid_t> xvfb;
    const bool started = WaitFor(
        [&] {
          xvfb = Children(pid, "Xvfb");
          return HasPartial(dir.path()) && !xvfb.empty();
        },
        60.0);
    INFO(ReadWholeFile(dir.path() / "err.txt"));
    REQUIRE(started);
    // Meanwhile a second writer is refused.
    const auto second = RunCommand(kExe + " report " + kWhine + " --out " + out.string());
    CHECK(second.exit_code == 4);
    CHECK(second.err.find("another gearnvh run") != std::string::npos);

    REQUIRE(::kill(pid, sig) == 0);
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == sig);
    CHECK(WaitFor([&] { return !Alive(xvfb.front()); }, 10.0));  // Xvfb died with its parent
    CHECK(Snapshot(out) == before);
    if (sig == SIGTERM) {
      CHECK(!HasPartial(dir.path()));  // removed by the signal cleanup
      CHECK(!fs::exists(dir.path() / ".OLD.lock"));
    } else {
      CHECK(HasPartial(dir.path()));  // nothing runs after kill -9 ...
      const auto next = RunCommand(kExe + " report " + (dir.path() / "typo.yaml").string() +
                                   " --out " + out.string());
      CHECK(next.exit_code == 1);
      CHECK(!HasPartial(dir.path()));  // ... the next run into the folder removes the debris
      CHECK(Snapshot(out) == before);
    }
  }
}

#endif  // GEARNVH_HAVE_RENDER

TEST_CASE("a mistyped command is named, with the closest command and the list",
          "[cli][hardening]") {
  const auto typo = RunCommand(kExe + " simulat " + kWhine);
  CHECK(typo.exit_code == 2);
  CHECK(typo.err.find("error: unknown command 'simulat' (did you mean simulate?); commands: "
                      "check, simulate, ") != std::string::npos);
  const auto unknown = RunCommand(kExe + " bogus");
  CHECK(unknown.exit_code == 2);
  CHECK(unknown.err.find("error: unknown command 'bogus'; commands: check, ") != std::string::npos);
}

#if !defined(GEARNVH_UNDER_ASAN)  // ASan reserves more address space than the cap below
TEST_CASE("simulate: running out of memory is an error that says so, not an internal error",
          "[cli][hardening]") {
  const TempDir dir;
  const fs::path out = dir.path() / "run";
  // 200000 recorded cycles keep 4 million samples (the bound), 244 MiB, and 22.9 MiB of event
  // log; the address space is capped at 300 MB, ~100 MB of it mapped at the start.
  const std::string run = "ulimit -v 300000 && " + kExe + " simulate " + kWhine +
                          " --cycles 200000 --transient 0 --out " + out.string();
  // The estimate sees the cap: refused before the run.
  const auto refused = RunCommand(run);
  INFO(refused.err);
  CHECK(refused.exit_code == 2);
  CHECK(refused.err.find("--cycles: the run would hold about 267 MiB") != std::string::npos);
  CHECK(refused.err.find("(the address space left under ulimit -v, less 16 MiB kept back)") !=
        std::string::npos);
  CHECK(!fs::exists(out));
  CHECK(Debris(dir.path()).empty());
  // With the check told there is room, the allocation itself fails: an error that says so.
  const auto failed = RunCommand("export GEARNVH_MEMORY_LIMIT=1000000000000 && " + run);
  INFO(failed.err);
  CHECK(failed.exit_code == 1);
  CHECK(failed.err.find("error: out of memory: ") != std::string::npos);
  CHECK(failed.err.find("internal error") == std::string::npos);
  CHECK(!fs::exists(out));
  CHECK(Debris(dir.path()).empty());
  // 100000 cycles under 440000 KiB: the address space is read at the check (the model built) and
  // the estimate counts FFTW's plan (TE spectrum 134 MiB, 352 MiB in all), so the run that used
  // to pass the check (estimate 328 MiB, ~330 MiB left at the start) and then ran out of memory
  // after the whole run is refused up front.
  const auto at_the_check = RunCommand("ulimit -v 440000 && " + kExe + " simulate " + kWhine +
                                       " --cycles 100000 --out " + out.string());
  INFO(at_the_check.err);
  CHECK(at_the_check.exit_code == 2);
  CHECK(at_the_check.err.find("--cycles: the run would hold about 352 MiB (recorded samples 195 "
                              "MiB, event log 22.9 MiB, TE spectrum 134 MiB), more than the ") !=
        std::string::npos);
  CHECK(!fs::exists(out));
  CHECK(Debris(dir.path()).empty());
}
#endif

TEST_CASE(
    "simulate: SIGINT or SIGTERM mid-run says on stderr that the run was stopped and the "
    "earlier results kept",
    "[cli][hardening]") {
  const TempDir dir;
  const fs::path out = dir.path() / "run";
  const auto first = RunCommand(kExe + " simulate " + kWhine +
                                " --cycles 20 --transient 10 --out " + out.string());
  REQUIRE(first.exit_code == 0);
  const auto before = Snapshot(out);
  for (const int sig : {SIGINT, SIGTERM}) {
    const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
    INFO(name);
    // A million mesh cycles take minutes: the signal comes while it computes, its staging
    // folder in place.
    const pid_t pid =
        Spawn({"simulate", kWhine, "--cycles", "1000000", "--out", out.string()}, dir.path());
    REQUIRE(pid > 0);
    REQUIRE(WaitFor([&] { return HasPartial(dir.path()); }, 30.0));
    REQUIRE(::kill(pid, sig) == 0);
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == sig);
    const std::string err = ReadWholeFile(dir.path() / "err.txt");
    INFO(err);
    CHECK(err.find("gearnvh: stopped by " + name +
                   ": the unfinished outputs were removed, earlier results are unchanged\n") !=
          std::string::npos);
    CHECK(err.find('\x1b') == std::string::npos);  // not a terminal: no control sequences
    CHECK(Snapshot(out) == before);
    CHECK(Debris(dir.path()).empty());
  }
}

TEST_CASE(
    "output: a full disk while writing leaves the earlier results - a full or read-only "
    "disk is refused before the computation",
    "[cli][hardening]") {
  if (!NamespacesAvailable()) {
    WARN("user and mount namespaces unavailable: the full-disk test is not run here");
    return;
  }
  const TempDir dir;
  const std::string d = dir.path().string();
  const std::string simulate = kExe + " simulate " + kWhine + " --transient 5";
  // 1.5 MB: enough to start (1 MB free needed), too small for 2000 cycles of trajectory (~6 MB).
  const auto full = RunCommand(
      "unshare -rm sh -c 'mount -t tmpfs -o size=1500k tmpfs " + d + " && mkdir " + d +
      "/out && echo old > " + d + "/out/results.json && " + simulate + " --cycles 2000 --out " + d +
      "/out; echo rc=$?; cat " + d + "/out/results.json; ls -a " + d + "'");
  INFO(full.out << full.err);
  CHECK(full.out.find("rc=4") != std::string::npos);
  CHECK(full.out.find("\nold\n") != std::string::npos);  // the earlier result
  CHECK(full.out.find(".partial-") == std::string::npos);
  CHECK(full.err.find("No space left") != std::string::npos);

  const auto tiny =
      RunCommand("unshare -rm sh -c 'mount -t tmpfs -o size=512k tmpfs " + d + " && " + simulate +
                 " --cycles 1000000 --out " + d + "/out; echo rc=$?'");
  INFO(tiny.out << tiny.err);
  CHECK(tiny.out.find("rc=4") != std::string::npos);
  CHECK(tiny.err.find("disk is full") != std::string::npos);

  const auto readonly = RunCommand("unshare -rm sh -c 'mount -t tmpfs -o size=4m tmpfs " + d +
                                   " && mount -o remount,ro " + d + " && " + simulate +
                                   " --cycles 1000000 --out " + d + "/out; echo rc=$?'");
  INFO(readonly.out << readonly.err);
  CHECK(readonly.out.find("rc=4") != std::string::npos);
  CHECK(readonly.err.find("ead-only") != std::string::npos);  // Read-only / read-only
  CHECK(readonly.err.find("disk is full") == std::string::npos);
}

TEST_CASE("output: --out . works when the parent folder is not writable", "[cli][hardening]") {
  if (!NamespacesAvailable()) {
    WARN("user and mount namespaces unavailable: the read-only-parent test is not run here");
    return;
  }
  const TempDir dir;
  const std::string d = dir.path().string();
  // A read-only parent with a writable output folder mounted inside it.
  const auto run =
      RunCommand("unshare -rm sh -c 'mount -t tmpfs -o size=8m tmpfs " + d + " && mkdir " + d +
                 "/out && mount -t tmpfs -o size=8m tmpfs " + d + "/out && mount -o remount,ro " +
                 d + " && cd " + d + "/out && " + kExe + " simulate " + kWhine +
                 " --cycles 20 --transient 5 --out . ; echo rc=$?; ls -a " + d + "/out'");
  INFO(run.out << run.err);
  CHECK(run.out.find("rc=0") != std::string::npos);
  CHECK(run.out.find("results.json") != std::string::npos);
  CHECK(run.out.find(".gearnvh") == std::string::npos);  // lock and staging are gone
}

TEST_CASE("output: a failed rename undoes the moves and says where the new results are",
          "[cli][hardening]") {
  if (!NamespacesAvailable()) {
    WARN("user and mount namespaces unavailable: the failed-rename test is not run here");
    return;
  }
  const TempDir dir;
  const std::string d = dir.path().string();
  fs::create_directories(dir.path() / "out");
  for (const char* f : {"trajectory.csv", "events.csv", "results.json"}) {
    std::ofstream(dir.path() / "out" / f) << "old " << f << "\n";
  }
  std::ofstream(dir.path() / "pinned") << "old results.json\n";
  // A mount point cannot be renamed over (EBUSY): the commit fails on results.json.
  const auto run = RunCommand("unshare -rm sh -c 'mount --bind " + d + "/pinned " + d +
                              "/out/results.json && " + kExe + " simulate " + kWhine +
                              " --cycles 20 --transient 5 --out " + d + "/out; echo rc=$?'");
  INFO(run.out << run.err);
  CHECK(run.out.find("rc=4") != std::string::npos);
  CHECK(run.err.find("is unchanged") != std::string::npos);
  for (const char* f : {"trajectory.csv", "events.csv", "results.json"}) {
    INFO(f);
    CHECK(ReadWholeFile(dir.path() / "out" / f) == std::string("old ") + f + "\n");
  }
  // The complete new results, where the message says.
  fs::path kept;
  for (const auto& e : fs::directory_iterator(dir.path())) {
    if (e.path().filename().string().rfind("out.new-", 0) == 0) kept = e.path();
  }
  REQUIRE(!kept.empty());
  CHECK(run.err.find(kept.string()) != std::string::npos);
  CHECK(nlohmann::json::parse(ReadWholeFile(kept / "results.json"))["summary"]["status"] ==
        "success");
  CHECK(Debris(dir.path()).empty());
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

// `example` with every occurrence of `from` replaced by `to`, written into `dir`.
fs::path Variant(const TempDir& dir, const std::string& example, const std::string& from,
                 const std::string& to, const std::string& name) {
  std::string text = ReadWholeFile(kExamples + "/" + example);
  REQUIRE(text.find(from) != std::string::npos);
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return dir.Write(name, text);
}

TEST_CASE("malformed inputs: absurd values are input errors naming the path, value and rule",
          "[cli][hardening]") {
  const TempDir dir;
  struct Case {
    std::string example, from, to, path, rule;
  };
  const std::vector<Case> cases{
      {"industrial_whine.yaml", "pressure_angle: 20 deg", "pressure_angle: 44 deg",
       "gears.pinion.pressure_angle", "pointed teeth"},
      {"industrial_whine.yaml", "speed: 1500 rpm", "speed: 1e-6 rpm", "operating.speed",
       "simulated time"},
      {"industrial_whine.yaml", "module: 4 mm", "module: 1e300 mm", "gears.pinion.module",
       "must be in"},
      {"industrial_whine.yaml", "torque: 1500 N*m", "torque: 1e12 N*m", "operating.torque",
       "linear-elastic"},
      {"idle_rattle.yaml", "amplitude: 1500 rad/s^2", "amplitude: 1e12 rad/s^2",
       "operating.excitation[0].amplitude", "turn backwards"},
      {"flexible_shafts.yaml", "element_length: 10 mm", "element_length: 0.05 mm", "element_length",
       "GB"},
      {"industrial_whine.yaml", "teeth: 25", "teeth: 16", "gears.pinion.teeth", "undercut"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    INFO(c.to);
    const fs::path file =
        Variant(dir, c.example, c.from, c.to, "case" + std::to_string(i) + ".yaml");
    const auto run = RunCommand(kExe + " check " + file.string());
    CHECK(run.exit_code == 1);
    CHECK(run.err.find(c.path) != std::string::npos);
    CHECK(run.err.find(c.rule) != std::string::npos);
    CHECK(run.out.find("nan") == std::string::npos);
  }
  // The same rules hold for simulate (it never starts the run).
  const fs::path slow =
      Variant(dir, "industrial_whine.yaml", "speed: 1500 rpm", "speed: 1e-6 rpm", "slow.yaml");
  const auto run =
      RunCommand(kExe + " simulate " + slow.string() + " --out " + (dir.path() / "out").string());
  CHECK(run.exit_code == 1);
  CHECK(run.err.find("operating.speed") != std::string::npos);
  CHECK(!fs::exists(dir.path() / "out"));
  CHECK(Debris(dir.path()).empty());
}

TEST_CASE("malformed inputs: invalid UTF-8 is an input error and leaves no staging folder",
          "[cli][hardening]") {
  const TempDir dir;
  const fs::path file = Variant(dir, "industrial_whine.yaml", "name: Industrial",
                                "name: Indus\xFF\xFEtrial", "bad.yaml");
  const auto check = RunCommand(kExe + " check --json " + file.string());
  CHECK(check.exit_code == 1);
  CHECK(check.err.find("UTF-8") != std::string::npos);
  CHECK(check.err.find("bad.yaml:") != std::string::npos);
  const auto simulate =
      RunCommand(kExe + " simulate " + file.string() + " --out " + (dir.path() / "out").string());
  CHECK(simulate.exit_code == 1);
  CHECK(!fs::exists(dir.path() / "out"));
  CHECK(Debris(dir.path()).empty());
}

}  // namespace
}  // namespace gearnvh
