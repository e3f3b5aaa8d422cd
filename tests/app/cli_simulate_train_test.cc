// `gearnvh simulate` on gear trains (schema gearnvh/2): the train solver end to end.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "app/three_shaft_train_yaml.h"
#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::RunCommand;

using testing::kExe;
using testing::kExamples;

TEST_CASE("a train without load or excitation rests: no contact event", "[cli][train]") {
  // Every gear at rest on its wall or floating at relative speed 0: the gaps move by rounding
  // alone. The event search once took that noise for crossings and stopped after 1000 events in
  // one grid segment (at 5000 rpm, 0.25 ms in).
  std::string yaml = testing::ReplaceFirst(testing::kThreeShaftTrainYaml, "torque: 1 N*m",
                                           "torque: 0 N*m");
  yaml = testing::ReplaceFirst(yaml, "  excitation:\n    - {order: 2, amplitude: 500 rad/s^2}\n",
                               "");
  yaml = testing::ReplaceFirst(yaml, "value: 1000 rpm", "value: 5000 rpm");
  const testing::TempDir dir;
  const auto r = RunCommand(kExe + " simulate --json --cycles 512 --transient 10 " +
                            dir.Write("resting.yaml", yaml).string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto solver = nlohmann::json::parse(r.out)["summary"];
  CHECK(solver["status"] == "success");
  CHECK(solver["events"] == 0);
}

TEST_CASE("simulate --json on a train reports every mesh and ranks the loose gears",
          "[cli][train]") {
  const auto r = RunCommand(kExe + " simulate --json --cycles 40 --transient 10 " + kExamples +
                            "/manual_transmission_idle.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["schema"] == "gearnvh/2");
  CHECK(doc["state_dim"] == 2 * 7 + 3);  // x, x', 1 and the engine order's two states
  REQUIRE(doc["meshes"].size() == 6);
  CHECK(doc["meshes"][0]["name"] == "in-l0");
  CHECK(doc["meshes"][5]["name"] == "l5-o5");
  for (const auto& m : doc["meshes"]) {
    CHECK(m["te"]["rms"].get<double>() >= 0.0);
    CHECK(m["te"]["peak_to_peak"].get<double>() >= 2.0 * m["te"]["rms"].get<double>() - 1e-15);
    CHECK(m["mesh_force"]["max"].get<double>() >= m["mesh_force"]["mean"].get<double>());
    const double f = m["rattle"]["separation_fraction"].get<double>();
    CHECK((f >= 0.0 && f <= 1.0));
  }
  // The four loose gears, ranked 1..4 by a non-increasing impact energy per second (each
  // impacts at idle), with their impact rates, velocities and RMS acceleration.
  const auto& loose = doc["loose_gears"];
  REQUIRE(loose.size() == 4);
  for (size_t k = 0; k < loose.size(); ++k) {
    CHECK(loose[k]["rank"] == static_cast<int>(k) + 1);
    CHECK(loose[k]["impacts"].get<long>() > 0);
    CHECK(loose[k]["impact_velocity_max"].get<double>() >=
          loose[k]["impact_velocity_rms"].get<double>());
    CHECK(loose[k]["rattle_index"].get<double>() > 0.0);
    CHECK(loose[k]["drive_impacts_per_second"].get<double>() +
              loose[k]["back_impacts_per_second"].get<double>() >
          0.0);
    if (k > 0) {
      CHECK(loose[k]["impact_energy_per_second"].get<double>() <=
            loose[k - 1]["impact_energy_per_second"].get<double>());
    }
  }
  // 50 cycles of the headset mesh (21 teeth at 800 rpm).
  CHECK(doc["summary"]["simulated_s"].get<double>() ==
        Approx(50.0 * 60.0 / (800.0 * 21.0)).epsilon(1e-9));
  CHECK(doc["summary"]["cache"]["bytes"].get<double>() > 0.0);
  // A rattling idle with no transient: nothing jumped, and the reason is given.
  CHECK(doc["summary"]["jumps"]["periods"].get<long>() == 0);
  CHECK(doc["summary"]["jumps"]["status"].get<std::string>() == "transient too short");
  CHECK(doc["summary"]["jumps"]["cycle_map"]["builds"].get<long>() == 0);
  // Segment runs fuse unrecorded time only: with no transient nothing is fused or built.
  const auto& runs = doc["summary"]["segment_runs"];
  CHECK(runs["runs"].get<long>() == 0);
  CHECK(runs["grid_segments"].get<long>() == 0);
  CHECK(runs["tables"].get<long>() == 0);
  CHECK(runs["levels"].get<int>() == 5);
  CHECK(runs["min_periods"].get<long>() == 64);
}

TEST_CASE("neutral at standstill: the fixed output stands and all five loose gears rattle",
          "[cli][train]") {
  // examples/manual_transmission_neutral.yaml: the output shaft is fixed, o1..o5 idle on it.
  const std::string file = kExamples + "/manual_transmission_neutral.yaml";
  const auto check = RunCommand(kExe + " check --json " + file);
  INFO(check.err);
  REQUIRE(check.exit_code == 0);
  const auto model = nlohmann::json::parse(check.out);
  bool found = false;
  for (const auto& b : model["bodies"]) {
    if (b["name"] != "output") continue;
    found = true;
    CHECK(b["speed"].get<double>() == 0.0);
    CHECK(b["gears"].empty());
  }
  CHECK(found);
  // A fixed shaft has no order line (shaft lines read "<shaft>[, <shaft>] 1x"), so no crossing.
  const auto names_output = [](const nlohmann::json& label) {
    const std::string text = label.get<std::string>();
    return text.find("output 1x") != std::string::npos ||
           text.find("output, ") != std::string::npos;
  };
  REQUIRE_FALSE(model["campbell"]["orders"].empty());
  for (const auto& o : model["campbell"]["orders"]) CHECK_FALSE(names_output(o["label"]));
  for (const auto& c : model["critical_speeds"]) CHECK_FALSE(names_output(c["line"]));

  const auto r = RunCommand(kExe + " simulate --json --cycles 40 --transient 10 " + file);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["state_dim"] == 2 * 8 + 3);  // 3 shafts and 5 loose gears, 1, the engine order
  const auto& loose = doc["loose_gears"];
  REQUIRE(loose.size() == 5);
  for (const auto& g : loose) CHECK(g["impacts"].get<long>() > 0);
}

TEST_CASE("the driveline example: couplings carry the torque flow and the flywheel drives",
          "[cli][train]") {
  // examples/manual_transmission_driveline.yaml: flywheel -(clutch damper)- input ... output
  // -(halfshaft)- wheels, 15 N m on the wheels.
  const std::string file = kExamples + "/manual_transmission_driveline.yaml";
  const auto check = RunCommand(kExe + " check --json " + file);
  INFO(check.err);
  REQUIRE(check.exit_code == 0);
  const auto model = nlohmann::json::parse(check.out);
  REQUIRE(model["couplings"].size() == 2);
  const auto& damper = model["couplings"][0];
  const auto& halfshaft = model["couplings"][1];
  CHECK(damper["name"] == "clutch_damper");
  CHECK(damper["between"][0] == "flywheel");
  // 9 N m/deg in SI; the damper carries the input torque (flywheel to input: > 0), the halfshaft
  // the wheels' load, and each twists by its torque over its stiffness (rounding only).
  CHECK(damper["stiffness_n_m_per_rad"].get<double>() ==
        Approx(9.0 * 180.0 / std::numbers::pi).epsilon(1e-14));
  CHECK(damper["mean_torque_n_m"].get<double>() ==
        Approx(model["input_torque"].get<double>()).epsilon(1e-14));
  CHECK(halfshaft["mean_torque_n_m"].get<double>() == Approx(15.0).epsilon(1e-14));
  CHECK(halfshaft["mean_twist_deg"].get<double>() ==
        Approx(15.0 / 700.0 * 180.0 / std::numbers::pi).epsilon(1e-14));
  // The flywheel and the wheels carry no gear and turn with the shafts they are coupled to.
  double input = 0.0, flywheel = 0.0, output = 0.0, wheels = 0.0;
  for (const auto& b : model["bodies"]) {
    const double w = b["speed"].get<double>();
    if (b["name"] == "input") input = w;
    if (b["name"] == "flywheel") flywheel = w;
    if (b["name"] == "output") output = w;
    if (b["name"] == "wheels") wheels = w;
  }
  CHECK(flywheel > 0.0);
  CHECK(input == flywheel);
  CHECK(wheels == output);
  CHECK(model["fe"]["free_rotations"] == 1);
  // The 2nd engine order on the flywheel crosses each tier-1 mode at half the input speed where
  // the flywheel's (and the input's) 1x line does (rounding only).
  std::map<int, double> order_two, shaft_one;
  for (const auto& c : model["critical_speeds"]) {
    const std::string line = c["line"].get<std::string>();
    if (line == "excitation 2x flywheel") order_two[c["mode"]] = c["input_speed"];
    const bool shaft_line = line.rfind("mesh ", 0) != 0 && line.rfind("excitation ", 0) != 0;
    if (shaft_line && line.find("flywheel") != std::string::npos) {
      shaft_one[c["mode"]] = c["input_speed"];
    }
  }
  REQUIRE(order_two.size() == shaft_one.size());
  REQUIRE_FALSE(order_two.empty());
  for (const auto& [mode, speed] : order_two) {
    CHECK(speed == Approx(0.5 * shaft_one[mode]).epsilon(1e-14));
  }
  // Each crossing names its mode's frequency: the order line's there (2 x the flywheel speed;
  // rounding only).
  for (const auto& c : model["critical_speeds"]) {
    if (c["line"] != "excitation 2x flywheel") continue;
    CHECK(c["frequency_hz"].get<double>() ==
          Approx(2.0 * c["input_speed"].get<double>() / (2.0 * std::numbers::pi)).epsilon(1e-13));
  }

  const testing::TempDir dir;
  const auto r = RunCommand(kExe + " simulate --json --cycles 20 --transient 5 --out " +
                            (dir.path() / "out").string() + " --uff " +
                            (dir.path() / "run.uff").string() + " " + file);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["state_dim"] == 2 * 9 + 3);  // 5 shafts and 4 loose gears, 1, the engine order
  CHECK(doc["summary"]["status"] == "success");
  REQUIRE(doc["couplings"].size() == 2);
  CHECK(doc["couplings"][1]["name"] == "halfshaft");

  // trajectory.csv: each coupling's twist and torque at every sample. Every sample lies inside
  // the exact record's certified extrema (rounding: 1e-9 of the range), and the torque column is
  // k twist + c twist': against c times the samples' central difference of the twist, whose
  // truncation error (w dt)^2 / 6 is < 1 % at the mesh frequencies the twist carries (32 samples
  // per fastest mesh cycle), so 1 % of the largest c twist' bounds it (measured: 6e-4).
  const std::vector<std::vector<double>> samples = [&] {
    std::ifstream csv(dir.path() / "out" / "trajectory.csv");
    std::string line;
    std::getline(csv, line);
    std::vector<std::string> names;
    std::stringstream header(line);
    for (std::string name; std::getline(header, name, ',');) names.push_back(name);
    std::vector<std::vector<double>> columns(4);
    const std::vector<std::string> wanted = {"clutch_damper.twist_rad", "clutch_damper.torque_n_m",
                                             "halfshaft.twist_rad", "halfshaft.torque_n_m"};
    std::vector<size_t> at;
    for (const std::string& w : wanted) {
      at.push_back(static_cast<size_t>(std::find(names.begin(), names.end(), w) - names.begin()));
      REQUIRE(at.back() < names.size());
    }
    while (std::getline(csv, line)) {
      std::vector<std::string> cells;
      std::stringstream row(line);
      for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
      REQUIRE(cells.size() == names.size());
      for (size_t k = 0; k < 4; ++k) columns[k].push_back(std::stod(cells[at[k]]));
    }
    return columns;
  }();
  REQUIRE(samples[0].size() > 100);
  const double dt = doc["time_histories"]["sample_interval_s"].get<double>();
  for (size_t c = 0; c < 2; ++c) {
    const auto& exact = doc["couplings"][c];
    const std::vector<double>& twist = samples[2 * c];
    const std::vector<double>& torque = samples[2 * c + 1];
    for (const auto& [series, key] : {std::pair{&twist, "twist_rad"}, {&torque, "torque_n_m"}}) {
      const double low = exact[key]["min"].get<double>(), high = exact[key]["max"].get<double>();
      const double slack = 1e-9 * (high - low) + 1e-15 * std::abs(high);
      CHECK(*std::min_element(series->begin(), series->end()) >= low - slack);
      CHECK(*std::max_element(series->begin(), series->end()) <= high + slack);
    }
    const double k = model["couplings"][c]["stiffness_n_m_per_rad"].get<double>();
    const double damping = model["couplings"][c]["damping_n_m_s_per_rad"].get<double>();
    double largest = 0.0, worst = 0.0;
    for (size_t j = 1; j + 1 < twist.size(); ++j) {
      const double viscous = damping * (twist[j + 1] - twist[j - 1]) / (2.0 * dt);
      largest = std::max(largest, std::abs(viscous));
      worst = std::max(worst, std::abs(torque[j] - k * twist[j] - viscous));
    }
    INFO("coupling " << c << ": largest c twist' " << largest << " N m");
    CHECK(largest > 1e-3);  // the engine order moves both couplings
    CHECK(worst <= 0.01 * largest);
  }
  // The UFF file holds each coupling's twist and torque histories: their first samples are the
  // CSV's (the file's 12 significant digits: 1e-10 relative).
  const std::string uff = [&] {
    std::ifstream in(dir.path() / "run.uff");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }();
  for (size_t c = 0; c < 2; ++c) {
    const std::string name = doc["couplings"][c]["name"];
    for (const std::string what : {"coupling twist, ", "coupling torque, "}) {
      const size_t at = uff.find(what + name);
      REQUIRE(at != std::string::npos);
      // Dataset 58: the ID line, 4 more ID lines, records 6 to 11, then the values.
      std::stringstream block(uff.substr(at));
      std::string line;
      for (int skip = 0; skip < 11; ++skip) std::getline(block, line);
      double first = 0.0;
      block >> first;
      const double expected = samples[2 * c + (what == "coupling twist, " ? 0 : 1)].front();
      CHECK(first == Approx(expected).epsilon(1e-10));
    }
  }

  // From tier 2 on the bearings' force rows are tracked first: the couplings' columns still follow
  // the bearings' and hold values inside their exact extrema (as above).
  const auto tier3 = RunCommand(kExe + " simulate --json --tier 3 --cycles 6 --transient 2 --out " +
                                (dir.path() / "tier3").string() + " " + file);
  INFO(tier3.err);
  REQUIRE(tier3.exit_code == 0);
  const auto doc3 = nlohmann::json::parse(tier3.out);
  REQUIRE_FALSE(doc3["bearings"].empty());
  {
    std::ifstream csv(dir.path() / "tier3" / "trajectory.csv");
    std::string header, row;
    REQUIRE(std::getline(csv, header));
    const std::string tail =
        ",clutch_damper.twist_rad,clutch_damper.torque_n_m,"
        "halfshaft.twist_rad,halfshaft.torque_n_m";
    REQUIRE(header.size() > tail.size());
    CHECK(header.substr(header.size() - tail.size()) == tail);
    CHECK(header.find(".force_z_n") < header.find("clutch_damper"));
    long rows = 0;
    while (std::getline(csv, row)) {
      ++rows;
      REQUIRE(std::count(row.begin(), row.end(), ',') ==
              std::count(header.begin(), header.end(), ','));
      const size_t comma =
          row.rfind(',', row.rfind(',', row.rfind(',', row.rfind(',') - 1) - 1) - 1);
      const double twist = std::stod(row.substr(comma + 1));
      const auto& exact = doc3["couplings"][0]["twist_rad"];
      const double slack = 1e-9 * (exact["max"].get<double>() - exact["min"].get<double>());
      CHECK(twist >= exact["min"].get<double>() - slack);
      CHECK(twist <= exact["max"].get<double>() + slack);
    }
    CHECK(rows == doc3["time_histories"]["samples"].get<long>());
  }

  // Without the engine order the train stays in permanent contact near its static state: each
  // coupling's exact mean twist is its static T / k (the meshes' stiffness variation and the
  // start's ringing move the shafts by a small part of that; 1e-4).
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const std::string quiet =
      testing::ReplaceFirst(text.str(), "amplitude: 600 rad/s^2", "amplitude: 0 rad/s^2");
  const auto still = RunCommand(kExe + " simulate --json --cycles 40 --transient 10 " +
                                dir.Write("quiet.yaml", quiet).string());
  INFO(still.err);
  REQUIRE(still.exit_code == 0);
  const auto calm = nlohmann::json::parse(still.out);
  REQUIRE(calm["summary"]["events"] == 0);  // in contact throughout
  for (size_t c = 0; c < 2; ++c) {
    const auto& twist = calm["couplings"][c]["twist_rad"];
    const double expected =
        model["couplings"][c]["mean_twist_deg"].get<double>() * std::numbers::pi / 180.0;
    CHECK(twist["mean"].get<double>() == Approx(expected).epsilon(1e-4));
  }
}

TEST_CASE("a coupling twisted past 15 deg by its static torque is warned of: a unit slip?",
          "[cli][train]") {
  // 9 N m/rad instead of 9 N m/deg: 4.69 N m twists the damper by 29.8 deg.
  std::ifstream in(kExamples + "/manual_transmission_driveline.yaml");
  std::stringstream text;
  text << in.rdbuf();
  const testing::TempDir dir;
  const auto run = [&](const std::string& yaml) {
    const auto r = RunCommand(kExe + " check --json " + dir.Write("d.yaml", yaml).string());
    REQUIRE(r.exit_code == 0);
    return nlohmann::json::parse(r.out)["warnings"].dump();
  };
  CHECK(run(text.str()).find("clutch_damper") == std::string::npos);
  const std::string soft =
      run(testing::ReplaceFirst(text.str(), "stiffness: 9 N*m/deg", "stiffness: 9 N*m/rad"));
  CHECK(soft.find("coupling 'clutch_damper': the static twist 29.8") != std::string::npos);
  CHECK(soft.find("N*m/deg") != std::string::npos);
}

TEST_CASE("check on a multi-stage clutch damper: the static twist along its stages, its stage",
          "[cli][train]") {
  // The example's damper in three stages: 0.4 N m/deg to 1.5 deg, 9 to 8 deg, 60 beyond. The
  // input torque T (4.686 N m) twists it by 1.5 deg + (T - 0.6 N m) / (9 N m/deg), in stage 2
  // (closed form, rounding only: 1e-12); the modes use stage 2's stiffness, as the linear file's.
  std::ifstream in(kExamples + "/manual_transmission_driveline.yaml");
  std::stringstream text;
  text << in.rdbuf();
  const testing::TempDir dir;
  const auto check = [&](const std::string& yaml) {
    const auto r = RunCommand(kExe + " check --json " + dir.Write("d.yaml", yaml).string());
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return nlohmann::json::parse(r.out);
  };
  const nlohmann::json linear = check(text.str());
  const nlohmann::json staged = check(testing::ReplaceFirst(
      text.str(), "stiffness: 9 N*m/deg",
      "stages: [{to: 1.5 deg, stiffness: 0.4 N*m/deg}, {to: 8 deg, stiffness: 9 N*m/deg}, "
      "{stiffness: 60 N*m/deg}]"));
  const auto& damper = staged["couplings"][0];
  const double torque = damper["mean_torque_n_m"].get<double>();
  CHECK(damper["mean_twist_deg"].get<double>() ==
        Approx(1.5 + (torque - 0.4 * 1.5) / 9.0).epsilon(1e-12));
  CHECK(damper["static_stage"] == 2);
  CHECK(damper["static_stiffness_n_m_per_rad"].get<double>() ==
        Approx(9.0 * 180.0 / std::numbers::pi).epsilon(1e-14));
  CHECK(damper["stages_after_first"].size() == 2);
  // The same frequencies as the linear damper at stage 2's stiffness (one eigensolve each, the
  // same matrices: 1e-12).
  for (const auto& [lin, stg] :
       {std::pair{linear["fe"], staged["fe"]}, std::pair{linear["tiers"][0], staged["tiers"][0]},
        std::pair{linear["tiers"][2], staged["tiers"][2]}}) {
    const auto& f_lin = lin["natural_frequencies_hz"];
    const auto& f_stg = stg["natural_frequencies_hz"];
    REQUIRE(f_lin.size() == f_stg.size());
    for (size_t i = 0; i < f_lin.size(); ++i)
      CHECK(f_stg[i].get<double>() == Approx(f_lin[i].get<double>()).epsilon(1e-12));
  }
  // Stiffnesses per radian meant per degree twist it past 90 deg: warned of.
  const nlohmann::json slip = check(testing::ReplaceFirst(
      text.str(), "stiffness: 9 N*m/deg",
      "stages: [{to: 1.5 deg, stiffness: 0.4 N*m/rad}, {to: 8 deg, stiffness: 0.9 N*m/rad}, "
      "{stiffness: 1 N*m/rad}]"));
  CHECK(slip["warnings"].dump().find("past 90 deg") != std::string::npos);
}

TEST_CASE("the driveline's sweep gives each coupling's twist and torque at every speed",
          "[cli][train][sweep]") {
  // Without the engine order, in permanent contact: at every speed the halfshaft carries the
  // wheels' 15 N m and the clutch damper the input torque, each at its mean over the record (what
  // the start leaves ringing moves the means by 1e-6 of the torque, measured: 1e-5).
  std::ifstream in(kExamples + "/manual_transmission_driveline.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml =
      testing::ReplaceFirst(text.str(), "amplitude: 600 rad/s^2", "amplitude: 0 rad/s^2");
  yaml = testing::ReplaceFirst(
      yaml, "analysis:\n", "analysis:\n  speed_sweep: {from: 700 rpm, to: 1500 rpm, points: 3}\n");
  const testing::TempDir dir;
  const std::string file = dir.Write("quiet.yaml", yaml).string();
  const auto check = RunCommand(kExe + " check --json " + file);
  REQUIRE(check.exit_code == 0);
  const double input_torque = nlohmann::json::parse(check.out)["input_torque"].get<double>();
  const auto r = RunCommand(kExe + " sweep --json --cycles 400 --transient 200 --out " +
                            (dir.path() / "out").string() + " " + file);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  REQUIRE(doc["points"].size() == 3);
  for (const auto& p : doc["points"]) {
    REQUIRE(p["couplings"].size() == 2);
    CHECK(p["couplings"][0]["torque_n_m"]["mean"].get<double>() ==
          Approx(input_torque).epsilon(1e-5));
    CHECK(p["couplings"][1]["torque_n_m"]["mean"].get<double>() == Approx(15.0).epsilon(1e-5));
  }
  // couplings.csv: a row per speed and coupling, the JSON's numbers (12 digits).
  std::ifstream csv(dir.path() / "out" / "couplings.csv");
  std::string line;
  REQUIRE(std::getline(csv, line));
  CHECK(line.rfind("speed_rpm,coupling,twist_mean_rad,", 0) == 0);
  long rows = 0;
  while (std::getline(csv, line)) {
    std::stringstream row(line);
    std::string speed, name, twist_mean;
    std::getline(row, speed, ',');
    std::getline(row, name, ',');
    std::getline(row, twist_mean, ',');
    const auto& coupling = doc["points"][rows / 2]["couplings"][rows % 2];
    CHECK(name == coupling["name"].get<std::string>());
    CHECK(std::stod(twist_mean) ==
          Approx(coupling["twist_rad"]["mean"].get<double>()).epsilon(1e-11));
    ++rows;
  }
  CHECK(rows == 6);
}

TEST_CASE("simulate on a train prints the per-mesh table", "[cli][train]") {
  const auto r = RunCommand(kExe + " simulate --cycles 20 --transient 0 " + kExamples +
                            "/manual_transmission_idle.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("l3-o3") != std::string::npos);
  CHECK(r.out.find("loose gears by impact energy") != std::string::npos);
  CHECK(r.err.empty());  // quiet when piped
}

TEST_CASE("simulate --tier 3 on a train runs the reduced model", "[cli][train][tiers]") {
  const testing::TempDir dir;
  const auto r = RunCommand(kExe + " simulate --json --tier 3 --cycles 20 --transient 5 --out " +
                            (dir.path() / "out").string() + " " + kExamples +
                            "/two_stage_helical_reducer.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["tier"] == "tier 3");
  // Tier 3 keeps 6 DOF at each of the 4 gears: more than tier 1's 3 bodies (state 2n + 2).
  CHECK(doc["state_dim"].get<int>() > 2 * 3 + 2);
  REQUIRE(doc["meshes"].size() == 2);
  for (const auto& m : doc["meshes"]) CHECK(m["te"]["rms"].get<double>() > 0.0);
  // Every bearing's force on the housing: exact mean within its exact extrema, a line per mesh
  // harmonic 1..3 when there is a spectrum window (none in 20 cycles), and the reducer's helical
  // meshes load the bearings axially.
  REQUIRE(doc["bearings"].size() >= 4);
  const size_t lines = doc["sideband_window_common_periods"].get<long>() > 0 ? 6 : 0;
  double axial = 0.0;
  for (const auto& b : doc["bearings"]) {
    INFO(b["name"]);
    for (const char* d : {"x", "y", "z"}) {
      CHECK(b["force_min_n"][d].get<double>() <= b["force_mean_n"][d].get<double>());
      CHECK(b["force_mean_n"][d].get<double>() <= b["force_max_n"][d].get<double>());
      CHECK(b["force_rms_n"][d].get<double>() >= 0.0);
    }
    axial = std::max(axial, std::abs(b["force_mean_n"]["z"].get<double>()));
    CHECK(b["lines"].size() == lines);
  }
  CHECK(axial > 1.0);
  // trajectory.csv carries every bearing's force after the meshes' columns.
  std::ifstream csv(dir.path() / "out" / "trajectory.csv");
  std::string header;
  REQUIRE(std::getline(csv, header));
  for (const auto& b : doc["bearings"]) {
    const std::string name = b["name"].get<std::string>();
    for (const char* column : {".force_x_n", ".force_y_n", ".force_z_n"}) {
      CHECK(header.find(name + column) != std::string::npos);
    }
  }
  std::string row;
  REQUIRE(std::getline(csv, row));
  CHECK(std::count(row.begin(), row.end(), ',') == std::count(header.begin(), header.end(), ','));
}

TEST_CASE("simulate --uff on a train at tier 3 writes every bearing's force history and spectrum",
          "[cli][train][tiers]") {
  // The base train with tooth counts of a short common period (23:46 and 20:40: one input
  // revolution), so 50 cycles hold a spectrum window.
  std::string yaml = testing::ReplaceFirst(testing::kThreeShaftTrainYaml,
                                           "g2: {shaft: b, teeth: 41", "g2: {shaft: b, teeth: 46");
  yaml = testing::ReplaceFirst(yaml, "g3: {shaft: b, teeth: 19", "g3: {shaft: b, teeth: 20");
  yaml = testing::ReplaceFirst(yaml, "g4: {shaft: c, teeth: 37", "g4: {shaft: c, teeth: 40");
  const testing::TempDir dir;
  const std::string uff = (dir.path() / "run.uff").string();
  const auto r = RunCommand(kExe + " simulate --json --tier 3 --uff " + uff + " " +
                            dir.Write("short.yaml", yaml).string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  REQUIRE(doc["sideband_window_common_periods"].get<long>() > 0);
  const size_t bearings = doc["bearings"].size();
  REQUIRE(bearings == 3);  // a default support per rigid shaft
  std::ifstream in(uff);
  std::string line;
  size_t histories = 0, spectra = 0;
  while (std::getline(in, line)) {
    if (line.rfind("bearing force ", 0) != 0) continue;
    (line.find("amplitude spectrum") != std::string::npos ? spectra : histories) += 1;
  }
  CHECK(histories == 3 * bearings);
  CHECK(spectra == 3 * bearings);
}

TEST_CASE("simulate on a train at tier 1 has no bearing forces", "[cli][train][tiers]") {
  const auto r = RunCommand(kExe + " simulate --json --cycles 20 --transient 5 " + kExamples +
                            "/two_stage_helical_reducer.yaml");
  REQUIRE(r.exit_code == 0);
  CHECK(nlohmann::json::parse(r.out)["bearings"].empty());
}

TEST_CASE("simulate on a train refuses a bad tier and a tier the train does not have",
          "[cli][train][tiers]") {
  const auto bad =
      RunCommand(kExe + " simulate --tier 7 " + kExamples + "/two_stage_helical_reducer.yaml");
  CHECK(bad.exit_code == 2);  // a command-line option: usage error
  CHECK(bad.err.find("--tier") != std::string::npos);
  // The manual transmission has no elastic shaft: no Craig-Bampton modes for tier 4.
  const auto missing = RunCommand(kExe + " simulate --tier 4 --cycles 1 --transient 0 " +
                                  kExamples + "/manual_transmission_idle.yaml");
  CHECK(missing.exit_code != 0);
  CHECK(missing.err.find("--tier") != std::string::npos);
  CHECK(missing.err.find("elastic shaft") != std::string::npos);
}

TEST_CASE("simulate on a train: per-mesh TE spectrum lines over whole common periods",
          "[cli][train][sidebands]") {
  // The two-stage reducer: common period 1349 cycles of g1-g2 (= 437 of g3-g4), no engine order.
  const std::string file = kExamples + "/two_stage_helical_reducer.yaml";
  const auto r = RunCommand(kExe + " simulate --json --cycles 1349 --transient 100 " + file);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["sideband_window_common_periods"] == 1);
  CHECK(doc["meshes"][0]["sideband_window_cycles"] == 1349);
  CHECK(doc["meshes"][1]["sideband_window_cycles"] == 437);
  CHECK(doc["sidebands_notes"][0].get<std::string>().find(
            "no runout, pitch error or engine order") != std::string::npos);
  for (const auto& m : doc["meshes"]) {
    // Without runout, pitch errors or engine orders only the mesh's harmonics are considered.
    REQUIRE(!m["sidebands"].empty());
    const double fm = 1.0 / m["mesh_period_s"].get<double>();
    for (const auto& row : m["sidebands"]) {
      const std::string label = row["label"];
      INFO(label);
      REQUIRE(label.size() == 4);  // "k fm"
      CHECK(label.substr(1) == " fm");
      CHECK(row["frequency_hz"].get<double>() == Approx((label[0] - '0') * fm).epsilon(1e-12));
      // Parseval: a line of amplitude A carries A^2/2 of the variance, so A <= sqrt(2) RMS (the
      // same steady periodic state, in permanent contact; 1e-6 for the sampled RMS's window).
      CHECK(row["amplitude_m"].get<double>() <=
            std::sqrt(2.0) * m["te"]["rms"].get<double>() * (1 + 1e-6));
      CHECK(row["db_re_1um"].get<double>() ==
            Approx(20.0 * std::log10(row["amplitude_m"].get<double>() / 1e-6)).epsilon(1e-12));
    }
    CHECK(m["sidebands"][0]["label"] == "1 fm");
  }
  // A record shorter than one common period: no spectrum, and the note says what is needed.
  const auto short_run = RunCommand(kExe + " simulate --json --cycles 200 --transient 10 " + file);
  REQUIRE(short_run.exit_code == 0);
  const auto short_doc = nlohmann::json::parse(short_run.out);
  CHECK(short_doc["sideband_window_common_periods"] == 0);
  CHECK(short_doc["meshes"][0]["sidebands"].empty());
  CHECK(short_doc["sidebands_notes"][0].get<std::string>().find("1349 cycles") !=
        std::string::npos);
}

TEST_CASE("simulate on a train: a gear's runout shows as its shaft's order and sidebands",
          "[cli][train][sidebands][errors]") {
  // The reducer with 5 um runout on g2 (71 teeth, the intermediate shaft at 1480 * 19/71 rpm =
  // 6.60 Hz): 1349 cycles of g1-g2 are 19 intermediate revolutions, so the common period is
  // unchanged and the line sits on a bin. Far below the train's modes the TE follows the runout
  // one for one (quasi-static, (f/f_n)^2 < 1e-3), so the line is the runout's amplitude.
  std::string yaml = testing::ReadWholeFile(kExamples + "/two_stage_helical_reducer.yaml");
  const std::string g2 = "material: steel, helix_angle: 15 deg, hand: left}";
  const size_t at = yaml.find(g2);
  REQUIRE(at != std::string::npos);
  yaml.replace(at, g2.size(),
               "material: steel, helix_angle: 15 deg, hand: left,\n"
               "     runout: {amplitude: 5 um, phase: 20 deg}}");
  const testing::TempDir dir;
  const auto file = dir.Write("runout.yaml", yaml);
  const auto r =
      RunCommand(kExe + " simulate --json --cycles 1349 --transient 100 " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["sideband_window_common_periods"] == 1);
  for (const auto& w : doc["warnings"])
    CHECK(w.get<std::string>().find("runout") == std::string::npos);
  const double shaft_hz = 1480.0 / 60.0 * 19.0 / 71.0;
  const double fm = 1.0 / doc["meshes"][0]["mesh_period_s"].get<double>();
  bool line = false, sideband = false;
  for (const auto& row : doc["meshes"][0]["sidebands"]) {
    const std::string label = row["label"];
    if (label == "1 f_intermediate") {
      line = true;
      CHECK(row["frequency_hz"].get<double>() == Approx(shaft_hz).epsilon(1e-12));
      // 1 % for the quasi-static residue and the segment mean's sinc (< 1e-3 together).
      CHECK(row["amplitude_m"].get<double>() == Approx(5e-6).epsilon(1e-2));
    }
    if (label == "1 fm - 1 f_intermediate" || label == "1 fm + 1 f_intermediate") {
      sideband = true;
      const double sign = label[5] == '-' ? -1.0 : 1.0;
      CHECK(row["frequency_hz"].get<double>() == Approx(fm + sign * shaft_hz).epsilon(1e-12));
    }
  }
  CHECK(line);
  CHECK(sideband);
  // The text lists each mesh's harmonics on one line, as for a pair: the shaft-order lines and
  // sidebands (down to the rounding floor) are in --json only.
  const auto text = RunCommand(kExe + " simulate --cycles 1349 --transient 100 " + file.string());
  INFO(text.out);
  REQUIRE(text.exit_code == 0);
  const size_t listing = text.out.find("TE mesh harmonics per mesh over 1 common period");
  REQUIRE(listing != std::string::npos);
  std::istringstream lines(text.out.substr(text.out.find('\n', listing) + 1));
  std::string mesh_line;
  int meshes = 0;
  while (std::getline(lines, mesh_line) && mesh_line.rfind("    ", 0) == 0) {
    INFO(mesh_line);
    ++meshes;
    CHECK(mesh_line.find(" 1 fm: ") != std::string::npos);
    CHECK(mesh_line.find("f_intermediate") == std::string::npos);
    CHECK(mesh_line.find("dB") == std::string::npos);
  }
  CHECK(meshes == 2);
}

TEST_CASE("simulate on a train: the engine order shows in the headset mesh's spectrum",
          "[cli][train][sidebands]") {
  // Order 2 of the input at 800 rpm: 26.67 Hz, on a bin over whole common periods (105 cycles).
  const auto r = RunCommand(kExe + " simulate --json --cycles 210 --transient 50 " + kExamples +
                            "/manual_transmission_idle.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["sideband_window_common_periods"] == 2);
  bool found = false;
  for (const auto& row : doc["meshes"][0]["sidebands"]) {
    if (row["label"] == "2 fin") {
      found = true;
      CHECK(row["frequency_hz"].get<double>() == Approx(2.0 * 800.0 / 60.0).epsilon(1e-12));
    }
  }
  CHECK(found);
}

TEST_CASE("simulate --lyapunov on a train reports the largest exponents", "[cli][train]") {
  const auto r = RunCommand(kExe + " simulate --json --cycles 40 --transient 10 --lyapunov 3 " +
                            kExamples + "/manual_transmission_idle.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  const auto& l = doc["lyapunov"];
  CHECK(l["status"] == "success");
  REQUIRE(l["exponents_per_s"].size() == 3);
  REQUIRE(l["standard_errors_per_s"].size() == 3);
  // Largest first; per forcing cycle = per second * the forcing period (the first engine order of
  // the input, 800 rpm, order 2: 37.5 ms). Tolerance: rounding of one product.
  CHECK(l["forcing_period_s"].get<double>() == Approx(60.0 / (800.0 * 2.0)).epsilon(1e-12));
  for (size_t j = 0; j < 3; ++j) {
    const double lambda = l["exponents_per_s"][j].get<double>();
    if (j > 0) CHECK(lambda <= l["exponents_per_s"][j - 1].get<double>());
    CHECK(l["per_forcing_cycle"][j].get<double>() ==
          Approx(lambda * l["forcing_period_s"].get<double>()).epsilon(1e-12));
  }
  // The idling transmission rattles: impacts on every mesh, each a saltation of the tangents.
  CHECK(l["saltations"].get<long>() > 100);
}

TEST_CASE("simulate --lyapunov refuses more exponents than the train has and a single pair",
          "[cli][train]") {
  const auto many = RunCommand(kExe + " simulate --cycles 40 --lyapunov 13 " + kExamples +
                               "/manual_transmission_idle.yaml");
  CHECK(many.exit_code != 0);
  CHECK(many.err.find("--lyapunov") != std::string::npos);
  CHECK(many.err.find("2n - 2 = 12") != std::string::npos);
  const auto pair =
      RunCommand(kExe + " simulate --cycles 40 --lyapunov 1 " + kExamples + "/idle_rattle.yaml");
  CHECK(pair.exit_code != 0);
  CHECK(pair.err.find("--lyapunov") != std::string::npos);
  CHECK(pair.err.find("gear trains") != std::string::npos);
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("simulate on a train refuses a run above the memory limit and reports its estimate",
          "[cli][simulate][train][memory]") {
  // 1400 cycles of g1-g2 hold one common period (1349 cycles): the TE of both meshes is kept.
  const std::string run =
      " simulate --cycles 1400 --transient 0 " + kExamples + "/two_stage_helical_reducer.yaml";
  const auto probe = RunCommand(kExe + run + " --json");
  REQUIRE(probe.exit_code == 0);
  const auto doc = nlohmann::json::parse(probe.out);
  const auto estimate = doc["memory_estimate"]["bytes"].get<size_t>();
  const auto te = doc["memory_estimate"]["parts"]["TE samples"].get<size_t>();
  // The kept TE samples: one common period of both meshes at 32 samples per cycle of the fastest.
  CHECK(te > 0);
  CHECK(te % (2 * sizeof(double)) == 0);
  CHECK(estimate >= te);
  const auto refused =
      RunCommand("GEARNVH_MEMORY_LIMIT=" + std::to_string(estimate - 1) + " " + kExe + run);
  INFO(refused.err);
  CHECK(refused.exit_code == 2);
  CHECK(refused.err.find("--cycles: the run would hold about ") != std::string::npos);
  CHECK(refused.err.find("got 1400") != std::string::npos);
  CHECK(refused.out.empty());
  // At the limit: a warning before the run (above half the limit), in the JSON's warnings, and
  // shown once in the text.
  const std::string at_limit = "GEARNVH_MEMORY_LIMIT=" + std::to_string(estimate) + " " + kExe;
  const auto json = RunCommand(at_limit + run + " --json");
  REQUIRE(json.exit_code == 0);
  CHECK(json.err.find("warning: --cycles 1400: the run will hold about ") != std::string::npos);
  CHECK(nlohmann::json::parse(json.out)["warnings"].dump().find("the run will hold about") !=
        std::string::npos);
  const auto text = RunCommand(at_limit + run);
  REQUIRE(text.exit_code == 0);
  const std::string shown = text.err + text.out;
  INFO(shown);
  const size_t first = shown.find("the run will hold about");
  REQUIRE(first != std::string::npos);
  CHECK(shown.find("the run will hold about", first + 1) == std::string::npos);
}

TEST_CASE("simulate on a train stopped out of range says the cycles it ran, and no window",
          "[cli][train]") {
  // Tier 2 of this train grows without bound and stops after ~258 of the 600 cycles asked for.
  const auto r = RunCommand(kExe + " simulate --tier 2 --cycles 500 --transient 100 " +
                            testing::kStrongRattleTrain);
  INFO(r.out + r.err);
  CHECK(r.exit_code == 1);
  CHECK(r.out.find("out of range") != std::string::npos);
  CHECK(r.out.find("(100 + 500 cycles") == std::string::npos);
  CHECK(r.out.find("of the 100 + 500 cycles of pinion-wheel asked for: stopped") !=
        std::string::npos);
  CHECK(r.out.find("TE mesh harmonics per mesh over") == std::string::npos);  // no window
  CHECK(r.out.find("no spectrum: the run stopped") != std::string::npos);
  const auto json = RunCommand(kExe + " simulate --json --tier 2 --cycles 500 --transient 100 " +
                               testing::kStrongRattleTrain);
  const auto doc = nlohmann::json::parse(json.out);
  CHECK(doc["summary"]["status"] == "out of range");
  CHECK(doc["sideband_window_common_periods"] == 0);
}

}  // namespace
}  // namespace gearnvh
