#include "train_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "check_command.h"
#include "display_units.h"
#include "face_load_output.h"
#include "gearnvh/analysis/train_load_warnings.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/train_campbell.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh::app {
namespace {

// A load at the operating point: its speed relative to what it acts against (the housing or its
// `relative_to` shaft), its mean torque T + c |dW| and the power it takes, (T + c |dW|) |dW|.
struct LoadSummary {
  const TrainLoad* load = nullptr;
  double relative_speed = 0.0;  // rad/s
  double mean_torque = 0.0;     // N m
  double power = 0.0;           // W
};

std::vector<LoadSummary> SummariseLoads(const TrainSpec& spec, const GearTrain& train) {
  std::vector<LoadSummary> out;
  for (size_t i = 0; i < spec.operating.loads.size(); ++i) {
    const TrainLoad& load = spec.operating.loads[i];
    const double dw = ActionOfLoad(spec, train.topology, i).relative_speed;
    const double mean = load.torque + load.viscous * std::abs(dw);
    out.push_back({&load, dw, mean, mean * std::abs(dw)});
  }
  return out;
}

struct TierCrossing {
  int mode = 0;              // numbered from 1
  std::string line;          // the Campbell's order line: "mesh g1-g2 1x", "input 1x", ...
  double input_speed = 0.0;  // rad/s of the input shaft
  double frequency_hz = 0.0;  // the mode's undamped natural frequency at tier 1
};

// Input speeds at which an order line of the Campbell diagram (TrainOrderLines: every shaft speed,
// mesh harmonics 1-3, every engine order at its own shaft's speed, coinciding lines joined)
// crosses a tier-1 mode: the line's frequency is its order times the input speed.
std::vector<TierCrossing> CriticalSpeeds(const TrainSpec& spec, const GearTrain& train,
                                         const TrainTorsionalModes& modes) {
  const std::vector<OrderLine> lines = TrainOrderLines(spec, train);
  std::vector<TierCrossing> out;
  for (size_t k = 0; k < modes.frequencies_hz.size(); ++k) {
    const double w_mode = 2.0 * std::numbers::pi * modes.frequencies_hz[k];
    for (const OrderLine& line : lines) {
      if (line.order <= 0.0) continue;
      out.push_back(
          {static_cast<int>(k) + 1, line.label, w_mode / line.order, modes.frequencies_hz[k]});
    }
  }
  return out;
}

// The stage (1 = the first) that a coupling's static twist lies in.
int StaticStage(const TrainCouplingModel& m) {
  const double twist = std::abs(m.MeanTwist());
  return 1 + static_cast<int>(
                 std::count_if(m.stages.begin(), m.stages.end(),
                               [&](const TrainCouplingStage& s) { return twist > s.from; }));
}

// A multi-stage coupling's stages as written: "0.4 N m/deg to 1.5 deg, 9 N m/deg to 8 deg, 60 N
// m/deg beyond".
std::string StagesText(const TrainCoupling& c) {
  std::string text = Format(c.stiffness, c.stiffness_unit);
  for (const TrainCouplingStage& s : c.stages) {
    text += " to " + Format(s.from, c.angle_unit) + ", " + Format(s.stiffness, c.stiffness_unit);
  }
  return text + " beyond";
}

// Each coupling at the operating point: its shafts, stiffness (its stages') and damping as written
// (JSON: SI), the static torque it carries, the twist that gives and the stage it lies in.
nlohmann::json CouplingsJson(const TrainSpec& spec, const GearTrain& train) {
  nlohmann::json out = nlohmann::json::array();
  for (size_t c = 0; c < train.couplings.size(); ++c) {
    const TrainCouplingModel& m = train.couplings[c];
    const TrainCoupling& written = spec.couplings[c];
    out.push_back({{"name", m.name},
                   {"between", {written.shaft_a, written.shaft_b}},
                   {"stiffness_n_m_per_rad", m.stiffness},
                   {"damping_n_m_s_per_rad", m.damping},
                   {"mean_torque_n_m", m.mean_torque},
                   {"mean_twist_deg", m.MeanTwist() * 180.0 / std::numbers::pi},
                   {"static_stage", StaticStage(m)},
                   {"static_stiffness_n_m_per_rad", m.StaticStiffness()}});
    nlohmann::json stages = nlohmann::json::array();
    for (const TrainCouplingStage& s : m.stages) {
      stages.push_back({{"from_deg", s.from * 180.0 / std::numbers::pi},
                        {"stiffness_n_m_per_rad", s.stiffness}});
    }
    out.back()["stages_after_first"] = stages;
  }
  return out;
}

void PrintCouplings(const TrainSpec& spec, const GearTrain& train) {
  if (train.couplings.empty()) return;
  fmt::print("  {:<16}{:<26}{:>18}{:>20}{:>14}{:>12}\n", "coupling", "between", "stiffness",
             "damping", "torque [N m]", "twist [deg]");
  for (size_t c = 0; c < train.couplings.size(); ++c) {
    const TrainCouplingModel& m = train.couplings[c];
    const TrainCoupling& written = spec.couplings[c];
    // A multi-stage coupling: the stiffness of the stage its static twist lies in.
    fmt::print("  {:<16}{:<26}{:>18}{:>20}{:>14.4g}{:>12.4g}\n", m.name,
               written.shaft_a + " - " + written.shaft_b,
               Format(m.StaticStiffness(), written.stiffness_unit),
               written.damping > 0.0 ? Format(written.damping, written.damping_unit) : "-",
               m.mean_torque, m.MeanTwist() * 180.0 / std::numbers::pi);
    if (m.stages.empty()) continue;
    fmt::print("    stages {}; static twist in stage {} of {} (its stiffness above)\n",
               StagesText(written), StaticStage(m), m.stages.size() + 1);
  }
}

const char* KindName(BodyKind kind) { return kind == BodyKind::kShaft ? "shaft" : "loose gear"; }

nlohmann::json MatrixJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json CampbellJson(const CampbellData& data) {
  std::vector<double> speeds_rpm;
  for (double w : data.speeds_rad_s) speeds_rpm.push_back(Rpm(w));
  nlohmann::json modes = nlohmann::json::array();
  for (size_t k = 0; k < data.modes.size(); ++k) {
    nlohmann::json f = nlohmann::json::array();
    for (double x : data.frequency_hz[k])
      f.push_back(std::isfinite(x) ? nlohmann::json(x) : nlohmann::json());
    modes.push_back({{"mode", k + 1},
                     {"label", data.modes[k].Label()},
                     {"type", ModeTypeName(data.modes[k].type)},
                     {"whirl", WhirlName(data.modes[k].whirl)},
                     {"frequency_hz", f}});
  }
  nlohmann::json orders = nlohmann::json::array();
  for (const OrderLine& o : data.orders) orders.push_back({{"label", o.label}, {"order", o.order}});
  nlohmann::json critical = nlohmann::json::array();
  for (const CriticalSpeed& c : data.critical_speeds) {
    critical.push_back({{"order", c.order},
                        {"mode", c.mode + 1},
                        {"mode_label", data.modes[static_cast<size_t>(c.mode)].Label()},
                        {"speed_rpm", c.speed_rpm},
                        {"frequency_hz", c.frequency_hz}});
  }
  return {{"speeds_rpm", speeds_rpm},
          {"modes", modes},
          {"orders", orders},
          {"critical_speeds", critical}};
}

}  // namespace

TrainCheck BuildTrainCheck(const TrainSpec& spec, const std::atomic<bool>* cancel) {
  TrainCheck c;
  c.train = BuildGearTrain(spec);
  ThrowIfCancelled(cancel);
  for (const std::string& w : TrainLoadWarnings(spec, c.train.topology))
    c.train.warnings.push_back(w);
  c.torsional = TorsionalModes(c.train);
  c.structure = AssembleTrainStructure(spec, c.train);
  c.campbell_tier = spec.analysis.tier;
  if (!TrainTierAvailable(c.structure, c.campbell_tier)) {
    throw InputError("analysis.tier", 0, TierName(c.campbell_tier),
                     "tiers 4, 5, N20 simple and N20 MTA need an elastic shaft in the train");
  }
  ThrowIfCancelled(cancel);
  c.fe = FullTrainModes(c.structure, kReportedModes);
  ThrowIfCancelled(cancel);
  const TrainReducedModel* analysis = nullptr;
  std::vector<Tier> available;
  for (Tier t : kAllTiers) {
    (TrainTierAvailable(c.structure, t) ? available : c.unavailable).push_back(t);
  }
  c.tiers = ReduceTrainTiers(c.structure, available);
  ThrowIfCancelled(cancel);
  for (const TrainReducedModel& r : c.tiers) {
    if (r.tier == c.campbell_tier) analysis = &r;
  }
  // Every mode below 3x the highest order line's frequency at the sweep's top speed is tracked (a
  // mesh's 3x, or an excitation order above it).
  const SweepRange& sweep = spec.analysis.speed_sweep;
  std::vector<double> speeds;
  for (int i = 0; i < sweep.points; ++i) {
    speeds.push_back(sweep.from + (sweep.to - sweep.from) * i / std::max(1, sweep.points - 1));
  }
  double max_order = 0.0;
  for (const OrderLine& line : TrainOrderLines(spec, c.train))
    max_order = std::max(max_order, line.order);
  CampbellOptions options;
  options.max_frequency_hz = 3.0 * max_order * sweep.to / (2.0 * std::numbers::pi);
  c.campbell = TrainCampbell(spec, c.train, c.structure, *analysis, speeds, options);
  return c;
}

nlohmann::json TrainCheckReport(const TrainSpec& spec, const TrainCheck& check) {
  const GearTrain& train = check.train;
  const TrainTorsionalModes& modes = check.torsional;
  nlohmann::json doc;
  doc["name"] = spec.name;
  doc["schema"] = "gearnvh/2";
  doc["meshes"] = nlohmann::json::array();
  for (const TrainMeshModel& m : train.meshes) {
    const PairGeometry& g = m.geometry;
    nlohmann::json geometry = {{"contact_ratio", g.contact_ratio},
                               {"center_distance", g.center_distance},
                               {"working_pressure_angle", g.working_pressure_angle},
                               {"base_pitch", g.base_pitch},
                               {"gear_ratio", g.gear_ratio},
                               {"mesh_frequency_hz", g.mesh_frequency_hz}};
    if (g.helix_angle > 0.0) {
      geometry["helix_angle"] = g.helix_angle;
      geometry["base_helix_angle"] = g.base_helix_angle;
      geometry["overlap_ratio"] = g.overlap_ratio;
      geometry["total_contact_ratio"] = g.total_contact_ratio;
    }
    const MeshStiffnessSummary& k = m.stiffness;
    doc["meshes"].push_back(
        {{"name", m.name},
         {"gears",
          {spec.gears[static_cast<size_t>(m.gear_a)].name,
           spec.gears[static_cast<size_t>(m.gear_b)].name}},
         {"geometry", geometry},
         {"transmitted_torque", m.transmitted_torque},
         {"load", m.cycle.load},
         {"back_flank_loaded", m.back_flank_loaded},
         {"stiffness_model", m.cycle.overridden ? "override" : "potential_energy"},
         {"stiffness",
          {{"mean", k.mean},
           // null when a single pair never carries the load alone (total contact ratio >= 2)
           {"single_pair_mean",
            k.single_pair_mean > 0.0 ? nlohmann::json(k.single_pair_mean) : nlohmann::json()},
           {"min", k.min},
           {"max", k.max}}},
         {"lste_peak_to_peak", k.lste_peak_to_peak},
         {"load_sharing_max", k.load_sharing_max},
         {"face_load", FaceLoadJson(m.cycle.face)}});
  }
  doc["bodies"] = nlohmann::json::array();
  for (size_t b = 0; b < train.topology.bodies.size(); ++b) {
    const TrainBody& body = train.topology.bodies[b];
    nlohmann::json gears = nlohmann::json::array();
    for (int g : body.gears) gears.push_back(spec.gears[static_cast<size_t>(g)].name);
    doc["bodies"].push_back({{"name", body.name},
                             {"kind", KindName(body.kind)},
                             {"gears", gears},
                             {"speed", body.speed},
                             {"speed_rpm", Rpm(body.speed)},
                             {"polar_inertia", train.body_inertia[b]}});
  }
  doc["loads"] = nlohmann::json::array();
  for (const LoadSummary& l : SummariseLoads(spec, train)) {
    doc["loads"].push_back(
        {{"on", l.load->on},
         {"relative_to",
          l.load->relative_to.empty() ? nlohmann::json() : nlohmann::json(l.load->relative_to)},
         {"torque_n_m", l.load->torque},
         {"viscous_n_m_s_per_rad", l.load->viscous},
         {"relative_speed_rpm", Rpm(l.relative_speed)},
         {"mean_torque_n_m", l.mean_torque},
         {"power_w", l.power}});
  }
  doc["couplings"] = CouplingsJson(spec, train);
  doc["input_torque"] = train.input_torque;
  nlohmann::json critical = nlohmann::json::array();
  for (const TierCrossing& c : CriticalSpeeds(spec, train, modes)) {
    critical.push_back({{"mode", c.mode},
                        {"line", c.line},
                        {"input_speed", c.input_speed},
                        {"input_speed_rpm", Rpm(c.input_speed)},
                        {"frequency_hz", c.frequency_hz}});
  }
  const TrainStructure& st = check.structure;
  doc["fe"] = {{"nodes", st.nodes.size()},
               {"dofs", st.dofs},
               {"elastic_shafts", st.elastic_shafts.size()},
               {"free_rotations", st.free_rotations.cols()},
               {"rigid_body_modes", check.fe.rigid_body_modes},
               {"natural_frequencies_hz", check.fe.frequencies_hz}};
  doc["tiers"] = nlohmann::json::array();
  for (const TrainReducedModel& r : check.tiers) {
    doc["tiers"].push_back(
        {{"name", r.name},
         {"dof", r.dof},
         {"free_rotations", r.rigid_body_modes},
         {"natural_frequencies_hz", r.natural_frequencies_hz},
         {"static_compliance", MatrixJson(r.static_compliance)},
         {"compliance_error_vs_full",
          ComplianceErrorJson(ComplianceErrorVsFull(r.tier, r.compliance_error_vs_full))}});
  }
  nlohmann::json unavailable = nlohmann::json::array();
  for (Tier t : check.unavailable) unavailable.push_back(TierName(t));
  doc["tiers_unavailable"] = unavailable;
  doc["full_static_compliance"] = check.tiers.empty()
                                      ? nlohmann::json()
                                      : MatrixJson(check.tiers.front().full_static_compliance);
  doc["critical_speeds"] = critical;
  nlohmann::json campbell = CampbellJson(check.campbell);
  campbell["tier"] = TierName(check.campbell_tier);
  doc["campbell"] = campbell;
  doc["warnings"] = train.warnings;
  return doc;
}

void PrintTrainCheck(const std::string& file, const TrainSpec& spec, const TrainCheck& check) {
  const GearTrain& train = check.train;
  const TrainTorsionalModes& modes = check.torsional;
  fmt::print("{}  ({}, gear train: {} shafts, {} gears, {} meshes)\n", spec.name, file,
             spec.shafts.size(), spec.gears.size(), spec.meshes.size());
  fmt::print("  {:<16}{:>12}{:>8}{:>8}{:>9}{:>9}{:>10}{:>12}{:>12}\n", "mesh", "torque", "eps_a",
             "eps_b", "eps_g", "f_mesh", "k_mean", "k_single", "LSTE p-p");
  // Width-padded by bytes: each µ is two bytes, so its column is one wider.
  fmt::print("  {:<16}{:>12}{:>8}{:>8}{:>9}{:>9}{:>11}{:>13}{:>13}\n", "", "[N m]", "", "", "",
             "[Hz]", "[N/µm]", "[N/µm]", "[µm]");
  for (const TrainMeshModel& m : train.meshes) {
    const PairGeometry& g = m.geometry;
    const std::string single = m.stiffness.single_pair_mean > 0.0
                                   ? fmt::format("{:.1f}", m.stiffness.single_pair_mean * 1e-6)
                                   : "-";  // never one pair alone
    fmt::print("  {:<16}{:>12.4g}{:>8.4f}{:>8.4f}{:>9.4f}{:>9.1f}{:>10.1f}{:>12}{:>12.4f}{}\n",
               m.name, m.transmitted_torque, g.contact_ratio, g.overlap_ratio,
               g.total_contact_ratio, g.mesh_frequency_hz, m.stiffness.mean * 1e-6, single,
               m.stiffness.lste_peak_to_peak * 1e6,
               g.helix_angle > 0.0
                   ? fmt::format("  helical {:.1f}°", g.helix_angle * 180.0 / std::numbers::pi)
                   : "  spur");
  }
  for (const TrainMeshModel& m : train.meshes) {
    const std::string face = FaceLoadText(m.cycle.face, "    ");
    if (!face.empty()) fmt::print("  mesh {}:\n{}", m.name, face);
  }
  fmt::print("  {:<16}{:<12}{:>14}{:>18}   gears\n", "body", "kind", "speed [rpm]", "J [kg m²]");
  for (size_t b = 0; b < train.topology.bodies.size(); ++b) {
    const TrainBody& body = train.topology.bodies[b];
    std::string gears;
    for (int g : body.gears)
      gears += (gears.empty() ? "" : ", ") + spec.gears[static_cast<size_t>(g)].name;
    fmt::print("  {:<16}{:<12}{:>14.2f}{:>18.4e}   {}\n", body.name, KindName(body.kind),
               Rpm(body.speed), train.body_inertia[b], gears);
  }
  fmt::print("  {:<16}{:<14}{:>12}{:>20}{:>14}{:>12}\n", "load on", "relative to", "torque",
             "viscous", "speed [rpm]", "power [W]");
  for (const LoadSummary& l : SummariseLoads(spec, train)) {
    const TrainLoad& load = *l.load;
    fmt::print("  {:<16}{:<14}{:>12}{:>20}{:>14.2f}{:>12.4g}\n", load.on,
               load.relative_to.empty() ? "housing" : load.relative_to,
               Format(load.torque, load.torque_unit),
               load.viscous > 0.0 ? Format(load.viscous, load.viscous_unit) : "-",
               Rpm(l.relative_speed), l.power);
  }
  PrintCouplings(spec, train);
  fmt::print("  input torque balancing the loads: {:.4g} N m\n", train.input_torque);
  fmt::print("  tier 1 (torsional, {} DOF, {} free rotation{}): natural frequencies [Hz]\n   ",
             train.body_inertia.size(), modes.free_rotations, modes.free_rotations == 1 ? "" : "s");
  for (double f : modes.frequencies_hz) fmt::print(" {:.1f}", f);
  const TrainStructure& st = check.structure;
  fmt::print("\n  finite elements: {} nodes, {} DOF ({} elastic shaft{}), {} free rotation{}\n",
             st.nodes.size(), st.dofs, st.elastic_shafts.size(),
             st.elastic_shafts.size() == 1 ? "" : "s", st.free_rotations.cols(),
             st.free_rotations.cols() == 1 ? "" : "s");
  fmt::print("  {:<28}", "natural frequencies [Hz]");
  for (size_t i = 0; i < check.fe.frequencies_hz.size(); ++i) {
    if (i > 0 && i % 5 == 0) fmt::print("\n  {:<28}", "");
    fmt::print("{:>10.1f}", check.fe.frequencies_hz[i]);
  }
  fmt::print("\n  {:<12}{:>5}{:>6}{:>12}   lowest natural frequencies [Hz]\n", "modal tier", "DOF",
             "free", "G vs full");
  for (const TrainReducedModel& r : check.tiers) {
    fmt::print("  {:<12}{:>5}{:>6}{:>12}  ", r.name, r.dof, r.rigid_body_modes,
               ComplianceErrorText(ComplianceErrorVsFull(r.tier, r.compliance_error_vs_full)));
    for (size_t i = 0; i < std::min<size_t>(5, r.natural_frequencies_hz.size()); ++i) {
      fmt::print("{:>9.1f}", r.natural_frequencies_hz[i]);
    }
    fmt::print("\n");
  }
  if (!check.unavailable.empty()) {
    std::string names;
    for (Tier t : check.unavailable)
      names += (names.empty() ? "" : ", ") + std::string(TierName(t));
    fmt::print("  not available (no elastic shaft): {}\n", names);
  }
  const CampbellData& cd = check.campbell;
  fmt::print(
      "  Campbell ({}, input {:.0f}-{:.0f} rpm): {} tracked modes, {} order lines, {} "
      "critical speeds\n",
      TierName(check.campbell_tier), Rpm(cd.speeds_rad_s.front()), Rpm(cd.speeds_rad_s.back()),
      cd.modes.size(), cd.orders.size(), cd.critical_speeds.size());
  constexpr size_t kPrintedCrossings = 30;
  for (size_t i = 0; i < std::min(kPrintedCrossings, cd.critical_speeds.size()); ++i) {
    const CriticalSpeed& c = cd.critical_speeds[i];
    fmt::print("    {:<24} x mode {:<3} {:>10.1f} rpm {:>10.1f} Hz  {}\n", c.order, c.mode + 1,
               c.speed_rpm, c.frequency_hz, cd.modes[static_cast<size_t>(c.mode)].Label());
  }
  if (cd.critical_speeds.size() > kPrintedCrossings) {
    fmt::print("    ... and {} more (all in check --json)\n",
               cd.critical_speeds.size() - kPrintedCrossings);
  }
  for (const std::string& w : train.warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace gearnvh::app
