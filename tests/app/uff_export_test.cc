// UFF dataset 58 export: a small reader written here from the format's definition (fixed columns,
// independent of the writer) parses the files back, and the values must be those of the CSV and
// JSON outputs of the same run.
#include "uff_export.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "loose_gear_train_yaml.h"
#include "support/example_variant.h"
#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh::app {
namespace {

using testing::ReadWholeFile;
using testing::RunCommand;
using testing::TempDir;

struct ParsedAxis {
  int data_type = 0, length_exponent = 0, force_exponent = 0;
  std::string label, units;
};

struct Parsed58 {
  std::string id1, id2;
  int function_type = 0, function_id = 0;
  std::string response_name;
  int response_node = 0;
  int ordinate_type = 0, spacing = -1;
  long count = 0;
  double x_min = 0.0, dx = 0.0, z_value = 0.0;
  ParsedAxis abscissa, ordinate, denominator, z;
  std::vector<double> values;
};

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(' ');
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(' ') - a + 1);
}

// Columns [from, from + width) of a line, padded with blanks (Fortran reads short lines so).
std::string Field(const std::string& line, size_t from, size_t width) {
  std::string padded = line;
  if (padded.size() < from + width) padded.resize(from + width, ' ');
  return padded.substr(from, width);
}

ParsedAxis ParseAxis(const std::string& line) {  // FORMAT(I10,3I5,2(1X,20A1))
  return {std::stoi(Field(line, 0, 10)), std::stoi(Field(line, 10, 5)),
          std::stoi(Field(line, 15, 5)), Trim(Field(line, 26, 20)), Trim(Field(line, 47, 20))};
}

// Every dataset 58 of a file: blocks delimited by lines "    -1".
std::vector<Parsed58> ReadUff(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::vector<Parsed58> out;
  size_t i = 0;
  while (i < lines.size()) {
    REQUIRE(lines[i] == "    -1");
    REQUIRE(i + 13 < lines.size());
    REQUIRE(lines[i + 1] == "    58");
    Parsed58 d;
    d.id1 = Trim(lines[i + 2]);
    d.id2 = Trim(lines[i + 3]);
    for (int k = 2; k <= 6; ++k) CHECK(lines[i + k].size() <= 80);
    const std::string& r6 = lines[i + 7];  // FORMAT(2(I5,I10),2(1X,10A1,I10,I4))
    CHECK(r6.size() == 80);
    d.function_type = std::stoi(Field(r6, 0, 5));
    d.function_id = std::stoi(Field(r6, 5, 10));
    d.response_name = Trim(Field(r6, 31, 10));
    d.response_node = std::stoi(Field(r6, 41, 10));
    const std::string& r7 = lines[i + 8];  // FORMAT(3I10,3E13.5)
    d.ordinate_type = std::stoi(Field(r7, 0, 10));
    d.count = std::stol(Field(r7, 10, 10));
    d.spacing = std::stoi(Field(r7, 20, 10));
    d.x_min = std::stod(Field(r7, 30, 13));
    d.dx = std::stod(Field(r7, 43, 13));
    d.z_value = std::stod(Field(r7, 56, 13));
    d.abscissa = ParseAxis(lines[i + 9]);
    d.ordinate = ParseAxis(lines[i + 10]);
    d.denominator = ParseAxis(lines[i + 11]);
    d.z = ParseAxis(lines[i + 12]);
    i += 13;
    // Real double, even spacing: 4E20.12 per line.
    for (; i < lines.size() && lines[i] != "    -1"; ++i) {
      CHECK(lines[i].size() % 20 == 0);
      for (size_t c = 0; c + 20 <= lines[i].size(); c += 20) {
        d.values.push_back(std::stod(lines[i].substr(c, 20)));
      }
    }
    REQUIRE(i < lines.size());  // the closing -1
    ++i;
    out.push_back(std::move(d));
  }
  return out;
}

// E20.12 keeps 12 digits after the point: 5e-12 relative rounding.
constexpr double kUffRelative = 1e-11;

TEST_CASE("UFF dataset 58: the writer's records read back in their fixed columns", "[uff]") {
  UffFunction f;
  f.id1 = "a µ test";  // non-ASCII is replaced in the fixed-width ASCII records
  f.id2 = "gearbox";
  f.function_type = 12;
  f.function_id = 7;
  f.response_name = "TE";
  f.abscissa = {18, 0, 0, 0, "frequency", "Hz"};
  f.ordinate = {8, 1, 0, 0, "transmission error", "m"};
  f.z = {20, 0, 0, 0, "pinion order", "NONE"};
  f.z_value = 27.0;
  f.x_min = 12.5;
  f.dx = 0.25;
  f.values = {1.0, -2.5e-7, 3.14159265358979e-12, 0.0, 6.02214076e23};
  const std::vector<Parsed58> d = ReadUff(UffDataset58(f));
  REQUIRE(d.size() == 1);
  CHECK(d[0].id1 == "a __ test");  // the two bytes of µ
  CHECK(d[0].function_type == 12);
  CHECK(d[0].function_id == 7);
  CHECK(d[0].response_name == "TE");
  CHECK(d[0].ordinate_type == 4);  // real, double precision
  CHECK(d[0].spacing == 1);
  CHECK(d[0].count == 5);
  CHECK(d[0].x_min == 12.5);
  CHECK(d[0].dx == 0.25);
  CHECK(d[0].z_value == 27.0);
  CHECK(d[0].abscissa.data_type == 18);
  CHECK(d[0].abscissa.units == "Hz");
  CHECK(d[0].ordinate.data_type == 8);
  CHECK(d[0].ordinate.length_exponent == 1);
  CHECK(d[0].ordinate.label == "transmission error");
  CHECK(d[0].z.label == "pinion order");
  REQUIRE(d[0].values.size() == 5);
  for (size_t i = 0; i < 5; ++i) {
    CHECK(d[0].values[i] == Approx(f.values[i]).epsilon(kUffRelative).margin(1e-300));
  }
}

using testing::kExe;

// A loaded pair with short runs (its mesh harmonics stand far above the background).
const std::string kGearbox = R"(schema: gearnvh/1
name: uff pair
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

std::vector<std::vector<std::string>> Csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::istringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) row.push_back(c);
    rows.push_back(row);
  }
  return rows;
}

TEST_CASE("simulate --uff: TE and mesh force histories and the TE spectrum read back", "[uff]") {
  const TempDir dir;
  const auto file = dir.Write("pair.yaml", kGearbox);
  const auto uff = dir.path() / "op.uff";
  const auto r = RunCommand(kExe + " simulate --json --uff " + uff.string() + " --out " +
                            (dir.path() / "out").string() + " " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  const std::vector<Parsed58> d = ReadUff(ReadWholeFile(uff));
  REQUIRE(d.size() == 3);
  const auto csv = Csv(ReadWholeFile(dir.path() / "out" / "trajectory.csv"));
  REQUIRE(csv.size() == 1 + 64 * 32);
  REQUIRE(csv[0][1] == "te_m");
  REQUIRE(csv[0][2] == "mesh_force_n");
  // Time histories: every sample, in order, equal to the CSV's (17 digits) to the UFF rounding.
  const double mesh_period = 60.0 / (1500.0 * 23);
  for (int k = 0; k < 2; ++k) {
    const Parsed58& h = d[static_cast<size_t>(k)];
    INFO(h.id1);
    CHECK(h.function_type == 1);
    CHECK(h.abscissa.data_type == 17);
    CHECK(h.abscissa.units == "s");
    CHECK(h.ordinate.units == (k == 0 ? "m" : "N"));
    REQUIRE(h.count == 64 * 32);
    REQUIRE(h.values.size() == 64 * 32);
    // E13.5 abscissa fields: 6 significant digits.
    CHECK(h.dx == Approx(mesh_period / 32).epsilon(1e-5));
    CHECK(h.x_min == Approx(std::stod(csv[1][0])).epsilon(1e-5));
    for (size_t i = 0; i < h.values.size(); ++i) {
      const double expected = std::stod(csv[i + 1][static_cast<size_t>(k + 1)]);
      REQUIRE(h.values[i] == Approx(expected).epsilon(kUffRelative).margin(1e-300));
    }
  }
  // The spectrum: the mesh-frequency bin holds the "1 fm" amplitude of the sideband table.
  const Parsed58& s = d[2];
  CHECK(s.function_type == 12);
  CHECK(s.abscissa.data_type == 18);
  const long window = doc["sideband_window_cycles"].get<long>();
  REQUIRE(window == 64);
  CHECK(s.count == window * 32 / 2 + 1);
  CHECK(s.dx == Approx(1.0 / (window * mesh_period)).epsilon(1e-5));
  double fm_amplitude = -1.0;
  for (const auto& row : doc["sidebands"]) {
    if (row["label"] == "1 fm") fm_amplitude = row["amplitude_m"].get<double>();
  }
  REQUIRE(fm_amplitude > 0.0);
  CHECK(s.values[static_cast<size_t>(window)] == Approx(fm_amplitude).epsilon(kUffRelative));
}

TEST_CASE("simulate --uff and --out on a gear train: every mesh's histories and spectrum read back",
          "[uff][train]") {
  // The rattling three-mesh train: TE, mesh force and TE spectrum per mesh, response node i + 1,
  // the same values as trajectory.csv's columns of that mesh; events.csv holds the JSON's count.
  const TempDir dir;
  const auto file = dir.Write("train.yaml", testing::kLooseGearTrainYaml);
  const auto uff = dir.path() / "op.uff";
  const auto r =
      RunCommand(kExe + " simulate --json --cycles 200 --transient 50 --uff " + uff.string() +
                 " --out " + (dir.path() / "out").string() + " " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  const auto& meshes = doc["meshes"];
  REQUIRE(meshes.size() == 3);
  const long samples = doc["time_histories"]["samples"].get<long>();
  CHECK(samples == 200 * 32);  // the first mesh (a-b) is the fastest: 32 samples per cycle
  CHECK_FALSE(doc["time_histories"]["truncated"].get<bool>());
  const std::vector<Parsed58> d = ReadUff(ReadWholeFile(uff));
  REQUIRE(d.size() == 9);
  const auto csv = Csv(ReadWholeFile(dir.path() / "out" / "trajectory.csv"));
  REQUIRE(csv.size() == static_cast<size_t>(1 + samples));
  REQUIRE(csv[0].size() == 1 + 3 * 3);
  const auto events = Csv(ReadWholeFile(dir.path() / "out" / "events.csv"));
  CHECK(events.size() == 1 + doc["time_histories"]["events"].get<size_t>());
  CHECK(events[0] == std::vector<std::string>{"time_s", "mesh", "from", "to", "gap_rate_m_s"});
  int listed_lines = 0;
  for (size_t i = 0; i < 3; ++i) {
    const std::string name = meshes[i]["name"].get<std::string>();
    INFO("mesh " << name);
    CHECK(csv[0][1 + 3 * i] == name + ".te_m");
    CHECK(csv[0][2 + 3 * i] == name + ".mesh_force_n");
    CHECK(csv[0][3 + 3 * i] == name + ".contact");
    for (size_t k = 0; k < 2; ++k) {
      const Parsed58& h = d[3 * i + k];
      INFO(h.id1);
      CHECK(h.id1.find(", mesh " + name) != std::string::npos);
      CHECK(h.response_node == static_cast<int>(i) + 1);
      CHECK(h.function_type == 1);
      CHECK(h.ordinate.units == (k == 0 ? "m" : "N"));
      REQUIRE(h.count == samples);
      // E13.5 abscissa fields: 6 significant digits of the CSV's first time and its step.
      CHECK(h.x_min == Approx(std::stod(csv[1][0])).epsilon(1e-5));
      CHECK(h.dx == Approx(std::stod(csv[2][0]) - std::stod(csv[1][0])).epsilon(1e-5));
      for (size_t j = 0; j < h.values.size(); ++j) {
        const double expected = std::stod(csv[j + 1][1 + 3 * i + k]);
        REQUIRE(h.values[j] == Approx(expected).epsilon(kUffRelative).margin(1e-300));
      }
    }
    // The spectrum: the mesh frequency's bin holds the Hann amplitude (mean removed, periodic
    // window, 2 |X_k| / sum w) of the record's last n TE samples of trajectory.csv, by a direct
    // DFT at that one bin. The rattle is chaotic, so which lines the table lists differs between
    // builds; this check does not depend on it. 1e-9 of the largest bin: the DFT's and FFTW's
    // rounding over n <= 6,400 terms.
    const Parsed58& s = d[3 * i + 2];
    CHECK(s.function_type == 12);
    CHECK(s.response_node == static_cast<int>(i) + 1);
    CHECK(s.id1.find(", mesh " + name) != std::string::npos);
    const long window = meshes[i]["sideband_window_cycles"].get<long>();
    REQUIRE(window > 0);
    const long n = 2 * (s.count - 1);
    REQUIRE(n <= samples);
    std::vector<double> te(static_cast<size_t>(n));
    for (long j = 0; j < n; ++j) {
      te[static_cast<size_t>(j)] =
          std::stod(csv[static_cast<size_t>(samples - n + j + 1)][1 + 3 * i]);
    }
    double mean = 0.0;
    for (double v : te) mean += v;
    mean /= static_cast<double>(n);
    double re = 0.0, im = 0.0, window_sum = 0.0;
    for (long j = 0; j < n; ++j) {
      const double w = 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * static_cast<double>(j) /
                                             static_cast<double>(n)));
      const double phase =
          2.0 * std::numbers::pi * static_cast<double>(window * j % n) / static_cast<double>(n);
      re += (te[static_cast<size_t>(j)] - mean) * w * std::cos(phase);
      im -= (te[static_cast<size_t>(j)] - mean) * w * std::sin(phase);
      window_sum += w;
    }
    const double largest = *std::max_element(s.values.begin(), s.values.end());
    CHECK(s.values[static_cast<size_t>(window)] ==
          Approx(2.0 * std::hypot(re, im) / window_sum).epsilon(1e-9).margin(1e-9 * largest));
    // Every line the mesh's table lists sits on its bin of this spectrum.
    for (const auto& row : meshes[i]["sidebands"]) {
      ++listed_lines;
      const auto bin = static_cast<size_t>(std::lround(row["frequency_hz"].get<double>() / s.dx));
      INFO(row["label"].get<std::string>());
      CHECK(s.values[bin] == Approx(row["amplitude_m"].get<double>()).epsilon(kUffRelative));
    }
  }
  INFO("lines listed by the three meshes' tables: " << listed_lines);
}

TEST_CASE("sweep --uff: order tracks at mesh orders 1 to 3 equal the waterfall", "[uff]") {
  const TempDir dir;
  const auto file = dir.Write("pair.yaml", kGearbox);
  const auto uff = dir.path() / "sweep.uff";
  const auto r = RunCommand(kExe + " sweep --json --cycles 64 --transient 16 --uff " +
                            uff.string() + " " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  const auto& waterfall = doc["waterfall"];
  const double order_step = waterfall["order_step"].get<double>();
  const std::vector<Parsed58> d = ReadUff(ReadWholeFile(uff));
  REQUIRE(d.size() == 3);
  for (int k = 1; k <= 3; ++k) {
    const Parsed58& t = d[static_cast<size_t>(k - 1)];
    INFO("mesh order " << k);
    CHECK(t.abscissa.data_type == 19);  // rpm
    CHECK(t.abscissa.units == "rpm");
    CHECK(t.z.data_type == 20);  // order
    CHECK(t.z_value == Approx(23.0 * k).epsilon(1e-12));
    CHECK(t.x_min == Approx(1000.0).epsilon(1e-12));
    CHECK(t.dx == Approx(500.0).epsilon(1e-12));
    REQUIRE(t.values.size() == 3);
    const size_t bin = static_cast<size_t>(std::lround(23.0 * k / order_step));
    for (size_t p = 0; p < 3; ++p) {
      const double expected = waterfall["amplitude_m"][p][bin].get<double>();
      CHECK(t.values[p] == Approx(expected).epsilon(kUffRelative).margin(1e-300));
    }
  }
}

TEST_CASE("sweep --uff on a gear train: every mesh's order tracks equal its waterfall",
          "[uff][train]") {
  // Three meshes, three mesh orders each; a track reads the larger of the two waterfall bins
  // around its order (input-shaft orders), the bin itself when the order is on one. Five speeds,
  // not the file's default 56: what is checked is how tracks are read, not the sweep (the 56 took
  // 89 s under the sanitizers).
  const TempDir dir;
  const auto file = dir.Write(
      "train.yaml", std::string(testing::kLooseGearTrainYaml) +
                        "analysis:\n  speed_sweep: {from: 800 rpm, to: 1200 rpm, points: 5}\n");
  const auto uff = dir.path() / "sweep.uff";
  const auto r = RunCommand(kExe + " sweep --json --cycles 40 --transient 10 --uff " +
                            uff.string() + " " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  const auto& waterfall = doc["waterfall"];
  const double step = waterfall["order_step"].get<double>();
  const std::vector<double> speeds = doc["speeds_rpm"].get<std::vector<double>>();
  const std::vector<Parsed58> d = ReadUff(ReadWholeFile(uff));
  REQUIRE(waterfall["meshes"].size() == 3);
  REQUIRE(d.size() == 9);
  for (size_t i = 0; i < 3; ++i) {
    const auto& mesh = waterfall["meshes"][i];
    const std::string name = mesh["name"].get<std::string>();
    const double order = mesh["mesh_order"].get<double>();
    const auto rows = mesh["amplitude_m"].get<std::vector<std::vector<double>>>();
    REQUIRE(rows.size() == speeds.size());
    for (int k = 1; k <= 3; ++k) {
      const Parsed58& t = d[3 * i + static_cast<size_t>(k - 1)];
      INFO(t.id1);
      CHECK(t.id1.find("mesh order " + std::to_string(k) + " of " + name) != std::string::npos);
      CHECK(t.abscissa.label == "input speed");
      CHECK(t.z.label == "input order");
      CHECK(t.z_value == Approx(k * order).epsilon(1e-5));
      CHECK(t.x_min == Approx(speeds.front()).epsilon(1e-5));
      CHECK(t.dx == Approx(speeds[1] - speeds[0]).epsilon(1e-5));
      REQUIRE(t.values.size() == speeds.size());
      CHECK(*std::max_element(t.values.begin(), t.values.end()) > 0.0);  // a line, not empty
      const double at = k * order / step;
      const auto lo = static_cast<size_t>(std::floor(at + 1e-9));
      const size_t hi = std::abs(at - std::round(at)) < 1e-9 ? lo : lo + 1;
      for (size_t s = 0; s < speeds.size(); ++s) {
        const double expected = std::max(rows[s].at(lo), rows[s].at(hi));
        CHECK(t.values[s] == Approx(expected).epsilon(kUffRelative).margin(1e-300));
      }
    }
  }
}

TEST_CASE("sweep --uff with a failed speed writes the tracks of the speeds that succeeded",
          "[uff]") {
  // 5000 and 5500 rpm finish, 6000 rpm stops out of range (testing::kStrongRattleSweep).
  const TempDir dir;
  const std::string file =
      testing::WriteExampleVariant(dir, "flexible_shafts.yaml",
                                   {testing::kStrongRattlePoint, testing::kStrongRattleSweep})
          .string();
  const auto uff = dir.path() / "sweep.uff";
  const std::string sweep = kExe + " sweep --json --tier 2 --cycles 300 --transient 100 --uff ";
  const auto r = RunCommand(sweep + uff.string() + " " + file);
  INFO(r.err);
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("the order tracks hold the 2 speeds that succeeded") != std::string::npos);
  const auto doc = nlohmann::json::parse(r.out);
  const auto& waterfall = doc["waterfall"];
  const double order_step = waterfall["order_step"].get<double>();
  const std::string text = ReadWholeFile(uff);
  CHECK(text.find("speeds 5000 to 5500 rpm only: 1 of 3 speeds failed") != std::string::npos);
  const std::vector<Parsed58> d = ReadUff(text);
  REQUIRE(d.size() == 3);
  for (int k = 1; k <= 3; ++k) {
    const Parsed58& t = d[static_cast<size_t>(k - 1)];
    INFO("mesh order " << k);
    CHECK(t.x_min == Approx(5000.0).epsilon(1e-12));
    CHECK(t.dx == Approx(500.0).epsilon(1e-12));
    REQUIRE(t.values.size() == 2);
    const size_t bin = static_cast<size_t>(std::lround(31.0 * k / order_step));
    for (size_t p = 0; p < 2; ++p) {
      const double expected = waterfall["amplitude_m"][p][bin].get<double>();
      CHECK(t.values[p] == Approx(expected).epsilon(kUffRelative).margin(1e-300));
    }
  }

  // Every speed failed: nothing to write, and the earlier file is kept as it was.
  const std::string failing =
      testing::WriteExampleVariant(dir, "flexible_shafts.yaml",
                                   {testing::kStrongRattlePoint,
                                    {"  speed_sweep: {from: 500 rpm, to: 9000 rpm, points: 35}",
                                     "  speed_sweep: {from: 6000 rpm, to: 7000 rpm, points: 2}"}})
          .string();
  const auto none = RunCommand(sweep + uff.string() + " " + failing);
  CHECK(none.exit_code == 1);
  CHECK(none.err.find("not written") != std::string::npos);
  CHECK(ReadWholeFile(uff) == text);
}

}  // namespace
}  // namespace gearnvh::app
