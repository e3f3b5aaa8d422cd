// Unit tests of the output-safety pieces: the output folder (lock, staging, commit), the finite
// check of result documents and the UTF-8 check of input files.
#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <stdexcept>

#include "atomic_file.h"
#include "command_errors.h"
#include "config/utf8_check.h"
#include "finite_results.h"
#include "gearnvh/model/input_error.h"
#include "output_folder.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

namespace fs = std::filesystem;
using testing::ReadWholeFile;
using testing::TempDir;

TEST_CASE("OutputFolder: commits whole and keeps other files and holds one writer at a time",
          "[app][output]") {
  const TempDir dir;
  const fs::path target = dir.path() / "out";
  fs::create_directories(target);
  std::ofstream(target / "mine.txt") << "mine\n";
  std::ofstream(target / "a.csv") << "old\n";
  {
    app::OutputFolder out(target, "--out");
    CHECK(fs::is_directory(out.staging()));
    CHECK(fs::exists(dir.path() / ".out.lock"));
    // A second writer (even in this process: flock is per open file) is refused at once.
    CHECK_THROWS_AS(app::OutputFolder(target, "--out"), app::IoError);
    out.Write("a.csv", "new\n");
    out.Write("b.json", "{}\n");
    CHECK(ReadWholeFile(target / "a.csv") == "old\n");  // nothing visible before the commit
    out.Commit();
  }
  CHECK(ReadWholeFile(target / "a.csv") == "new\n");
  CHECK(ReadWholeFile(target / "b.json") == "{}\n");
  CHECK(ReadWholeFile(target / "mine.txt") == "mine\n");
  // Nothing but the target is left beside it.
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) entries += e.path() != target ? 1 : 0;
  CHECK(entries == 0);
}

TEST_CASE("OutputFolder: a symlink to the folder meets the same lock", "[app][output]") {
  const TempDir dir;
  const fs::path target = dir.path() / "out";
  fs::create_directories(target);
  fs::create_directory_symlink(target, dir.path() / "link");
  fs::create_directories(dir.path() / "elsewhere");
  fs::create_directory_symlink(dir.path(), dir.path() / "elsewhere" / "parent");
  {
    app::OutputFolder out(target, "--out");
    // The folder by another name, and through a symlinked parent: refused while the lock holds.
    CHECK_THROWS_AS(app::OutputFolder(dir.path() / "link", "--out"), app::IoError);
    CHECK_THROWS_AS(app::OutputFolder(dir.path() / "elsewhere" / "parent" / "out", "--out"),
                    app::IoError);
  }
  {
    app::OutputFolder out(dir.path() / "link", "--out");
    CHECK(out.staging().parent_path() == fs::canonical(dir.path()));
    CHECK_THROWS_AS(app::OutputFolder(target, "--out"), app::IoError);
    out.Write("a.csv", "new\n");
    out.Commit();
  }
  CHECK(fs::is_symlink(dir.path() / "link"));  // the link stays, the folder got the file
  CHECK(ReadWholeFile(target / "a.csv") == "new\n");
}

TEST_CASE("OutputFolder: an uncommitted run leaves nothing and stale staging is removed",
          "[app][output]") {
  const TempDir dir;
  const fs::path target = dir.path() / "out";
  fs::create_directories(dir.path() / ".out.partial-999999" / "x");  // a killed run's debris
  {
    app::OutputFolder out(target, "--out");
    CHECK(!fs::exists(dir.path() / ".out.partial-999999"));
    out.Write("a.csv", "new\n");
  }  // no commit: an error path
  CHECK(!fs::exists(target));
  CHECK(fs::is_empty(dir.path()));
  // A file in the way is refused before anything is made.
  std::ofstream(target) << "a file\n";
  CHECK_THROWS_AS(app::OutputFolder(target, "--out"), app::IoError);
  CHECK(ReadWholeFile(target) == "a file\n");
}

TEST_CASE(
    "WriteFileAtomically: a writer that throws anything leaves the earlier file and no temporary",
    "[app][output]") {
  const TempDir dir;
  const fs::path target = dir.path() / "results.uff";
  std::ofstream(target) << "earlier\n";
  // std::bad_alloc as from a string growing past the memory the process may have, and an
  // exception of no standard type: each reaches the caller as it was thrown.
  auto half_then = [](auto error) {
    return [error](std::FILE* f) {
      std::fputs("half a file\n", f);
      throw error;
    };
  };
  CHECK_THROWS_AS(app::WriteFileAtomically(target.string(), half_then(std::bad_alloc())),
                  std::bad_alloc);
  CHECK_THROWS_AS(app::WriteFileAtomically(target.string(), half_then(42)), int);
  CHECK(ReadWholeFile(target) == "earlier\n");
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) entries += e.path() != target ? 1 : 0;
  CHECK(entries == 0);
}

// The message of the IoError that opening `target` raises ("" when it opens).
std::string RefusalOf(const fs::path& target) {
  try {
    app::OutputFolder out(target, "--out");
  } catch (const app::IoError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("OutputFolder: a folder that cannot be written is refused with the system's reason",
          "[app][output]") {
  // /proc has no blocks and so no free space: it is not a full disk, and the reason it refuses
  // (no file can be created there) is the one reported.
  const std::string proc = RefusalOf("/proc/gearnvh-out");
  INFO(proc);
  CHECK(proc.rfind("--out /proc/gearnvh-out: ", 0) == 0);
  CHECK(proc.find("disk is full") == std::string::npos);
  // root may enter /proc and fails to create there; anyone else may not write it at all.
  CHECK((proc.find("/proc/.gearnvh-out.lock: No such file or directory") != std::string::npos ||
         proc.find("/proc is not writable: Permission denied") != std::string::npos));
  CHECK(!fs::exists("/proc/gearnvh-out"));
  // A parent that is a file: the path, the parent and the system's reason; the file and the
  // report folder beside it stay as they were.
  const TempDir dir;
  std::ofstream(dir.path() / "notes.txt") << "notes\n";
  fs::create_directories(dir.path() / "report");
  std::ofstream(dir.path() / "report" / "a.csv") << "old\n";
  const std::string file_parent = RefusalOf(dir.path() / "notes.txt" / "report");
  INFO(file_parent);
  CHECK(file_parent.find("--out " + (dir.path() / "notes.txt" / "report").string() +
                         ": cannot create " + (dir.path() / "notes.txt").string()) !=
        std::string::npos);
  CHECK(file_parent.find("Not a directory") != std::string::npos);
  CHECK(file_parent.find("disk is full") == std::string::npos);
  CHECK(ReadWholeFile(dir.path() / "notes.txt") == "notes\n");
  CHECK(ReadWholeFile(dir.path() / "report" / "a.csv") == "old\n");
}

TEST_CASE("RequireFinite names the quantity that is not finite", "[app][output]") {
  nlohmann::json doc = {{"te", {{"rms", 1e-6}, {"max", 2e-6}}}, {"list", {1.0, 2.0}}};
  CHECK_NOTHROW(app::RequireFinite(doc, "simulate"));
  doc["te"]["rms"] = std::numeric_limits<double>::quiet_NaN();
  try {
    app::RequireFinite(doc, "simulate");
    FAIL("no exception");
  } catch (const app::NonFiniteResult& e) {
    CHECK(std::string(e.what()).find("simulate: te.rms is NaN") != std::string::npos);
  }
  doc["te"]["rms"] = 1.0;
  doc["list"][1] = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(app::RequireFinite(doc, "x"), Catch::Contains("list[1] is infinite"));
}

TEST_CASE("RelativeDifference: relative above the quantity's resolution, against it below",
          "[app][output]") {
  // Exact arithmetic on binary-exact inputs: 0.25 against 0.5 is 0.5.
  CHECK(app::RelativeDifference(0.25, 0.5, app::kTeResolution) == 0.5);
  CHECK(app::RelativeDifference(-0.75, -0.5, app::kTeResolution) == 0.5);
  // A resting train: rounding-level TE beside an exact zero is 1e-7 of the resolution, where a
  // 1e-300 floor made it 1e281 (tiers printed 2e+288).
  CHECK(app::RelativeDifference(1e-19, 0.0, app::kTeResolution) == Approx(1e-7).epsilon(1e-12));
  CHECK(app::RelativeDifference(0.0, 0.0, app::kTeResolution) == 0.0);
  // A tier that rattles where the finest rests is a difference far above 1.
  CHECK(app::RelativeDifference(1e-3, 0.0, app::kAngularAccelerationResolution) ==
        Approx(1e3).epsilon(1e-15));
}

TEST_CASE("RequireValidUtf8 accepts UTF-8 and names the line of anything else", "[app][input]") {
  CHECK_NOTHROW(config::RequireValidUtf8("name: Zahnräder \xE2\x82\xAC \xF0\x9F\x98\x80\n", "f"));
  for (const std::string& bad : {std::string("\xFF"), std::string("\xC0\xAF"),  // overlong '/'
                                 std::string("\xED\xA0\x80"),                   // surrogate
                                 std::string("\xF4\x90\x80\x80"),               // > U+10FFFF
                                 std::string("\xE2\x82")}) {                    // cut short
    INFO(bad.size());
    try {
      config::RequireValidUtf8("schema: gearnvh/1\nname: a" + bad + "\n", "f.yaml");
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(e.line() == 2);
      CHECK(std::string(e.what()).find("UTF-8") != std::string::npos);
    }
  }
}

TEST_CASE("RequireValidUtf8 refuses the control characters YAML does not allow", "[app][input]") {
  // Tab, line feed and carriage return (CRLF files) are YAML's only C0 controls.
  CHECK_NOTHROW(config::RequireValidUtf8("name:\ta\r\nmesh: {}\r\n", "f"));
  // Before this check a leading NUL made yaml-cpp guess UTF-16 ("must be a mapping, got 'Ã뼊'")
  // and a later one ended the text ("materials: required key is missing").
  for (const char c : {'\x00', '\x01', '\x1B', '\x7F'}) {
    INFO(static_cast<int>(c));
    try {
      config::RequireValidUtf8("schema: gearnvh/1\nname: a" + std::string(1, c) + "b\n", "f.yaml");
      FAIL("accepted");
    } catch (const InputError& e) {
      CHECK(e.line() == 2);
      CHECK(e.value() == fmt::format("\"\\x{:02X}\" at column 8", static_cast<unsigned char>(c)));
      CHECK(e.rule().find("YAML allows no control characters") != std::string::npos);
    }
  }
}

}  // namespace
}  // namespace gearnvh
