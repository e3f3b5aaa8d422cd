// End-to-end tests of `gearnvh report`: the README's main job, batches with a bad file, the
// output folder rules, the no-display error, and the report opened in headless Chromium.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "app/three_shaft_train_yaml.h"
#include "gearnvh/render/plots.h"
#include "support/example_variant.h"
#include "support/paths.h"
#include "support/run_command.h"
#include "support/sanitizer.h"

namespace gearnvh {
namespace {

namespace fs = std::filesystem;
using testing::ReadWholeFile;
using testing::RunCommand;
using testing::TempDir;

using testing::kExamples;
using testing::kExe;
const std::array<std::uint8_t, 3> kWhite{255, 255, 255};

// Every <img src> of a page, in order.
std::vector<std::string> ImageSources(const std::string& html) {
  std::vector<std::string> out;
  const std::regex img("<img src=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != std::sregex_iterator();
       ++it) {
    out.push_back((*it)[1]);
  }
  return out;
}

// The report of the README's main command (the rattle example) plus a malformed file: the good
// gearbox completes, the bad one is listed with its error, the exit code is 1. The instrumented
// build draws the atlas from 4 x 4 cells instead of the report's 12 x 12: the same code paths, and
// the atlas was 90 % of this test's 215 s CPU there.
TEST_CASE("report: a batch with a malformed file completes the good gearbox and lists the bad one",
          "[cli][report]") {
  const TempDir dir;
  const fs::path bad = dir.path() / "broken.yaml";
  std::ofstream(bad) << "schema: gearnvh/1\nname: broken\ngears: {pinion: {teeth: -3}}\n";
  const fs::path out = dir.path() / "report";
#if defined(GEARNVH_UNDER_ASAN)
  const std::string example =
      testing::WriteExampleVariant(dir, "idle_rattle.yaml",
                                   {{"to: 3000 rpm, points: 24}", "to: 3000 rpm, points: 4}"},
                                    {"to: 5 N*m,    points: 24", "to: 5 N*m,    points: 4"}})
          .string();
  const size_t atlas_cells = 16;
#else
  const std::string example = kExamples + "/idle_rattle.yaml";
  const size_t atlas_cells = 144;  // the report's atlas: at most 12 x 12 of the file's 24 x 24
#endif
  const auto run = RunCommand(kExe + " report " + example + " " + bad.string() + " --out " +
                              out.string() + " --width 800 --height 560");
  INFO(run.out << run.err);
  CHECK(run.exit_code == 1);
  CHECK(run.err.find("broken.yaml") != std::string::npos);
  CHECK(run.err.find('\r') == std::string::npos);  // no progress line when stderr is a file
  const std::string batch = ReadWholeFile(out / "index.html");
  CHECK(batch.find("broken.yaml") != std::string::npos);
  CHECK(batch.find("failed:") != std::string::npos);
  CHECK(batch.find("idle-rattle/index.html") != std::string::npos);
  const auto summary = nlohmann::json::parse(ReadWholeFile(out / "report.json"));
  CHECK(summary["failed"] == 1);
  CHECK(!fs::exists(out / "broken"));  // no half-built folder for the bad gearbox

  // The good gearbox: every figure the page shows exists, is a PNG of the requested size, and has
  // ink inside its plot area (not a blank canvas).
  const fs::path g = out / "idle-rattle";
  const std::string page = ReadWholeFile(g / "index.html");
  const auto images = ImageSources(page);
  // TE, spectrum, sideband stems, phase, Campbell, order tracks, waterfall, whine tracks and
  // waterfall, tiers, 3 mesh, 2 atlas
  CHECK(images.size() == 15);
  CHECK(std::count(images.begin(), images.end(), "whine_te.png") == 1);
  CHECK(std::count(images.begin(), images.end(), "whine_waterfall_1.png") == 1);
  for (const std::string& src : images) {
    INFO(src);
    const render::RgbImage img = render::ReadPng((g / src).string());
    CHECK(img.width >= 533);
    CHECK(img.height >= 373);
    CHECK(img.CountDifferent(0.3, 0.0, 0.7, 0.08, kWhite) > 50);      // title
    CHECK(img.CountDifferent(0.15, 0.15, 0.85, 0.85, kWhite) > 800);  // data
  }
  const auto results = nlohmann::json::parse(ReadWholeFile(g / "results.json"));
  CHECK(results["operating_point"]["rattle"]["regime"].is_string());
  CHECK(results["sweep"]["campbell"]["modes"].size() >= 1);
  CHECK(results["atlas"]["cells"].size() == atlas_cells);
  CHECK(results["check"]["tiers"].size() >= 1);
  CHECK(results["whine"]["speeds"] == 1000);
  CHECK(page.find("Whine (frequency domain") != std::string::npos);
  for (const char* csv : {"whine_meshes.csv", "te_trace.csv", "spectrum.csv", "sidebands.csv", "mesh_cycle.csv",
                          "campbell.csv", "waterfall.csv", "order_tracks.csv", "atlas.csv"}) {
    INFO(csv);
    CHECK(fs::file_size(g / csv) > 30);
  }
  // No staging or temporary files left anywhere.
  for (const auto& e : fs::recursive_directory_iterator(dir.path())) {
    CHECK(e.path().filename().string().find(".tmp") == std::string::npos);
    CHECK(e.path().filename().string().find(".partial-") == std::string::npos);
  }

  // Headless Chromium (Debian's chromium; as root it needs --no-sandbox) loads every image. The
  // page's own script counts images that did not load into data attributes of <body>, which
  // --dump-dom prints after the load event. Release only: Chromium is not instrumented and reads
  // the files written above, whose writing the sanitizer build has just checked.
#if !defined(GEARNVH_UNDER_ASAN)
  {
    for (const fs::path& html : {g / "index.html", out / "index.html"}) {
      const auto dom = RunCommand(
          "chromium --headless --no-sandbox --disable-gpu --virtual-time-budget=10000 "
          "--dump-dom file://" +
          html.string() + " 2>/dev/null");
      INFO(html << "\n" << dom.out.substr(0, 400));
      REQUIRE(dom.exit_code == 0);
      const size_t expected = html == g / "index.html" ? images.size() : 0;
      CHECK(dom.out.find("data-images-total=\"" + std::to_string(expected) + "\"") !=
            std::string::npos);
      CHECK(dom.out.find("data-images-broken=\"0\"") != std::string::npos);
    }
    // A screenshot of the gearbox page as Chromium lays it out, kept as a test artefact
    // (GEARNVH_TEST_ARTIFACTS_DIR/report_page.png): the page is drawn, and drawn with figures
    // (a text-only page has far fewer non-white pixels than its images give).
    const fs::path shot = fs::path(GEARNVH_TEST_ARTIFACTS_DIR) / "report_page.png";
    fs::create_directories(shot.parent_path());
    fs::remove(shot);
    const auto screenshot = RunCommand(
        "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars "
        "--virtual-time-budget=10000 --window-size=1280,4000 --screenshot=" +
        shot.string() + " file://" + (g / "index.html").string() + " 2>/dev/null");
    REQUIRE(screenshot.exit_code == 0);
    REQUIRE(fs::exists(shot));
    const render::RgbImage page = render::ReadPng(shot.string());
    CHECK(page.width == 1280);
    CHECK(page.height == 4000);
    // Ten or more figures of the 1200 x 800 default scaled into the page: at least 5 % of it ink.
    CHECK(page.CountDifferent(0.0, 0.0, 1.0, 1.0, {255, 255, 255}) > 0.05 * 1280 * 4000);
  }
#endif
}

// A small loaded pair (short runs, three sweep speeds, no atlas) for the progress tests.
const std::string kSmallGearbox = R"(schema: gearnvh/1
name: small
materials: {steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}}
gears:
  pinion: {teeth: 23, module: 2 mm, face_width: 12 mm, bore_diameter: 20 mm, material: steel}
  wheel: {teeth: 37, module: 2 mm, face_width: 12 mm, bore_diameter: 25 mm, material: steel}
mesh: {backlash: 80 um}
operating: {speed: 1500 rpm, torque: 20 N*m}
analysis:
  cycles: 64
  transient_cycles: 16
  speed_sweep: {from: 1000 rpm, to: 2000 rpm, points: 3}
)";

TEST_CASE("report: one gearbox shows its stages on a terminal and stays quiet when piped",
          "[cli][report]") {
  const TempDir dir;
  const fs::path file = dir.Write("small.yaml", kSmallGearbox);
  const std::string command =
      kExe + " report " + file.string() + " --width 400 --height 300 --out ";
  // Piped (stderr to a file): nothing on stderr at all.
  const auto piped = RunCommand(command + (dir.path() / "piped").string());
  INFO(piped.out << piped.err);
  REQUIRE(piped.exit_code == 0);
  CHECK(piped.err.empty());
  // On a terminal (util-linux `script` gives the command a pseudo-terminal; its output is the
  // terminal's): the stages of the one gearbox, with counts.
  const auto tty =
      RunCommand("script -qec '" + command + (dir.path() / "tty").string() + "' /dev/null");
  INFO(tty.out << tty.err);
  REQUIRE(tty.exit_code == 0);
  for (const char* stage : {"model and modal tiers", "operating point", " mesh cycles",
                            "speed sweep", "3/3 speeds", "images", "data files and pages"}) {
    INFO(stage);
    CHECK(tty.out.find(stage) != std::string::npos);
  }
}

TEST_CASE("report: an output folder is replaced only when it is an earlier report",
          "[cli][report]") {
  const TempDir dir;
  const fs::path foreign = dir.path() / "mine";
  fs::create_directories(foreign);
  std::ofstream(foreign / "notes.txt") << "my notes\n";
  // The whine example on 3 of its 43 sweep speeds: the folder rules do not depend on the analysis.
  const std::string file =
      testing::WriteExampleVariant(dir, "industrial_whine.yaml",
                                   {{"cycles: 1000", "cycles: 100"},
                                    {"transient_cycles: 400", "transient_cycles: 50"},
                                    {"to: 4500 rpm, points: 43}", "to: 4500 rpm, points: 3}"}})
          .string();
  const auto refused =
      RunCommand(kExe + " report " + file + " --no-atlas --out " + foreign.string());
  CHECK(refused.exit_code == 4);  // an output that cannot be written: I/O
  CHECK(refused.err.find("not a gearnvh report") != std::string::npos);
  CHECK(ReadWholeFile(foreign / "notes.txt") == "my notes\n");

  const fs::path out = dir.path() / "report";
  REQUIRE(RunCommand(kExe + " report " + file + " --no-atlas --width 600 --height 400 --out " +
                     out.string())
              .exit_code == 0);
  std::ofstream(out / "industrial-whine" / "stale.png") << "old";
  const auto again = RunCommand(kExe + " report " + file +
                                " --no-atlas --width 600 --height 400 "
                                "--out " +
                                out.string());
  INFO(again.err);
  REQUIRE(again.exit_code == 0);
  CHECK(!fs::exists(out / "industrial-whine" / "stale.png"));  // the old report is gone as a whole
  CHECK(fs::exists(out / "industrial-whine" / "campbell.png"));
}

TEST_CASE("report: without a display and without Xvfb the error says what to install",
          "[cli][report]") {
  const TempDir dir;
  // PATH without Xvfb and no DISPLAY: a clear error and exit 1, never a crash, nothing written.
  const auto run =
      RunCommand("env -u DISPLAY PATH=" + dir.path().string() + " " + kExe + " report " +
                 kExamples + "/industrial_whine.yaml --out " + (dir.path() / "r").string());
  CHECK(run.exit_code == 1);
  CHECK(run.err.find("Xvfb") != std::string::npos);
  CHECK(run.err.find("apt-get install xvfb") != std::string::npos);
  CHECK(!fs::exists(dir.path() / "r"));
}

TEST_CASE("report: an Xvfb that exits at once is reported with its exit status, not as slow",
          "[cli][report]") {
  const TempDir dir;
  // An Xvfb that fails at start (a broken installation, a missing GL driver) exits at once.
  const fs::path xvfb = dir.path() / "Xvfb";
  std::ofstream(xvfb) << "#!/bin/sh\nexit 3\n";
  fs::permissions(xvfb, fs::perms::owner_all);
  const auto run =
      RunCommand("env -u DISPLAY PATH=" + dir.path().string() + " " + kExe + " report " +
                 kExamples + "/industrial_whine.yaml --out " + (dir.path() / "r").string());
  INFO(run.err);
  CHECK(run.exit_code == 1);
  CHECK(run.err.find("(" + xvfb.string() + ") exited with status 3 before it was ready") !=
        std::string::npos);
  CHECK(run.err.find("within 10 s") == std::string::npos);
  CHECK(!fs::exists(dir.path() / "r"));
}

TEST_CASE("report: a start lock held by a stopped process delays the Xvfb start, never blocks it",
          "[cli][report]") {
  // The Xvfb start lock in $TMPDIR is held here for the whole run, as by a gearnvh stopped while
  // starting its Xvfb. The run waits its bound (15 s) and then starts unserialised: here a fake
  // Xvfb that exits at once, so the run ends on that message instead of waiting forever.
  const TempDir dir;
  const fs::path xvfb = dir.path() / "Xvfb";
  std::ofstream(xvfb) << "#!/bin/sh\nexit 3\n";
  fs::permissions(xvfb, fs::perms::owner_all);
  const int lock =
      ::open((dir.path() / ".gearnvh-xvfb-start.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  REQUIRE(lock >= 0);
  REQUIRE(::flock(lock, LOCK_EX | LOCK_NB) == 0);
  const auto start = std::chrono::steady_clock::now();
  const auto run = RunCommand("env -u DISPLAY TMPDIR=" + dir.path().string() +
                              " PATH=" + dir.path().string() + " " + kExe + " report " + kExamples +
                              "/industrial_whine.yaml --out " + (dir.path() / "r").string());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ::close(lock);
  INFO(run.err);
  CHECK(run.exit_code == 1);
  CHECK(run.err.find("exited with status 3 before it was ready") != std::string::npos);
  CHECK(seconds >= 14.9);  // it waited for the lock's bound
  CHECK(seconds < 60.0);   // and not for the holder (the run's own work takes a few seconds)
}

TEST_CASE("report: a gear train gets its page and figures, next to a pair and past a bad file",
          "[cli][report][train]") {
  // The manual transmission, shortened (210 recorded cycles: two common periods; 3 sweep speeds),
  // beside the rattle pair on 3 sweep speeds and 200 cycles.
  const TempDir dir;
  const testing::TextEdit shorter = {"analysis:\n",
                                     "analysis:\n  cycles: 210\n  transient_cycles: 50\n"
                                     "  speed_sweep: {from: 700 rpm, to: 1300 rpm, points: 3}\n"};
  const fs::path train = dir.Write(
      "transmission.yaml", testing::ExampleVariantText("manual_transmission_idle.yaml", {shorter}));
  // A broken train (a mesh names a gear that does not exist) must not stop the batch.
  const fs::path broken =
      dir.Write("broken_train.yaml",
                testing::ExampleVariantText("manual_transmission_idle.yaml",
                                            {shorter, {"gears: [in, l0]", "gears: [in, zz]"}}));
  const fs::path pair =
      testing::WriteExampleVariant(dir, "idle_rattle.yaml",
                                   {{"cycles: 2000", "cycles: 200"},
                                    {"transient_cycles: 500", "transient_cycles: 100"},
                                    {"to: 3000 rpm, points: 25}", "to: 3000 rpm, points: 3}"}});
  const fs::path out = dir.path() / "report";
  const auto run =
      RunCommand(kExe + " report " + train.string() + " " + broken.string() + " " + pair.string() +
                 " --no-atlas --out " + out.string() + " --width 800 --height 560");
  INFO(run.out << run.err);
  CHECK(run.exit_code == 1);  // the broken train
  CHECK(run.err.find("broken_train.yaml") != std::string::npos);
  CHECK(fs::exists(out / "idle-rattle" / "index.html"));  // the pair completed
  const fs::path g = out / "transmission";
  const std::string page = ReadWholeFile(g / "index.html");
  CHECK(page.find("Loose gears by impact energy") != std::string::npos);
  CHECK(page.find("TE spectrum lines per mesh") != std::string::npos);
  CHECK(page.find("l5-o5") != std::string::npos);
  // Campbell, per-mesh TE RMS and impacts, order tracks, whine tracks, a waterfall and a whine
  // waterfall per mesh, loose gears: drawn, with a title and data.
  const auto images = ImageSources(page);
  CHECK(images.size() == 5 + 1 + 2 * 6);
  CHECK(std::count(images.begin(), images.end(), "whine_waterfall_6.png") == 1);
  CHECK(std::count(images.begin(), images.end(), "whine_te.png") == 1);
  CHECK(std::count(images.begin(), images.end(), "waterfall_6.png") == 1);
  for (const std::string& src : images) {
    INFO(src);
    const render::RgbImage img = render::ReadPng((g / src).string());
    CHECK(img.width >= 533);
    CHECK(img.CountDifferent(0.3, 0.0, 0.7, 0.08, kWhite) > 50);      // title
    CHECK(img.CountDifferent(0.15, 0.15, 0.85, 0.85, kWhite) > 800);  // data
  }
  const auto results = nlohmann::json::parse(ReadWholeFile(g / "results.json"));
  CHECK(results["schema"] == "gearnvh/2");
  CHECK(results["operating_point"]["meshes"].size() == 6);
  CHECK(results["operating_point"]["loose_gears"].size() == 4);
  CHECK(results["sweep"]["points"].size() == 3);
  CHECK(results["sweep"]["speeds_rpm"][0].get<double>() ==
        700.0);  // as written, not 700.0000000000001
  CHECK(results["check"]["campbell"]["modes"].size() >= 1);
  // Idle: the loose gears' meshes carry only their drag, so the whine section warns about any
  // without a static load and flags speeds where the mean model fails.
  CHECK(results["whine"]["file"] == "whine.json");
  CHECK(page.find("Whine (frequency domain") != std::string::npos);
  const std::string meshes = ReadWholeFile(g / "meshes.csv");
  CHECK(std::count(meshes.begin(), meshes.end(), '\n') == 1 + 3 * 6);
  // Waterfall rows per speed and mesh, order tracks 1-3 per mesh, and the UFF file: every mesh's
  // TE and force histories and spectrum (210 cycles: two common periods) and its 3 order tracks.
  const std::string waterfall = ReadWholeFile(g / "waterfall.csv");
  CHECK(waterfall.rfind("speed_rpm,mesh,order,frequency_hz,amplitude_m\n", 0) == 0);
  CHECK(static_cast<long>(std::count(waterfall.begin(), waterfall.end(), '\n')) ==
        1 + 3 * 6 * results["sweep"]["waterfall"]["order_bins"].get<long>());
  const std::string tracks = ReadWholeFile(g / "order_tracks.csv");
  CHECK(tracks.find("1x mesh l5-o5 (input order") != std::string::npos);
  CHECK(std::count(tracks.begin(), tracks.end(), '\n') == 1 + 3);
  const std::string uff = ReadWholeFile(g / "results.uff");
  size_t datasets = 0;
  for (size_t at = uff.find("    -1\n    58\n"); at != std::string::npos;
       at = uff.find("    -1\n    58\n", at + 1))
    ++datasets;
  CHECK(datasets == 6 * 3 + 6 * 3);
  const std::string batch = ReadWholeFile(out / "index.html");
  CHECK(batch.find("transmission/index.html") != std::string::npos);
  CHECK(batch.find("tier 1 (gear train)") != std::string::npos);
  CHECK(batch.find("broken_train.yaml") != std::string::npos);
  // The train's row: TE RMS and impacts per mesh, the loudest loose gear (not "-").
  const auto report = nlohmann::json::parse(ReadWholeFile(out / "report.json"));
  int trains = 0;
  for (const auto& gearbox : report["gearboxes"]) {
    if (gearbox["folder"] != "transmission") continue;
    ++trains;
    const auto& summary = gearbox["summary"];
    REQUIRE(summary["meshes"].size() == 6);
    REQUIRE(summary["loudest_loose_gear"].is_string());
    CHECK(summary["meshes"][5]["te_rms_um"].get<double>() > 0.0);
    const size_t row = batch.find("<a href=\"transmission/index.html\">");
    REQUIRE(row != std::string::npos);
    const std::string cells = batch.substr(row, batch.find("</tr>", row) - row);
    INFO(cells);
    CHECK(cells.find("<br>l5-o5 ") != std::string::npos);
    CHECK(cells.find("<td>" + summary["loudest_loose_gear"].get<std::string>() + " (") !=
          std::string::npos);
  }
  CHECK(trains == 1);
}

TEST_CASE("report: a disk that fills up mid-report exits 4 with one message naming the folder",
          "[cli][report][hardening]") {
  // A small tmpfs in a user and mount namespace (no root needed); skipped where not permitted.
  if (RunCommand("unshare -rm sh -c 'mount -t tmpfs -o size=64k tmpfs /mnt'").exit_code != 0) {
    WARN("user and mount namespaces unavailable: the full-disk report test is not run here");
    return;
  }
  const TempDir dir;
  const std::string d = dir.path().string();
  // 1100 kB: enough to start (1 MB free needed), full after the first images.
  const auto run = RunCommand("unshare -rm sh -c 'mount -t tmpfs -o size=1100k tmpfs " + d +
                              " && " + kExe + " report " + kExamples +
                              "/industrial_whine.yaml --no-atlas --width 600 --height 400 --out " +
                              d + "/out; echo rc=$?; ls -a " + d + "'");
  INFO(run.out << run.err);
  CHECK(run.out.find("rc=4") != std::string::npos);
  // One line: the folder, the system's reason; no VTK or libpng text, no temporary path.
  CHECK(run.err == "error: --out " + d + "/out: cannot write the results: No space left on " +
                       "device; nothing was written\n");
  CHECK(run.out.find(".partial-") == std::string::npos);
  CHECK(run.out.find("out\n") == std::string::npos);
}

TEST_CASE("report fails a gearbox whose operating point would hold more than the memory limit",
          "[cli][report][memory]") {
  TempDir dir;
  const fs::path out = dir.path() / "report";
  const std::string file = kExamples + "/idle_rattle.yaml";
  // report writes results.uff with the TE and force histories, as simulate --uff does: the same
  // estimate, UFF export included, so one byte less than simulate --uff's is refused.
  const auto probe =
      RunCommand(kExe + " simulate --json --uff " + (dir.path() / "x.uff").string() + " " + file);
  REQUIRE(probe.exit_code == 0);
  const nlohmann::json estimate = nlohmann::json::parse(probe.out)["memory_estimate"];
  REQUIRE(estimate["parts"]["UFF export"].get<size_t>() > 0);
  const auto short_by_one =
      RunCommand("GEARNVH_MEMORY_LIMIT=" + std::to_string(estimate["bytes"].get<size_t>() - 1) +
                 " " + kExe + " report --no-atlas --out " + out.string() + " " + file);
  INFO(short_by_one.err);
  CHECK(short_by_one.exit_code == 1);
  CHECK(short_by_one.err.find(", UFF export ") != std::string::npos);
  CHECK(!fs::exists(out));
  const auto r = RunCommand("GEARNVH_MEMORY_LIMIT=1 " + kExe + " report --no-atlas --out " +
                            out.string() + " " + file);
  INFO(r.err);
  CHECK(r.exit_code == 1);
  // The file's analysis.cycles at its line, the estimate by part and the limit.
  CHECK(r.err.find("idle_rattle.yaml:48: analysis.cycles: the run would hold about ") !=
        std::string::npos);
  CHECK(r.err.find("(GEARNVH_MEMORY_LIMIT)") != std::string::npos);
  CHECK(!fs::exists(out));
}

TEST_CASE("report fails a gear train whose operating point would hold more than the memory limit",
          "[cli][report][memory][train]") {
  TempDir dir;
  const fs::path out = dir.path() / "report";
  const std::string file = (fs::path(GEARNVH_TEST_DATA_DIR) / "loose_gear_train.yaml").string();
  // The train's page writes results.uff with every mesh's histories, as simulate --uff does: the
  // same estimate, so one byte less than simulate --uff's is refused before anything is written.
  const auto probe =
      RunCommand(kExe + " simulate --json --uff " + (dir.path() / "x.uff").string() + " " + file);
  REQUIRE(probe.exit_code == 0);
  const nlohmann::json estimate = nlohmann::json::parse(probe.out)["memory_estimate"];
  REQUIRE(estimate["parts"]["UFF export"].get<size_t>() > 0);
  const auto short_by_one =
      RunCommand("GEARNVH_MEMORY_LIMIT=" + std::to_string(estimate["bytes"].get<size_t>() - 1) +
                 " " + kExe + " report --no-atlas --out " + out.string() + " " + file);
  INFO(short_by_one.err);
  CHECK(short_by_one.exit_code == 1);
  CHECK(
      short_by_one.err.find("loose_gear_train.yaml: analysis.cycles: the run would hold about ") !=
      std::string::npos);
  CHECK(short_by_one.err.find(", UFF export ") != std::string::npos);
  CHECK(short_by_one.err.find("(GEARNVH_MEMORY_LIMIT)") != std::string::npos);
  CHECK(!fs::exists(out));
}

TEST_CASE("report: failed sweep speeds are listed on the page, in results.json, and exit 1",
          "[cli][report][train]") {
  // The pair at tier 2 by the strong-rattle point: 5000 rpm (the operating point) and 5500 rpm
  // finish, 6000 rpm stops out of range. The train (tests/data/strong_rattle_train.yaml) at tier
  // 2 and 5000 rpm: of 5000-10000 rpm, three stop, 7000 rpm the first.
  const TempDir dir;
  const fs::path pair = testing::WriteExampleVariant(
      dir, "flexible_shafts.yaml",
      {{"  speed: 3000 rpm\n  torque: 200 N*m\n",
        "  speed: 5000 rpm\n  torque: 20 N*m\n  excitation:\n"
        "    - {order: 15.5, amplitude: 200000 rad/s^2, phase: 0 deg}\n"},
       {"  tier: \"N20 MTA\"", "  tier: 2"},
       testing::kStrongRattleSweep,
       {"  cycles: 500\n  transient_cycles: 200\n", "  cycles: 300\n  transient_cycles: 100\n"}});
  std::string train_text = ReadWholeFile(testing::kStrongRattleTrain);
  train_text = testing::ReplaceFirst(train_text, "value: 7548.387097 rpm", "value: 5000 rpm");
  train_text = testing::ReplaceFirst(
      train_text, "  cycles: 500\n",
      "  cycles: 200\n  speed_sweep: {from: 5000 rpm, to: 10000 rpm, points: 6}\n");
  const fs::path train = dir.Write("train.yaml", train_text);
  const fs::path out = dir.path() / "report";
  const auto r = RunCommand(kExe + " report --no-atlas --jobs 1 --out " + out.string() + " " +
                            pair.string() + " " + train.string());
  INFO(r.err);
  CHECK(r.exit_code == 1);
  CHECK(r.err.find(pair.string() + ": 1 sweep speed failed") != std::string::npos);
  CHECK(r.err.find(train.string() + ": 3 sweep speeds failed") != std::string::npos);
  const std::string page = ReadWholeFile(out / "flexible-shafts" / "index.html");
  CHECK(page.find("3 speeds, 1 failed; 6000 rpm: at mesh cycle") != std::string::npos);
  const auto results =
      nlohmann::json::parse(ReadWholeFile(out / "flexible-shafts" / "results.json"));
  CHECK(results["sweep"]["failed_speeds"] == 1);
  CHECK(results["sweep"]["waterfall"]["points"][2]["te_rms"].is_null());
  const std::string train_page = ReadWholeFile(out / "train" / "index.html");
  CHECK(train_page.find("6 input speeds, 3 failed; 7000 rpm: the run stopped") !=
        std::string::npos);
  const auto batch = nlohmann::json::parse(ReadWholeFile(out / "report.json"));
  CHECK(batch["failed"] == 0);  // both gearboxes finished: their pages are written
  for (const auto& g : batch["gearboxes"]) CHECK(g["summary"]["failed_speeds"].get<int>() > 0);
}

}  // namespace
}  // namespace gearnvh
