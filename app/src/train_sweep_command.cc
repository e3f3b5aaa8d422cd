#include "train_sweep_command.h"

#include <fmt/format.h>

#include <optional>
#include <sstream>

#include "gearnvh/model/input_error.h"
#include "result_documents.h"
#include "train_command_options.h"

namespace gearnvh::app {

nlohmann::json TrainSweepPointJson(const TrainSweepPoint& p) {
  nlohmann::json meshes = nlohmann::json::array();
  for (const TrainMeshStatistics& m : p.meshes) {
    meshes.push_back({m.name, m.te_mean, m.te_rms, m.te_peak_to_peak, m.force_mean, m.force_max,
                      m.drive_impacts, m.back_impacts, m.separations, m.grazing,
                      m.free_time_fraction, m.impact_velocity_max, m.impact_velocity_rms});
  }
  nlohmann::json loose = nlohmann::json::array();
  for (const TrainLooseGearStatistics& g : p.loose_gears) {
    loose.push_back({g.name, g.body, g.rattle_index, g.impacts, g.rank, g.drive_impacts,
                     g.back_impacts, g.drive_impacts_per_second, g.back_impacts_per_second,
                     g.impact_velocity_rms, g.impact_velocity_max, g.impact_energy_per_second});
  }
  nlohmann::json couplings = nlohmann::json::array();
  for (const TrainCouplingResponse& c : p.couplings) {
    couplings.push_back({c.name, c.twist.mean, c.twist.rms, c.twist.min, c.twist.max, c.torque.mean,
                         c.torque.rms, c.torque.min, c.torque.max});
  }
  return {{"speed_rad_s", p.speed_rad_s},
          {"speed_rpm", p.speed_rpm},
          {"ok", p.ok},
          {"message", p.message},
          {"real_time_ratio", p.real_time_ratio},
          {"recorded_s", p.recorded_s},
          {"mesh_periods", p.mesh_periods},
          {"meshes", meshes},
          {"loose_gears", loose},
          {"couplings", couplings},
          {"waterfall", p.waterfall}};
}

TrainSweepPoint TrainSweepPointFromJson(const nlohmann::json& j) {
  TrainSweepPoint p;
  p.speed_rad_s = j.at("speed_rad_s").get<double>();
  p.speed_rpm = j.at("speed_rpm").get<double>();
  p.ok = j.at("ok").get<bool>();
  p.message = j.at("message").get<std::string>();
  p.real_time_ratio = j.at("real_time_ratio").get<double>();
  p.recorded_s = j.at("recorded_s").get<double>();
  p.mesh_periods = j.at("mesh_periods").get<std::vector<double>>();
  for (const auto& m : j.at("meshes")) {
    TrainMeshStatistics s;
    s.name = m.at(0).get<std::string>();
    s.te_mean = m.at(1).get<double>();
    s.te_rms = m.at(2).get<double>();
    s.te_peak_to_peak = m.at(3).get<double>();
    s.force_mean = m.at(4).get<double>();
    s.force_max = m.at(5).get<double>();
    s.drive_impacts = m.at(6).get<long>();
    s.back_impacts = m.at(7).get<long>();
    s.separations = m.at(8).get<long>();
    s.grazing = m.at(9).get<long>();
    s.free_time_fraction = m.at(10).get<double>();
    s.impact_velocity_max = m.at(11).get<double>();
    s.impact_velocity_rms = m.at(12).get<double>();
    p.meshes.push_back(std::move(s));
  }
  for (const auto& g : j.at("loose_gears")) {
    TrainLooseGearStatistics s;
    s.name = g.at(0).get<std::string>();
    s.body = g.at(1).get<int>();
    s.rattle_index = g.at(2).get<double>();
    s.impacts = g.at(3).get<long>();
    s.rank = g.at(4).get<int>();
    s.drive_impacts = g.at(5).get<long>();
    s.back_impacts = g.at(6).get<long>();
    s.drive_impacts_per_second = g.at(7).get<double>();
    s.back_impacts_per_second = g.at(8).get<double>();
    s.impact_velocity_rms = g.at(9).get<double>();
    s.impact_velocity_max = g.at(10).get<double>();
    s.impact_energy_per_second = g.at(11).get<double>();
    p.loose_gears.push_back(std::move(s));
  }
  for (const auto& c : j.at("couplings")) {
    const auto summary = [&c](int first) {
      return TrainOutputSummary{c.at(first).get<double>(), c.at(first + 1).get<double>(),
                                c.at(first + 2).get<double>(), c.at(first + 3).get<double>()};
    };
    p.couplings.push_back({c.at(0).get<std::string>(), summary(1), summary(5)});
  }
  p.waterfall = j.at("waterfall").get<std::vector<std::vector<double>>>();
  return p;
}

TrainSweepOptions PlanTrainSweep(const SweepOptions& options, const TrainSpec& spec,
                                 const OptionNames& names) {
  const TrainCommandSettings settings =
      CheckTrainCommandOptions(options.tier, spec, options.method, names);
  TrainSweepOptions sweep;
  sweep.cycles = options.cycles.value_or(sweep.cycles);
  sweep.transient = options.transient.value_or(sweep.transient);
  sweep.threads = options.jobs;
  sweep.events = settings.events;
  sweep.tier = settings.tier;
  sweep.allow_slow = options.allow_slow;
  sweep.names = names;
  RequireCycleCounts(sweep.cycles, 1, sweep.transient, names);
  if (sweep.threads < 0)
    throw InputError(names("jobs"), 0, std::to_string(sweep.threads), "must be >= 0");
  RequireRunLengthOfOptions(spec, spec.analysis.speed_sweep.from, sweep.cycles, sweep.transient,
                            options.cycles, options.transient, names);
  return sweep;
}

nlohmann::json TrainSweepJson(const TrainSweepResult& r) {
  nlohmann::json speeds = nlohmann::json::array(), points = nlohmann::json::array();
  for (const TrainSweepPoint& p : r.points) {
    speeds.push_back(p.speed_rpm);
    nlohmann::json meshes = nlohmann::json::array(), loose = nlohmann::json::array();
    for (size_t i = 0; i < p.meshes.size(); ++i) {
      const TrainMeshStatistics& m = p.meshes[i];
      const double cycles = p.recorded_s / p.mesh_periods[i];
      meshes.push_back(
          {{"name", m.name},
           {"te", {{"mean", m.te_mean}, {"rms", m.te_rms}, {"peak_to_peak", m.te_peak_to_peak}}},
           {"mesh_force", {{"mean", m.force_mean}, {"max", m.force_max}}},
           {"rattle",
            {{"impacts_per_cycle", p.ImpactsPerCycle(i)},
             {"drive_impacts_per_cycle", cycles > 0 ? m.drive_impacts / cycles : 0.0},
             {"back_impacts_per_cycle", cycles > 0 ? m.back_impacts / cycles : 0.0},
             {"separation_fraction", m.free_time_fraction},
             {"impact_velocity_rms", m.impact_velocity_rms}}}});
    }
    loose = TrainLooseGearsJson(p.loose_gears);
    points.push_back({{"speed_rpm", p.speed_rpm},
                      {"speed_rad_s", p.speed_rad_s},
                      {"ok", p.ok},
                      {"message", p.message},
                      {"real_time_ratio", p.real_time_ratio},
                      {"meshes", meshes},
                      {"loose_gears", loose},
                      {"couplings", TrainCouplingsJson(p.couplings, p.recorded_s)}});
  }
  nlohmann::json waterfall_meshes = nlohmann::json::array();
  for (size_t i = 0; i < r.mesh_names.size(); ++i) {
    nlohmann::json rows = nlohmann::json::array();
    for (const TrainSweepPoint& p : r.points)
      rows.push_back(i < p.waterfall.size() ? p.waterfall[i] : std::vector<double>{});
    waterfall_meshes.push_back(
        {{"name", r.mesh_names[i]}, {"mesh_order", r.mesh_orders[i]}, {"amplitude_m", rows}});
  }
  return {{"schema", "gearnvh/2"},
          {"speeds_rpm", speeds},
          {"meshes", r.mesh_names},
          {"loose_gears", r.loose_gear_names},
          {"points", points},
          {"failed_speeds", r.failed()},
          {"waterfall",
           {{"order_step", r.order_step},
            {"order_bins", r.order_bins},
            {"reference", "input shaft"},
            {"meshes", waterfall_meshes}}}};
}

std::string TrainMeshesCsv(const TrainSweepResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "speed_rpm,mesh,te_mean_m,te_rms_m,te_peak_to_peak_m,force_mean_n,force_max_n,"
        "impacts_per_cycle,separation_fraction,impact_velocity_rms_m_s\n";
  for (const TrainSweepPoint& p : r.points) {
    if (!p.ok) continue;
    for (size_t i = 0; i < p.meshes.size(); ++i) {
      const TrainMeshStatistics& m = p.meshes[i];
      os << p.speed_rpm << ',' << m.name << ',' << m.te_mean << ',' << m.te_rms << ','
         << m.te_peak_to_peak << ',' << m.force_mean << ',' << m.force_max << ','
         << p.ImpactsPerCycle(i) << ',' << m.free_time_fraction << ',' << m.impact_velocity_rms
         << '\n';
    }
  }
  return os.str();
}

std::string TrainLooseGearsCsv(const TrainSweepResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "speed_rpm,gear,rank,impact_energy_per_second_w,drive_impacts_per_second,"
        "back_impacts_per_second,impact_velocity_rms_m_s,impact_velocity_max_m_s,impacts,"
        "rattle_index_rad_s2\n";
  for (const TrainSweepPoint& p : r.points) {
    if (!p.ok) continue;
    for (const TrainLooseGearStatistics& g : p.loose_gears) {
      os << p.speed_rpm << ',' << g.name << ',' << g.rank << ',' << g.impact_energy_per_second
         << ',' << g.drive_impacts_per_second << ',' << g.back_impacts_per_second << ','
         << g.impact_velocity_rms << ',' << g.impact_velocity_max << ',' << g.impacts << ','
         << g.rattle_index << '\n';
    }
  }
  return os.str();
}

std::string TrainCouplingsCsv(const TrainSweepResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "speed_rpm,coupling,twist_mean_rad,twist_rms_rad,twist_min_rad,twist_max_rad,"
        "torque_mean_n_m,torque_rms_n_m,torque_min_n_m,torque_max_n_m\n";
  for (const TrainSweepPoint& p : r.points) {
    for (const TrainCouplingResponse& c : p.couplings) {
      os << p.speed_rpm << ',' << c.name << ',' << c.twist.mean << ',' << c.twist.rms << ','
         << c.twist.min << ',' << c.twist.max << ',' << c.torque.mean << ',' << c.torque.rms << ','
         << c.torque.min << ',' << c.torque.max << '\n';
    }
  }
  return os.str();
}

void PrintTrainSweep(const TrainSweepResult& r, const DisplayUnit& speed_unit) {
  const std::string unit = speed_unit.symbol;
  auto shown = [&speed_unit](const TrainSweepPoint& p) {
    return Significant(p.speed_rad_s * speed_unit.per_si, 6);
  };
  for (size_t i = 0; i < r.mesh_names.size(); ++i) {
    fmt::print("\n  mesh {}\n  {:>8}{:>12}{:>12}{:>14}{:>16}{:>11}\n", r.mesh_names[i], unit,
               "TE RMS µm", "TE p-p µm", "force max N", "impacts/cycle", "separated");
    for (const TrainSweepPoint& p : r.points) {
      if (!p.ok) {
        fmt::print("  {:>8}  failed: {}\n", shown(p), p.message);
        continue;
      }
      const TrainMeshStatistics& m = p.meshes[i];
      fmt::print("  {:>8}{:12.4f}{:12.4f}{:14.2f}{:16.4f}{:10.1f}%\n", shown(p), m.te_rms * 1e6,
                 m.te_peak_to_peak * 1e6, m.force_max, p.ImpactsPerCycle(i),
                 100.0 * m.free_time_fraction);
    }
  }
  if (r.loose_gear_names.empty()) return;
  fmt::print("\n  loose gears: impact energy (mW) and rank (- : no impact)\n  {:>8}", unit);
  for (const std::string& name : r.loose_gear_names) fmt::print("{:>16}", name);
  fmt::print("\n");
  for (const TrainSweepPoint& p : r.points) {
    if (!p.ok) continue;
    fmt::print("  {:>8}", shown(p));
    // The columns follow the names, found by name.
    for (const std::string& name : r.loose_gear_names) {
      const TrainLooseGearStatistics* g = FindLooseGear(p.loose_gears, name);
      if (!g) {
        fmt::print("{:>16}", "-");
        continue;
      }
      fmt::print("{:>16}", fmt::format("{:.4g} ({})", g->impact_energy_per_second * 1e3,
                                       g->rank > 0 ? std::to_string(g->rank) : "-"));
    }
    fmt::print("\n");
  }
}

nlohmann::json TrainSweepDocument(const TrainSweepResult& r, const TrainSpec& spec,
                                  const std::string& file, const TrainSweepOptions& options) {
  nlohmann::json doc = TrainSweepJson(r);
  doc["name"] = spec.name;
  doc["file"] = file;
  doc["tier"] = TierName(options.tier);
  doc["cycles_per_speed"] = options.cycles;
  doc["transient_cycles"] = options.transient;
  return doc;
}

}  // namespace gearnvh::app
