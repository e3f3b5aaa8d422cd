// Train outputs in the units the file wrote (as the pair: text in them, JSON keys in fixed units),
// and the warning before a very slow run (analysis/include/gearnvh/analysis/run_cost.h,
// CheckRunCost).
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>

#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_tables.h"
#include "model/test_trains.h"
#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::RunCommand;
using testing::TempDir;

using testing::kExamples;
using testing::kExe;

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The reducer example with its speed and load rewritten in other units.
std::string ReducerIn(const std::string& speed, const std::string& load) {
  std::string text = ReadFile(kExamples + "/two_stage_helical_reducer.yaml");
  const std::string old_speed = "value: 1480 rpm", old_load = "torque: 900 N*m";
  REQUIRE(text.find(old_speed) != std::string::npos);
  REQUIRE(text.find(old_load) != std::string::npos);
  text.replace(text.find(old_speed), old_speed.size(), "value: " + speed);
  text.replace(text.find(old_load), old_load.size(), "torque: " + load);
  return text;
}

TEST_CASE("simulate on a train prints speed and loads in the units the file wrote",
          "[cli][train][units]") {
  const TempDir dir;
  // 1480 rpm = 24.67 rev/s; 900 N m = 0.9 kN m.
  const auto file = dir.Write("reducer.yaml", ReducerIn("24.6667 rev/s", "0.9 kN*m"));
  const auto r = RunCommand(kExe + " simulate --cycles 4 --transient 0 " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  INFO(r.out);
  CHECK(r.out.find("input shaft input at 24.67 rev/s") != std::string::npos);
  CHECK(r.out.find("loads 0.9 kN m on output") != std::string::npos);
  CHECK(r.out.find("rpm") == std::string::npos);
  // The example as written: rpm and N m.
  const auto as_written = RunCommand(kExe + " simulate --cycles 4 --transient 0 " + kExamples +
                                     "/two_stage_helical_reducer.yaml");
  REQUIRE(as_written.exit_code == 0);
  CHECK(as_written.out.find("input shaft input at 1480 rpm, loads 900 N m on output") !=
        std::string::npos);
  // JSON keeps its keys in fixed units, whatever the file wrote (as the pair's).
  const auto json = RunCommand(kExe + " simulate --json --cycles 4 --transient 0 " + file.string());
  REQUIRE(json.exit_code == 0);
  const auto doc = nlohmann::json::parse(json.out);
  CHECK(doc["input_speed"]["rpm"].get<double>() == Approx(1480.0).epsilon(1e-5));
}

TEST_CASE("sweep on a train prints its speeds in the unit the file wrote", "[cli][train][units]") {
  const TempDir dir;
  std::string text = ReducerIn("155 rad/s", "900 N*m");
  text += "  speed_sweep: {from: 100 rad/s, to: 150 rad/s, points: 2}\n";
  const auto file = dir.Write("reducer.yaml", text);
  const auto r = RunCommand(kExe + " sweep --cycles 4 --transient 0 " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  INFO(r.out);
  CHECK(r.out.find("rad/s") != std::string::npos);
  CHECK(r.out.find("     100") != std::string::npos);  // the rows: 100 and 150 rad/s
  CHECK(r.out.find("     150") != std::string::npos);
  CHECK(r.out.find("rpm") == std::string::npos);
}

TEST_CASE("a train with a tiny loose gear is warned about before its slow run",
          "[train][warnings]") {
  // The rattler (test_trains.h) with the loose gear g4 at 1e-9 kg m^2: against the much heavier
  // layshaft (1e-3 kg m^2) its mode is sqrt(k r_b^2 / J) to 1e-6 (the heavy side barely moves),
  // k the mesh's drive stiffness in segment 0 (the estimate's tuple: every mesh in drive at t = 0)
  // and r_b = |v| on the gear's coordinate.
  TrainSpec spec = testing::RattlerTrain(1500.0);
  const TrainTables normal = BuildTrainTables(spec, BuildGearTrain(spec));
  CHECK(gearnvh::CheckRunCost(gearnvh::EstimateRunCost(normal, 0.1), false).empty());
  spec.gears[3].gear.inertia = 1e-9;
  const TrainTables tiny = BuildTrainTables(spec, BuildGearTrain(spec));
  const int loose = 2;  // bodies: input, layshaft, g4
  REQUIRE(tiny.loose[loose]);
  REQUIRE(tiny.inertia[loose] == 1e-9);
  const TrainMeshTable& mt = tiny.meshes[1];
  const double k = mt.k_drive[0];
  const double hz = std::sqrt(k * mt.v[loose] * mt.v[loose] / 1e-9) / (2.0 * std::numbers::pi);
  // 0.1 s: ~2e6 sub-steps of ~50 ns at m = 8, about 0.4 s by the estimate: no warning. 100 s:
  // about 400 s, a warning (above 60 s) and no refusal (below an hour).
  CHECK(gearnvh::CheckRunCost(gearnvh::EstimateRunCost(tiny, 0.1), false).empty());
  const gearnvh::RunCostEstimate cost = gearnvh::EstimateRunCost(tiny, 100.0);
  CHECK(cost.wall_s ==
        Approx(cost.substeps * gearnvh::kSubstepSecondsPerState2 * tiny.m * tiny.m).epsilon(1e-12));
  CHECK(cost.substeps == Approx(100.0 / cost.substep_s).epsilon(1e-12));
  CHECK(cost.dominant == gearnvh::RateTerm::kStiffness);
  const std::string w = gearnvh::CheckRunCost(cost, false);
  INFO(w << "\nexpected " << hz << " Hz");
  REQUIRE(!w.empty());
  CHECK(w.find(fmt::format("{:.4g} Hz", hz)) != std::string::npos);
  CHECK(w.find("body g4, inertia 1e-09 kg m²") != std::string::npos);
  CHECK(w.find("sub-steps of at most") != std::string::npos);
  CHECK(w.find("for the 100 s simulated") != std::string::npos);

  // A run estimated above a minute says it before it starts, and keeps it in its warnings (JSON
  // `warnings`): 10 cycles of the first mesh with g4 at 1e-15 kg m^2 (~1e10 rad/s: ~4e8 sub-steps,
  // ~80 s by the estimate). The run is cancelled when the warning is said, so before its first
  // step (it would take that long); a flag set earlier would stop the table build before it.
  spec.gears[3].gear.inertia = 1e-15;
  gearnvh::TrainRunOptions run;
  run.cycles = 10;
  run.transient = 0;
  run.spectra = false;
  std::atomic<bool> cancelled{false};
  run.cancel = &cancelled;
  std::vector<std::string> said;
  run.before_run_warning = [&](const std::string& text) {
    said.push_back(text);
    cancelled.store(true);
  };
  CHECK_THROWS_AS(gearnvh::RunTrainOperatingPoint(spec, run), RunCancelled);
  REQUIRE(said.size() == 1);
  CHECK(said[0].find("the run would take about") != std::string::npos);
  CHECK(said[0].find("body g4, inertia 1e-15 kg m²") != std::string::npos);
}

TEST_CASE("the slow-run estimate's sub-step follows the solver's bound with tooth friction",
          "[train][warnings]") {
  // The tiny loose gear g4 (1e-9 kg m^2) of the test above dominates every bound: on its
  // coordinate alone (the others are >= 1e-3 kg m^2, so they move the results by ~1e-6) the
  // frictionless bound is omega = sqrt(k v^2 / J) (damping's c v^2 / J = 2 zeta omega is smaller)
  // and with friction rho = sqrt(omega^2 + k n) + c v^2 / J + c n, n = |u_0 - v| |v| / J the
  // solver's friction term (docs/gear-trains.md, "Events"), k and u_0 of segment 0 (the estimate's
  // tuple: every mesh in drive at t = 0). Tolerance 1e-4: the heavy bodies.
  TrainSpec spec = testing::RattlerTrain(1500.0);
  spec.gears[3].gear.inertia = 1e-9;
  const TrainTables plain = BuildTrainTables(spec, BuildGearTrain(spec));
  spec.meshes[1].mesh.friction_coefficient = 0.1;
  const TrainTables rubbing = BuildTrainTables(spec, BuildGearTrain(spec));
  const int loose = 2;  // bodies: input, layshaft, g4
  const TrainMeshTable& mt = rubbing.meshes[1];
  REQUIRE(mt.has_friction());
  REQUIRE(!plain.meshes[1].has_friction());
  const double k = mt.k_drive[0];
  const double J = 1e-9, v = std::abs(mt.v[loose]);
  const double slide = std::abs(mt.ForceVector(0, true)[loose] - mt.v[loose]);
  REQUIRE(slide > 0.0);
  const double omega = std::sqrt(k * v * v / J);
  const double n = slide * v / J;
  const double rho = std::sqrt(omega * omega + k * n) + mt.damping * (v * v / J + n);

  const gearnvh::RunCostEstimate without = gearnvh::EstimateRunCost(plain, 0.1);
  const gearnvh::RunCostEstimate with = gearnvh::EstimateRunCost(rubbing, 0.1);
  CHECK(without.substep_s == Approx(0.5 / omega).epsilon(1e-4));
  CHECK(with.substep_s == Approx(0.5 / rho).epsilon(1e-4));
  CHECK(with.substep_s < without.substep_s);
  // The mode (and so the body named) is the frictionless one either way.
  CHECK(with.mode_hz == Approx(without.mode_hz).epsilon(1e-12));
  CHECK(with.body == loose);
  CHECK(with.substeps == Approx(0.1 / with.substep_s).epsilon(1e-12));
  const std::string w = gearnvh::RunCostText(with, "the run");
  CHECK(w.find(fmt::format("({:.3g} dense sub-steps", 0.1 / with.substep_s)) != std::string::npos);
}

}  // namespace
}  // namespace gearnvh
