// `gearnvh validate` and the event methods of `gearnvh simulate` on gear trains (schema gearnvh/2).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "app/three_shaft_train_yaml.h"
#include "support/run_command.h"
#include "support/paths.h"

namespace gearnvh {
namespace {

using testing::ReplaceFirst;
using testing::RunCommand;

using testing::kExe;
using testing::kExamples;

TEST_CASE(
    "validate on a rattling train compares V3 with CVODE, V2 and V1, and fusion with stepping",
    "[cli][train]") {
  const auto r =
      RunCommand(kExe + " validate --json " + kExamples + "/manual_transmission_idle.yaml");
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["pass"].get<bool>());
  REQUIRE(doc["checks"].size() == 5);
  for (const auto& c : doc["checks"]) {
    CHECK(c["pass"].get<bool>());
    CHECK_FALSE(c["skipped"].get<bool>());
  }
  // The window where CVODE is trusted (8.59 of the 10 cycles run when written) holds the loose
  // gears' first impacts: 10 events, each matched by CVODE.
  const std::string events = doc["checks"][1]["detail"].get<std::string>();
  std::smatch m;
  REQUIRE(std::regex_search(events, m, std::regex("([0-9]+) CVODE events, ([0-9]+) exact")));
  CHECK(std::stoi(m[1]) >= 8);
  CHECK(m[1] == m[2]);
  CHECK(doc["checks"][1]["value"].get<double>() == 0.0);
  // The fusion row: some runs certified between the rattle's impacts (28 when written), each
  // equal to its stepped grid segments within the row's tolerance.
  const auto& fusion = doc["checks"][4];
  CHECK(fusion["name"].get<std::string>().find("segment-run fusion") != std::string::npos);
  CHECK(fusion["threshold"].get<double>() == 3e-11);
  CHECK(fusion["value"].get<double>() <= 3e-11);
  const std::string runs = fusion["detail"].get<std::string>();
  REQUIRE(std::regex_search(runs, m, std::regex("; ([0-9]+) runs")));
  CHECK(std::stoi(m[1]) > 0);
}

TEST_CASE("validate pairs the simultaneous events of a kinematic loop whatever their order",
          "[cli][train][validate]") {
  // Two identical meshes in parallel between shafts a and b (a loop with consistent ratios): under
  // a light load they open and close at the same instants, which CVODE may list in either order.
  // The events row once matched CVODE's events by order and failed here while the TE agreed.
  std::string yaml = ReplaceFirst(testing::kThreeShaftTrainYaml, "torque: 1 N*m", "torque: 0.05 N*m");
  yaml = ReplaceFirst(yaml, "teeth: 41", "teeth: 46");
  yaml = ReplaceFirst(yaml, "  g3: {shaft: b",
                      "  g5: {shaft: a, teeth: 23, module: 2 mm, face_width: 15 mm, bore_diameter: "
                      "20 mm, material: steel}\n"
                      "  g6: {shaft: b, teeth: 46, module: 2 mm, face_width: 15 mm, bore_diameter: "
                      "20 mm, material: steel}\n  g3: {shaft: b");
  yaml = ReplaceFirst(yaml, "  - {gears: [g3, g4], backlash: 100 um}\n",
                      "  - {gears: [g3, g4], backlash: 100 um}\n"
                      "  - {gears: [g5, g6], backlash: 100 um}\n");
  const testing::TempDir dir;
  const auto r = RunCommand(kExe + " validate --json " + dir.Write("loop.yaml", yaml).string());
  INFO(r.out << r.err);
  const auto doc = nlohmann::json::parse(r.out);
  REQUIRE(doc["checks"].size() >= 2);
  const auto& events = doc["checks"][1];
  INFO(events.dump());
  CHECK(events["name"].get<std::string>().find("events vs CVODE") != std::string::npos);
  CHECK_FALSE(events["skipped"].get<bool>());
  CHECK(events["value"].get<double>() == 0.0);  // every event paired (14 when written)
  CHECK(doc["checks"][0]["pass"].get<bool>());
  CHECK(r.exit_code == 0);
}

TEST_CASE("simulate on a train runs every event method with the same events", "[cli][train]") {
  long events[3] = {-1, -1, -1};
  const char* methods[3] = {"v3", "v2", "v1"};
  for (int k = 0; k < 3; ++k) {
    const auto r = RunCommand(kExe + " simulate --json --cycles 8 --transient 0 --method " +
                              methods[k] + " " + kExamples + "/manual_transmission_idle.yaml");
    INFO(methods[k] << "\n" << r.err);
    REQUIRE(r.exit_code == 0);
    const auto doc = nlohmann::json::parse(r.out);
    CHECK(doc["method"] == methods[k]);
    events[k] = doc["summary"]["events"].get<long>();
    // V1 walks its flagged sub-steps on the dyadic grid; V2 and V3 never do.
    CHECK((doc["summary"]["dyadic_substeps"].get<long>() > 0) == (k == 2));
  }
  // 8 cycles from the static state: the three methods agree to ~1e-10 of the TE there (validate),
  // so their event counts are equal.
  CHECK(events[0] > 0);
  CHECK(events[1] == events[0]);
  CHECK(events[2] == events[0]);
}

}  // namespace
}  // namespace gearnvh
