// The speed sweep of a gear train (analysis/include/gearnvh/analysis/train_sweep.h): a train
// decoupled by a massive layshaft sweeps as its two stages swept alone; the rattle ranking of a
// loose gear under drag; the manual transmission's operating point and sweep at the report's
// settings run to their end.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>

#include "config/gearbox_loader.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/input_error.h"
#include "model/test_specs.h"
#include "model/test_trains.h"
#include "train_sweep_command.h"

namespace gearnvh {
namespace {

using testing::kRpm;  // rad/s per rpm

// Input (g1, 20) -> layshaft (g2, 40; g3, 40) -> output (g4, 80), 150 N m on the output, swept
// over 500-900 rpm of the input. Both meshes have the same frequency (20 x the input speed), so
// the train's samples and its stages' fall at the same instants. `which`: 0 the train, 1 the first
// stage alone (input -> layshaft carrying the output's power, 75 N m at twice the output speed),
// 2 the second alone (the layshaft as the input at half the input speed).
TrainSpec Stage(int which, double layshaft_inertia) {
  TrainSpec t;
  t.name = "massive layshaft";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {testing::RigidShaft("input", 2e-3), testing::RigidShaft("layshaft", layshaft_inertia),
              testing::RigidShaft("output", 5e-3)};
  t.gears = {testing::TrainGearOf("g1", "input", 20), testing::TrainGearOf("g2", "layshaft", 40),
             testing::TrainGearOf("g3", "layshaft", 40), testing::TrainGearOf("g4", "output", 80)};
  t.meshes = {testing::TrainMeshOf("g1", "g2"), testing::TrainMeshOf("g3", "g4")};
  t.operating.input_shaft = "input";
  t.operating.speed = 700.0 * kRpm;
  t.operating.loads = {{"output", 150.0}};
  t.analysis.segments_per_cycle = 16;
  t.analysis.speed_sweep = {500.0 * kRpm, 900.0 * kRpm, 3};
  if (which == 1) {
    t.shafts.pop_back();
    t.gears.resize(2);
    t.meshes.pop_back();
    t.operating.loads = {{"layshaft", 75.0}};
  } else if (which == 2) {
    t.shafts.erase(t.shafts.begin());
    t.gears.erase(t.gears.begin(), t.gears.begin() + 2);
    t.meshes.erase(t.meshes.begin());
    t.operating.input_shaft = "layshaft";
    t.operating.speed *= 0.5;
    t.analysis.speed_sweep = {250.0 * kRpm, 450.0 * kRpm, 3};
  }
  return t;
}

TEST_CASE("train sweep: a massive layshaft's two stages sweep as two one-mesh trains",
          "[app][train][sweep]") {
  // What couples the stages is the layshaft's motion under the other stage's mesh-frequency force
  // fluctuation dT: r_b dT / (J_lay w_m^2) ~ 0.04 m * 10 N m / (1e8 kg m^2 * (2 pi 167 Hz)^2)
  // ~ 4e-15 m. Same sample instants (equal mesh periods, the same transient and record), so the
  // sampled statistics agree to that: 1e-11 m on TE, 1e-9 relative on forces, far below what a
  // wrong speed, load or period per point would make (the TE RMS here is ~1e-7 m).
  const double j_lay = 1e8;
  gearnvh::TrainSweepOptions options;
  options.cycles = 64;
  options.transient = 32;
  options.threads = 1;
  const gearnvh::TrainSweepResult full = gearnvh::RunTrainSweep(Stage(0, j_lay), options);
  const gearnvh::TrainSweepResult first = gearnvh::RunTrainSweep(Stage(1, j_lay), options);
  const gearnvh::TrainSweepResult second = gearnvh::RunTrainSweep(Stage(2, j_lay), options);
  REQUIRE(full.points.size() == 3);
  REQUIRE(full.mesh_names == std::vector<std::string>{"g1-g2", "g3-g4"});
  CHECK(full.loose_gear_names.empty());
  for (size_t s = 0; s < 3; ++s) {
    const gearnvh::TrainSweepPoint& p = full.points[s];
    REQUIRE(p.ok);
    REQUIRE(first.points[s].ok);
    REQUIRE(second.points[s].ok);
    CHECK(p.speed_rpm == Approx(500.0 + 200.0 * static_cast<double>(s)).epsilon(1e-12));
    const TrainMeshStatistics* alone[2] = {&first.points[s].meshes[0], &second.points[s].meshes[0]};
    for (size_t i = 0; i < 2; ++i) {
      const TrainMeshStatistics& m = p.meshes[i];
      INFO("speed " << p.speed_rpm << " rpm, mesh " << m.name);
      CHECK(m.te_rms > 1e-9);  // a real fluctuation to compare
      CHECK(m.te_mean == Approx(alone[i]->te_mean).margin(1e-11));
      CHECK(m.te_rms == Approx(alone[i]->te_rms).margin(1e-11));
      CHECK(m.te_peak_to_peak == Approx(alone[i]->te_peak_to_peak).margin(1e-11));
      CHECK(m.force_mean == Approx(alone[i]->force_mean).epsilon(1e-9));
      CHECK(m.force_max == Approx(alone[i]->force_max).epsilon(1e-9));
      // The exact events agree too (the first stage touches its back flank near 900 rpm).
      CHECK(m.drive_impacts == alone[i]->drive_impacts);
      CHECK(m.back_impacts == alone[i]->back_impacts);
      CHECK(m.separations == alone[i]->separations);
      CHECK(m.free_time_fraction == Approx(alone[i]->free_time_fraction).margin(1e-9));
    }
    // The mean mesh force is the transmitted torque over the base radius (a periodic state has no
    // mean acceleration): 150 N m on g4's base radius (80 teeth, 2 mm, 20 deg), the same force on
    // g2 (75 N m on half the radius). 1 %: the mean is sampled (32 samples per cycle land on the
    // segment boundaries where the stiffness jumps; measured 0.4 %).
    const double force = 150.0 / (0.5 * 80 * 2e-3 * std::cos(20.0 * std::numbers::pi / 180.0));
    CHECK(p.meshes[0].force_mean == Approx(force).epsilon(0.01));
    CHECK(p.meshes[1].force_mean == Approx(force).epsilon(0.01));
  }
}

TEST_CASE("train sweep: a loose gear under drag rattles under engine excitation, ranked",
          "[app][train][sweep]") {
  // Input (g1, 20) -> layshaft (g2, 30; g3, 25) -> loose g4 (25) idling on the input shaft, a small
  // drag on g4 and the engine's second order on the input: the loose gear separates and hits.
  TrainSpec t;
  t.name = "rattler";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {testing::RigidShaft("input", 2e-3), testing::RigidShaft("layshaft", 1e-3)};
  t.gears = {testing::TrainGearOf("g1", "input", 20), testing::TrainGearOf("g2", "layshaft", 30),
             testing::TrainGearOf("g3", "layshaft", 25),
             testing::TrainGearOf("g4", "input", 25, Mounting::kLoose)};
  t.meshes = {testing::TrainMeshOf("g1", "g2"), testing::TrainMeshOf("g3", "g4")};
  t.operating.input_shaft = "input";
  t.operating.speed = 800.0 * kRpm;
  t.operating.loads = {{"layshaft", 20.0}, {"g4", 0.05}};
  t.operating.excitation = {{2.0, 1500.0, 0.0}};
  t.analysis.segments_per_cycle = 16;
  t.analysis.speed_sweep = {700.0 * kRpm, 900.0 * kRpm, 2};
  gearnvh::TrainSweepOptions options;
  options.cycles = 100;
  options.transient = 50;
  const gearnvh::TrainSweepResult r = gearnvh::RunTrainSweep(t, options);
  REQUIRE(r.loose_gear_names == std::vector<std::string>{"g4"});
  for (const gearnvh::TrainSweepPoint& p : r.points) {
    REQUIRE(p.ok);
    REQUIRE(p.loose_gears.size() == 1);
    CHECK(p.loose_gears[0].rank == 1);
    CHECK(p.loose_gears[0].rattle_index > 0.0);
    // The loose gear's mesh impacts, the loaded mesh stays in contact.
    CHECK(p.ImpactsPerCycle(1) > 0.0);
    CHECK(p.loose_gears[0].impacts == p.meshes[1].drive_impacts + p.meshes[1].back_impacts);
    CHECK(p.meshes[1].free_time_fraction > 0.0);
  }
  // The JSON and CSV hold every point and mesh.
  const nlohmann::json doc = app::TrainSweepJson(r);
  CHECK(doc["points"].size() == 2);
  CHECK(doc["points"][0]["meshes"].size() == 2);
  CHECK(doc["failed_speeds"] == 0);
  const std::string csv = app::TrainMeshesCsv(r);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 2 * 2);
}

TEST_CASE("train sweep: a viscous drag's tooth load is checked at every speed",
          "[app][train][sweep]") {
  // g4's needle-bearing drag c |dW| relative to the input grows with speed (dW = W_in / 3): within
  // the tooth-load limit at the file's 200 rpm, above it at 800 rpm, where that speed fails with
  // the rule at the drag's path (the run would leave the linear-elastic tooth model).
  TrainSpec t = testing::RattlerTrain(0.0);
  t.operating.speed = 200.0 * kRpm;
  t.operating.loads[1].viscous = 1000.0;
  t.operating.loads[1].relative_to = "input";
  REQUIRE_NOTHROW(ValidateTrainSpec(t));
  TrainSpec fast = t;
  fast.operating.speed = 800.0 * kRpm;
  REQUIRE_THROWS_AS(ValidateTrainSpec(fast), InputError);
  t.analysis.speed_sweep = {200.0 * kRpm, 800.0 * kRpm, 2};
  // A few cycles: the rule is checked before a speed runs (the drag's contact chatter made 25
  // cycles take 19 s in Release and 144 s under the sanitizers).
  gearnvh::TrainSweepOptions options;
  options.cycles = 3;
  options.transient = 1;
  const gearnvh::TrainSweepResult r = gearnvh::RunTrainSweep(t, options);
  REQUIRE(r.points.size() == 2);
  INFO(r.points[0].message << " | " << r.points[1].message);
  CHECK(r.points[0].ok);
  CHECK(r.points[1].message.find("operating.loads[1].viscous") != std::string::npos);
  CHECK_FALSE(r.points[1].ok);
  CHECK(r.points[0].message.find("tooth load") == std::string::npos);
}

TEST_CASE("train report runs: the manual transmission's operating point and sweep reach their end",
          "[app][train]") {
  // What `report` runs on the manual transmission shortened as the report test does (210 + 50
  // cycles, 700-1300 rpm at 3 speeds; the sweep at the report's 256 + 100 cycles). A merge once
  // made this report stop with "more than 1000 events in a grid segment" while simulate ran; a run
  // that stops now fails here with the stepper's own message (where, and on which mesh).
  std::ifstream in(std::string(GEARNVH_EXAMPLES_DIR) + "/manual_transmission_idle.yaml");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const config::LoadedGearbox loaded = config::LoadAnyGearboxFromString(text);
  REQUIRE(loaded.schema == 2);
  TrainSpec spec = loaded.train;
  gearnvh::TrainRunOptions run;
  run.cycles = 210;
  run.transient = 50;
  const gearnvh::TrainOperatingPoint op = gearnvh::RunTrainOperatingPoint(spec, run);
  INFO(TrainStepperMessage(op.summary));
  REQUIRE(op.ok());
  CHECK(TrainStepperMessage(op.summary).empty());
  CHECK(op.summary.events > 0);  // the loose gears rattle at idle
  spec.analysis.speed_sweep = {700.0 * kRpm, 1300.0 * kRpm, 3};
  gearnvh::TrainSweepOptions options;
  options.cycles = 256;
  options.transient = 100;
  const gearnvh::TrainSweepResult sweep = gearnvh::RunTrainSweep(spec, options);
  REQUIRE(sweep.points.size() == 3);
  for (const gearnvh::TrainSweepPoint& p : sweep.points) {
    INFO(p.speed_rpm << " rpm: " << p.message);
    CHECK(p.ok);
  }
}

TEST_CASE("a train sweep's speed crosses between MPI ranks whole: its JSON round-trips bit for bit",
          "[train][sweep][mpi]") {
  // Every field the outputs read, with numbers that are not short decimals (the JSON must carry
  // all 17 digits) and integers past 2^31.
  TrainSweepPoint p;
  p.speed_rad_s = 100.0 / 3.0;
  p.speed_rpm = p.speed_rad_s * 60.0 / (2.0 * std::numbers::pi);
  p.ok = true;
  p.message = "a \"quoted\" note";
  p.real_time_ratio = 12.345678901234567;
  p.recorded_s = 0.1 + 0.2;
  p.mesh_periods = {1.0 / 7.0, 1.0 / 11.0};
  TrainMeshStatistics m;
  m.name = "a-b";
  m.te_mean = 4.1e-5 / 3.0;
  m.te_rms = 1e-7 / 7.0;
  m.te_peak_to_peak = 2e-6 / 9.0;
  m.force_mean = 442.0 / 3.0;
  m.force_max = 1e3 / 7.0;
  m.drive_impacts = 3000000000L;
  m.back_impacts = 7;
  m.separations = 11;
  m.grazing = 2;
  m.free_time_fraction = 1.0 / 3.0;
  m.impact_velocity_max = 0.01 / 3.0;
  m.impact_velocity_rms = 0.004 / 7.0;
  p.meshes = {m, m};
  p.meshes[1].name = "c-d";
  TrainLooseGearStatistics f;
  f.name = "f";
  f.body = 5;
  f.rattle_index = 1234.5 / 7.0;
  f.drive_impacts = 40;
  f.back_impacts = 2;
  f.impacts = 42;
  f.drive_impacts_per_second = 400.0 / 3.0;
  f.back_impacts_per_second = 20.0 / 3.0;
  f.impact_velocity_rms = 0.01 / 3.0;
  f.impact_velocity_max = 0.02 / 7.0;
  f.impact_energy_per_second = 1e-3 / 3.0;
  f.rank = 1;
  p.loose_gears = {f};
  p.waterfall = {{0.0, 1e-6 / 3.0, 5e-300}, {1.0 / 3.0, 0.0, 2.0}};
  p.couplings = {{"clutch_damper",
                  {0.01 / 3.0, 0.002 / 7.0, -1e-3 / 3.0, 0.02 / 3.0},
                  {4.7 / 3.0, 1.0 / 7.0, -0.5 / 3.0, 10.0 / 3.0}}};
  using app::TrainSweepPointFromJson;
  using app::TrainSweepPointJson;
  const TrainSweepPoint back = TrainSweepPointFromJson(
      nlohmann::json::parse(TrainSweepPointJson(p).dump()));  // as the ranks send it: text
  CHECK(TrainSweepPointJson(back) == TrainSweepPointJson(p));
  CHECK(back.speed_rad_s == p.speed_rad_s);
  CHECK(back.speed_rpm == p.speed_rpm);
  CHECK(back.ok);
  CHECK(back.message == p.message);
  CHECK(back.real_time_ratio == p.real_time_ratio);
  CHECK(back.recorded_s == p.recorded_s);
  CHECK(back.mesh_periods == p.mesh_periods);
  REQUIRE(back.meshes.size() == 2);
  CHECK(back.meshes[1].name == "c-d");
  CHECK(back.meshes[0].te_rms == m.te_rms);
  CHECK(back.meshes[0].force_max == m.force_max);
  CHECK(back.meshes[0].drive_impacts == 3000000000L);
  CHECK(back.meshes[0].grazing == 2);
  CHECK(back.meshes[0].free_time_fraction == m.free_time_fraction);
  CHECK(back.meshes[0].impact_velocity_rms == m.impact_velocity_rms);
  REQUIRE(back.couplings.size() == 1);
  CHECK(back.couplings[0].name == "clutch_damper");
  CHECK(back.couplings[0].twist.min == p.couplings[0].twist.min);
  CHECK(back.couplings[0].torque.rms == p.couplings[0].torque.rms);
  CHECK(back.couplings[0].torque.max == p.couplings[0].torque.max);
  REQUIRE(back.loose_gears.size() == 1);
  CHECK(back.loose_gears[0].body == 5);
  CHECK(back.loose_gears[0].rattle_index == p.loose_gears[0].rattle_index);
  CHECK(back.loose_gears[0].rank == 1);
  CHECK(back.loose_gears[0].impacts == 42);
  CHECK(back.loose_gears[0].drive_impacts == 40);
  CHECK(back.loose_gears[0].back_impacts == 2);
  CHECK(back.loose_gears[0].drive_impacts_per_second == f.drive_impacts_per_second);
  CHECK(back.loose_gears[0].back_impacts_per_second == f.back_impacts_per_second);
  CHECK(back.loose_gears[0].impact_velocity_rms == f.impact_velocity_rms);
  CHECK(back.loose_gears[0].impact_velocity_max == f.impact_velocity_max);
  CHECK(back.loose_gears[0].impact_energy_per_second == f.impact_energy_per_second);
  CHECK(back.waterfall == p.waterfall);
  // A failed speed: no statistics, its message.
  TrainSweepPoint failed;
  failed.speed_rad_s = 50.0;
  failed.message = "lost: no rank returned this speed";
  const TrainSweepPoint failed_back = TrainSweepPointFromJson(TrainSweepPointJson(failed));
  CHECK_FALSE(failed_back.ok);
  CHECK(failed_back.message == failed.message);
  CHECK(failed_back.meshes.empty());
}

}  // namespace
}  // namespace gearnvh
