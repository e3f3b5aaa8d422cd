// `gearnvh atlas` and `gearnvh orbits` on a gear train (schema gearnvh/2): a small train whose
// meshes have a constant stiffness (a Fourier stiffness with its mean only), so that in permanent
// contact its tier-1 dynamics is linear and time-invariant and the closed forms are the
// eigenvalues of its generator A: the largest Lyapunov exponent is the slowest decay max Re(lambda)
// and the Floquet multipliers over a period T are exp(lambda T) (free rotation removed).
#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/gearbox_loader.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_tables.h"
#include "support/paths.h"
#include "support/run_command.h"
#include "three_shaft_train_yaml.h"

namespace gearnvh {
namespace {

using testing::ReadWholeFile;
using testing::RunCommand;
using testing::TempDir;

using testing::kExe;
using testing::kExamples;

// The linear train of tests/data (shared with python/tests/test_trains.py: input shaft g1 drives
// the output shaft through g1-g2, loads[0] on the output, engine order 2 on the input) with a loose
// gear: g4 turns loosely on the output shaft, driven by g3 on the input against its drag
// (loads[1]).
std::string SmallTrain(const std::string& drag) {
  std::string yaml =
      ReadWholeFile(std::filesystem::path(GEARNVH_TEST_DATA_DIR) / "linear_train.yaml");
  const auto insert_before = [&yaml](const std::string& line, const std::string& text) {
    const size_t at = yaml.find(line);
    REQUIRE(at != std::string::npos);
    yaml.insert(at, text);
  };
  insert_before("meshes:\n",
                "  g3: {shaft: input, teeth: 30, module: 2 mm, face_width: 12 mm, bore_diameter: "
                "20 mm, material: steel}\n"
                "  g4: {shaft: output, mounting: loose, teeth: 30, module: 2 mm, face_width: 12 mm,"
                "\n       bore_diameter: 20 mm, material: steel}\n");
  insert_before("operating:\n",
                "  - {gears: [g3, g4], backlash: 80 um, damping_ratio: 0.02,\n"
                "     stiffness: {model: fourier, fourier: {mean: 1.5e8 N/m}}}\n");
  insert_before("  excitation:\n", "    - {on: g4, torque: " + drag + "}\n");
  return yaml;
}

// The eigenvalues of the tier-1 generator in drive contact on every mesh on the quotient by the
// free rotation: the elastic block A_e of A (the slots only feed it) restricted to its invariant
// complement {y : U^T W y = 0} of U = [[r, 0], [0, r]], W = diag(M, M) (an orthonormal basis Q of
// it, Q^T A_e Q). The free rotation's double zero, a Jordan block, would come out of A_e itself
// only to sqrt(rounding).
std::vector<std::complex<double>> ElasticEigenvalues(const std::string& yaml) {
  const config::LoadedGearbox loaded = config::LoadAnyGearboxFromString(yaml);
  REQUIRE(loaded.schema == 2);
  const GearTrain train = BuildGearTrain(loaded.train);
  const TrainTables t = BuildTrainTables(loaded.train, train);
  const std::vector<ContactState> drive(t.meshes.size(), ContactState::kDrive);
  const std::vector<int> segments(t.meshes.size(), 0);
  const Eigen::MatrixXd A = AssembleTrainGenerator(t, segments, drive);
  const int n = t.n, e = 2 * n;
  Eigen::MatrixXd WU = Eigen::MatrixXd::Zero(e, 2);
  WU.col(0).head(n) = t.inertia.cwiseProduct(t.rigid_rotation);
  WU.col(1).tail(n) = t.inertia.cwiseProduct(t.rigid_rotation);
  const Eigen::MatrixXd Q =
      Eigen::HouseholderQR<Eigen::MatrixXd>(WU).householderQ() * Eigen::MatrixXd::Identity(e, e);
  const Eigen::MatrixXd Qc = Q.rightCols(e - 2);
  const Eigen::VectorXcd lambda = (Qc.transpose() * A.topLeftCorner(e, e) * Qc).eigenvalues();
  return {lambda.data(), lambda.data() + lambda.size()};
}

double SlowestDecay(const std::vector<std::complex<double>>& lambda) {
  double slowest = -1e300;
  for (const auto& l : lambda) slowest = std::max(slowest, l.real());
  return slowest;
}

TEST_CASE(
    "atlas on a train: a loaded cell decays at the slowest rate of the linear system, an "
    "undragged loose gear rattles",
    "[cli][train][atlas]") {
  const TempDir dir;
  const auto file = dir.Write("train.yaml", SmallTrain("1 N*m"));
  const long cycles = 600;  // of g1-g2: 1 ms each at 3000 rpm (20 teeth)
  const auto r = RunCommand(kExe + " atlas --json --jobs 2 --cycles " + std::to_string(cycles) +
                            " --transient 50 --x operating.loads[1].torque=0Nm:2Nm:2"
                            " --y operating.speed=2900rpm:3000rpm:2 --out " +
                            (dir.path() / "out").string() + " " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["schema"] == "gearnvh/2");
  CHECK(doc["meshes"] == nlohmann::json({"g1-g2", "g3-g4"}));
  CHECK(doc["loose_gears"] == nlohmann::json({"g4"}));
  REQUIRE(doc["cells"].size() == 4);
  const double mesh_period = 60.0 / (3000.0 * 20.0);
  for (const auto& c : doc["cells"]) {
    INFO("cell " << c.dump());
    REQUIRE(c["ok"] == true);
    const int ix = c["ix"], iy = c["iy"];
    if (ix == 1) {
      // Drag 2 N m: every mesh stays in drive contact, the train is linear.
      CHECK(c["regime"] == "no impact");
      for (const auto& m : c["meshes"]) CHECK(m["regime"] == "no impact");
      const double rpm = iy == 0 ? 2900.0 : 3000.0;
      std::string yaml = SmallTrain("2 N*m");
      yaml.replace(yaml.find("3000 rpm"), 8, std::to_string(rpm) + " rpm");
      const double expected = SlowestDecay(ElasticEigenvalues(yaml));
      CHECK(expected < 0.0);
      // Tolerance 3 / T, T the averaged time (whole standard-error blocks of the cycles of the
      // first mesh at this speed): Benettin's error for the largest exponent is a boundary term
      // ln(cond) / T (the train's Lyapunov test measured < 0.35 / T).
      const double T = static_cast<double>(cycles / 8 * 8) * mesh_period * 3000.0 / rpm;
      CHECK(std::abs(c["lyapunov_per_s"].get<double>() - expected) <= 3.0 / T);
    } else {
      // No drag: the loose gear g4 rattles in its backlash; the loaded mesh g1-g2 does not.
      CHECK(c["regime"] != "no impact");
      CHECK(c["meshes"][1]["regime"] != "no impact");
      CHECK(c["meshes"][1]["drive_impacts_per_cycle"].get<double>() > 0.0);
      CHECK(c["meshes"][0]["regime"] == "no impact");
      CHECK(c["loose_gears"][0]["rattle_index"].get<double>() > 0.0);
      CHECK(c["loose_gears"][0]["impact_energy_per_second"].get<double>() > 0.0);
      CHECK(c["loose_gears"][0]["rank"] == 1);
    }
  }
  CHECK(doc["regime_counts"]["no impact"] == 2);
  const std::string csv = ReadWholeFile(dir.path() / "out" / "atlas.csv");
  CHECK(csv.find("operating.loads[1].torque [N m],operating.speed [rpm]") != std::string::npos);
  CHECK(csv.find("g3-g4 regime") != std::string::npos);
  CHECK(csv.find("g4 impact_energy_per_second,g4 rattle_index") != std::string::npos);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 5);
  CHECK(nlohmann::json::parse(ReadWholeFile(dir.path() / "out" / "atlas.json"))["cells"].size() ==
        4);

  // The terminal map (piped: no progress on stderr).
  const auto text = RunCommand(kExe +
                               " atlas --jobs 1 --cycles 64 --transient 10"
                               " --x operating.loads[1].torque=0Nm:2Nm:2"
                               " --y operating.speed=2900rpm:3000rpm:2 " +
                               file.string());
  INFO(text.err);
  REQUIRE(text.exit_code == 0);
  CHECK(text.err.empty());
  CHECK(text.out.find("mesh g3-g4:") != std::string::npos);
  CHECK(text.out.find("loose gear that rattles most") != std::string::npos);
}

TEST_CASE("atlas and orbits on a train refuse bad parameters naming the value and the rule",
          "[cli][train][atlas][orbits]") {
  const TempDir dir;
  const auto file = dir.Write("train.yaml", SmallTrain("1 N*m")).string();
  struct Case {
    std::string args, value, rule;
  };
  for (const Case& c : std::vector<Case>{
           {"atlas --x operating.torque=1Nm:2Nm:2 --y operating.speed=1000rpm:2000rpm:2",
            "'operating.torque'",
            "is a schema-1 parameter; a gear train's torques are "
            "operating.loads[i].torque"},
           {"atlas --x mesh.backlash=50um:100um:2 --y operating.speed=1000rpm:2000rpm:2",
            "'mesh.backlash'", "a gear train's meshes are meshes[i]"},
           {"atlas --x meshes[0].stiffness=1:2:2 --y operating.speed=1000rpm:2000rpm:2",
            "'meshes[0].stiffness'", "is not a parameter a gear train can vary"},
           {"atlas --x operating.loads[7].torque=0Nm:1Nm:2 --y operating.speed=1000rpm:2000rpm:2",
            "operating.loads[7].torque", "has 2 entries (0: on output, 1: on g4)"},
           {"atlas --x meshes[0].backlash=50um:100um:1 --y operating.speed=1000rpm:2000rpm:2",
            "'meshes[0].backlash=50um:100um:1'", "POINTS must be >= 2"},
           {"atlas --x meshes[0].backlash=50um:100um:2 --y operating.speed=2000rpm:1000rpm:2",
            "'operating.speed=2000rpm:1000rpm:2'", "TO must be greater than from"},
           {"orbits --sweep meshes[2].backlash=50um:100um:3", "meshes[2].backlash",
            "has 2 entries (0: g1-g2, 1: g3-g4)"},
           {"orbits --sweep operating.speed=1000Nm:2000Nm:3", "'1000Nm'", "rpm"},
       }) {
    const auto r = RunCommand(kExe + " " + c.args + " " + file);
    INFO(c.args << ": " << r.err);
    CHECK(r.exit_code == 2);  // a command-line option: usage error
    CHECK(r.out.empty());
    CHECK(r.err.find(c.value) != std::string::npos);
    CHECK(r.err.find(c.rule) != std::string::npos);
  }
  // One load: "has 1 entry", not "1 entries".
  const auto one = RunCommand(kExe +
                              " atlas --x operating.loads[3].torque=0Nm:1Nm:2"
                              " --y operating.speed=1000rpm:2000rpm:2 " +
                              kExamples + "/two_stage_helical_reducer.yaml");
  INFO(one.err);
  CHECK(one.exit_code == 2);
  CHECK(one.err.find("the file's operating.loads has 1 entry (0: on output)") !=
        std::string::npos);
  // A value outside the schema's range fails its cell with the schema path and rule.
  const auto r = RunCommand(kExe +
                            " atlas --json --cycles 8 --transient 0"
                            " --x meshes[0].backlash=0um:80um:2"
                            " --y operating.speed=2900rpm:3000rpm:2 " +
                            file);
  CHECK(r.exit_code == 1);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["failed_cells"] == 2);  // backlash 0 at both speeds
  CHECK(doc["cells"][0]["ok"] == false);
  CHECK(doc["cells"][0]["message"].get<std::string>().find(
            "meshes[0].backlash: must be > 0, got 0 µm") != std::string::npos);
  CHECK(doc["cells"][1]["ok"] == true);
  // The terminal map shows the failed cells (it crashed on them once) and --out is released.
  const TempDir out;
  const auto text = RunCommand(kExe +
                               " atlas --cycles 8 --transient 0"
                               " --x meshes[0].backlash=0um:80um:2"
                               " --y operating.speed=2900rpm:3000rpm:2 --out " +
                               (out.path() / "atlas").string() + " " + file);
  INFO(text.err);
  CHECK(text.exit_code == 1);
  CHECK(text.out.find("  mesh g1-g2:\n  X") != std::string::npos);  // column 0: backlash 0
  CHECK(text.out.find("  mesh g3-g4:\n  X") != std::string::npos);
  CHECK(text.out.find("cell (0, 1) failed: meshes[0].backlash: must be > 0") != std::string::npos);
  CHECK(std::filesystem::exists(out.path() / "atlas" / "atlas.csv"));
  CHECK(!std::filesystem::exists(out.path() / ".atlas.lock"));

  // orbits: a failed first point names its value as the axis shows it (-10 µm, not -1e-05), and the
  // document keeps the train's common period, that of the points that ran: one input revolution,
  // 0.02 s at 3000 rpm (20 and 30 teeth, engine order 2: whole cycles per revolution).
  const auto o = RunCommand(kExe + " orbits --json --transient 8 --sweep " +
                            "meshes[0].backlash=-10um:80um:2 " + file);
  INFO(o.err);
  CHECK(o.exit_code == 1);
  const auto orbits = nlohmann::json::parse(o.out);
  CHECK(orbits["points"][0]["ok"] == false);
  CHECK(orbits["points"][0]["message"].get<std::string>() ==
        "meshes[0].backlash: must be > 0, got -10 µm");
  CHECK(orbits["points"][1]["ok"] == true);
  CHECK(orbits["common_period_s"].get<double>() == Approx(0.02).epsilon(1e-12));
}

TEST_CASE(
    "orbits on a loaded train: the linear periodic solution with multipliers "
    "exp(lambda T)",
    "[cli][train][orbits]") {
  const TempDir dir;
  const std::string yaml = SmallTrain("2 N*m");
  const auto file = dir.Write("train.yaml", yaml);
  const auto r = RunCommand(kExe + " orbits --json --transient 20 --out " +
                            (dir.path() / "out").string() + " " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  // One input revolution at 3000 rpm: 20 and 30 mesh cycles, two cycles of engine order 2.
  CHECK(doc["common_period_s"].get<double>() == Approx(0.02).epsilon(1e-12));
  REQUIRE(doc["points"].size() == 1);
  const auto& p = doc["points"][0];
  REQUIRE(p["found"] == true);
  CHECK(p["stable"] == true);
  CHECK(p["events_per_period"] == 0);  // permanent contact: the linear periodic solution
  const double T = doc["period_s"].get<double>();
  const std::vector<std::complex<double>> lambda = ElasticEigenvalues(yaml);
  REQUIRE(p["multipliers"].size() == lambda.size());
  // Each exp(lambda T) has a computed multiplier within 2e-5 of the largest modulus. Tolerance:
  // the monodromy is the product of ~10^3 exact pieces S e^{D tau} S^-1 per period, each carrying
  // rounding times cond(S) (up to 1e6 before a tuple falls back to the dense path), ~1e-10 each,
  // so ~1e-7 of |J|; the phase of exp(lambda T) turns ~200 rad here, which amplifies nothing
  // further. Measured 4e-6 of the largest modulus; Newton's tolerance does not enter J.
  double largest = 0.0;
  for (const auto& m : p["multipliers"]) largest = std::max(largest, m["abs"].get<double>());
  for (const auto& l : lambda) {
    const std::complex<double> expected = std::exp(l * T);
    double nearest = 1e300;
    for (const auto& m : p["multipliers"]) {
      nearest = std::min(nearest, std::abs(std::complex<double>(m["re"], m["im"]) - expected));
    }
    INFO("lambda " << l << ", expected multiplier " << expected);
    CHECK(nearest <= 2e-5 * largest);
  }
  CHECK(std::filesystem::exists(dir.path() / "out" / "orbits.csv"));

  // Without drag the loose gear rattles; the text says plainly when no stable orbit is found.
  const auto text = RunCommand(kExe +
                               " orbits --transient 20 --sweep "
                               "operating.loads[1].torque=0Nm:2Nm:2 " +
                               dir.Write("train0.yaml", SmallTrain("0 N*m")).string());
  INFO(text.err);
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("operating.loads[1].torque = 2 N m: stable") != std::string::npos);
  CHECK(text.out.find("multipliers:") != std::string::npos);
  // At zero drag and 3200 rpm shooting finds no orbit (at 3000 rpm an 8-impact one is stable,
  // 2900 and 3100 rpm unstable): said plainly.
  const std::string fast =
      testing::ReplaceFirst(SmallTrain("0 N*m"), "value: 3000 rpm", "value: 3200 rpm");
  const auto none =
      RunCommand(kExe + " orbits --transient 20 " + dir.Write("train0_fast.yaml", fast).string());
  INFO(none.err);
  REQUIRE(none.exit_code == 0);
  CHECK(none.out.find("No stable period-1 orbit exists at this operating point") !=
        std::string::npos);
}

}  // namespace
}  // namespace gearnvh
