// `gearnvh simulate` on gear trains (schema gearnvh/2): the tier-1 train solver end to end.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::RunCommand;

const std::string kExe = GEARNVH_EXE;
const std::string kExamples = GEARNVH_EXAMPLES_DIR;

TEST_CASE("simulate --json on a train reports every mesh and ranks the loose gears",
          "[cli][train]") {
  const auto r = RunCommand(kExe + " simulate --json --cycles 40 --transient 10 " + kExamples +
                            "/manual_transmission_idle.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["schema"] == "gearnvh/2");
  CHECK(doc["state_dim"] == 2 * 7 + 2);
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
  // The four loose gears, ranked 1..4 by a non-increasing rattle index.
  const auto& loose = doc["loose_gears"];
  REQUIRE(loose.size() == 4);
  for (size_t k = 0; k < loose.size(); ++k) {
    CHECK(loose[k]["rank"] == static_cast<int>(k) + 1);
    if (k > 0) {
      CHECK(loose[k]["rattle_index"].get<double>() <= loose[k - 1]["rattle_index"].get<double>());
    }
  }
  // 50 cycles of the headset mesh (21 teeth at 800 rpm).
  CHECK(doc["summary"]["simulated_s"].get<double>() ==
        Approx(50.0 * 60.0 / (800.0 * 21.0)).epsilon(1e-9));
  CHECK(doc["summary"]["cache"]["bytes"].get<double>() > 0.0);
}

TEST_CASE("simulate on a train prints the per-mesh table", "[cli][train]") {
  const auto r = RunCommand(kExe + " simulate --cycles 20 --transient 0 " + kExamples +
                            "/manual_transmission_idle.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("l3-o3") != std::string::npos);
  CHECK(r.out.find("loose gears by rattle index") != std::string::npos);
  CHECK(r.err.empty());  // quiet when piped
}

TEST_CASE("simulate on a train refuses a tier other than 1", "[cli][train]") {
  const auto r =
      RunCommand(kExe + " simulate --tier 3 " + kExamples + "/manual_transmission_idle.yaml");
  CHECK(r.exit_code == 2);  // a command-line option: usage error
  CHECK(r.err.find("--tier") != std::string::npos);
  CHECK(r.err.find("tier 1") != std::string::npos);
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
