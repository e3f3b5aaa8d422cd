// The batch index of a report (DIR/index.html): what it lists for a pair and for a gear train.
#include "report_batch.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace gearnvh::app {
namespace {

// The cells of the row that links to `folder`.
std::string RowOf(const std::string& html, const std::string& folder) {
  const size_t at = html.find("<a href=\"" + folder + "/index.html\">");
  REQUIRE(at != std::string::npos);
  const size_t start = html.rfind("<tr>", at);
  return html.substr(start, html.find("</tr>", at) - start);
}

// A gearbox of this run that completed, with `summary`.
GearboxEntry Completed(const std::string& folder, nlohmann::json summary) {
  GearboxEntry e;
  e.file = folder + ".yaml";
  e.folder = folder;
  e.name = "a " + folder;
  e.ok = true;
  e.summary = std::move(summary);
  return e;
}

TEST_CASE("batch index: a gear train shows its per-mesh metrics and its loudest loose gear",
          "[app][report][train]") {
  const GearboxEntry pair = Completed("pair", {{"tier", "tier 2"},
                                               {"speed", "800 rpm"},
                                               {"torque", "20 N m on the wheel"},
                                               {"te_rms_um", 1.5},
                                               {"regime", "single-sided impacts"},
                                               {"impacts_per_cycle", 0.25},
                                               {"acceleration_ratio", 3.0},
                                               {"real_time_ratio", 12.0}});
  const GearboxEntry train =
      Completed("train", {{"tier", "tier 1 (gear train)"},
                          {"speed", "12000 rpm (input)"},
                          {"torque", "20 N m on layshaft"},
                          {"meshes",
                           {{{"name", "in-l0"}, {"te_rms_um", 0.123}, {"impacts_per_cycle", 0.5}},
                            {{"name", "l5-o5"}, {"te_rms_um", 4.5}, {"impacts_per_cycle", 0.0}}}},
                          {"loudest_loose_gear", "o5"},
                          {"loudest_loose_gear_impact_energy_per_second_w", 0.321},
                          {"first_critical_speed_rpm", 950.0},
                          {"real_time_ratio", 2.5}});
  const std::string html = BatchIndex({pair, train});
  const std::string t = RowOf(html, "train");
  CHECK(t.find("<td>tier 1 (gear train)</td><td>12000 rpm (input)</td><td>20 N m on "
               "layshaft</td>") != std::string::npos);
  CHECK(t.find("<td>in-l0 0.123<br>l5-o5 4.5</td><td>o5 (321 mW of impacts)</td><td>in-l0 "
               "0.5<br>l5-o5 "
               "0</td><td>-</td><td>950</td><td>-</td><td>2.5</td>") != std::string::npos);
  const std::string p = RowOf(html, "pair");
  CHECK(p.find("<td>1.5</td><td>single-sided impacts</td><td>0.25</td><td>3</td><td>-</td><td>-"
               "</td><td>12</td>") != std::string::npos);
}

TEST_CASE("batch index: a train without loose gears shows '-' for the loudest one",
          "[app][report][train]") {
  const GearboxEntry train = Completed(
      "train",
      {{"meshes", {{{"name", "a-b"}, {"te_rms_um", 2.0}}}}, {"loudest_loose_gear", nullptr}});
  const std::string row = RowOf(BatchIndex({train}), "train");
  CHECK(row.find("<td>a-b 2</td><td>-</td><td>a-b -</td>") != std::string::npos);
  // With loose gears of which none impacts, the column says so.
  const GearboxEntry quiet =
      Completed("quiet", {{"meshes", {{{"name", "a-b"}, {"te_rms_um", 2.0}}}},
                          {"loudest_loose_gear", nullptr},
                          {"loose_gears", 2}});
  CHECK(RowOf(BatchIndex({quiet}), "quiet").find("<td>no loose gear impacts</td>") !=
        std::string::npos);
}

}  // namespace
}  // namespace gearnvh::app
