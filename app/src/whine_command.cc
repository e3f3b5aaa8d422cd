#include "whine_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/written_numbers.h"
#include "housing_table.h"
#include "output_folder.h"
#include "result_documents.h"
#include "train_command_options.h"
#include "uff_export.h"

namespace gearnvh::app {
namespace {

constexpr const char* kDirections[3] = {"x", "y", "z"};

const char* LineKindName(WhineLineKind kind) {
  switch (kind) {
    case WhineLineKind::kMeshOrder:
      return "mesh_order";
    case WhineLineKind::kSideband:
      return "sideband";
    case WhineLineKind::kShaftOrder:
      return "shaft_order";
    case WhineLineKind::kExcitation:
      return "excitation";
  }
  return "";
}

std::vector<double> SpeedsRpm(const WhineResult& r) {
  std::vector<double> rpm;
  for (double w : r.speed_rad_s) rpm.push_back(Rpm(w));
  return rpm;
}

// The largest value of `values` and the speed (rad/s) it is at.
std::pair<double, double> Peak(const std::vector<double>& values, const WhineResult& r) {
  const auto it = std::max_element(values.begin(), values.end());
  return {*it, r.speed_rad_s[static_cast<size_t>(it - values.begin())]};
}

// Speed ranges flagged for contact loss, "1200-1350, 4000" in the user's unit.
std::string FlaggedRanges(const WhineMesh& m, const WhineResult& r, const DisplayUnit& unit) {
  std::vector<std::string> parts;
  const size_t n = r.speed_rad_s.size();
  for (size_t s = 0; s < n; ++s) {
    if (!m.contact_loss[s]) continue;
    size_t e = s;
    while (e + 1 < n && m.contact_loss[e + 1]) ++e;
    const std::string a = Significant(r.speed_rad_s[s] * unit.per_si, 5);
    parts.push_back(e == s ? a : a + "-" + Significant(r.speed_rad_s[e] * unit.per_si, 5));
    s = e;
  }
  std::string text;
  for (size_t i = 0; i < parts.size(); ++i) text += (i ? ", " : "") + parts[i];
  return text;
}

void PrintWhine(const WhineResult& r, const TrainSpec& spec, const std::string& file) {
  const DisplayUnit& unit = spec.operating.speed_unit;
  fmt::print("{}  ({}), {}: whine, mean mesh stiffness, {} DOF, {} speeds of {} from {} to {} {}\n",
             spec.name, file, TierName(r.tier), r.dof, r.speed_rad_s.size(),
             spec.operating.input_shaft, Significant(r.speed_rad_s.front() * unit.per_si, 5),
             Significant(r.speed_rad_s.back() * unit.per_si, 5), unit.symbol);
  for (const WhineMesh& m : r.meshes) {
    fmt::print("\n  mesh {} ({} flank, static force {} N, mean stiffness {:.4g} N/m)\n", m.name,
               m.back_flank_loaded ? "back" : "drive", Significant(m.static_force, 5),
               m.mean_stiffness);
    fmt::print("  {:>10}  {:<36}{:>14}{:>12}{:>14}{:>12}\n", "order", "line", "peak TE µm",
               "at " + unit.symbol, "peak force N", "at " + unit.symbol);
    for (size_t l = 0; l < r.lines.size(); ++l) {
      const auto [te, te_at] = Peak(m.te_amplitude_m[l], r);
      const auto [f, f_at] = Peak(m.force_amplitude_n[l], r);
      if (te == 0.0 && f == 0.0) continue;
      fmt::print("  {:>10.6g}  {:<36}{:>14.6f}{:>12}{:>14.4g}{:>12}\n", r.lines[l].order,
                 r.lines[l].label, te * 1e6, Significant(te_at * unit.per_si, 5), f,
                 Significant(f_at * unit.per_si, 5));
    }
    const std::string flagged = FlaggedRanges(m, r, unit);
    if (!flagged.empty())
      fmt::print("  may lose contact (sum of force amplitudes >= static force) at {} {}\n", flagged,
                 unit.symbol);
  }
  if (!r.critical_speeds.empty()) {
    fmt::print(
        "\n  critical speeds, ranked by the mode's strain energy in the meshes (mean model, "
        "at rest)\n  {:>10} {:<8}{:>10}  {:<36}{:>10}\n",
        unit.symbol, "mode", "Hz", "line", "meshes %");
    for (size_t k = 0; k < std::min<size_t>(r.critical_speeds.size(), 12); ++k) {
      const WhineCriticalSpeed& c = r.critical_speeds[k];
      fmt::print("  {:>10} {:<8}{:>10.1f}  {:<36}{:>10.1f}\n",
                 Significant(c.speed_rad_s * unit.per_si, 5), c.mode + 1,
                 r.modes[c.mode].frequency_hz, r.lines[c.line].label,
                 100.0 * r.modes[c.mode].MeshEnergy());
    }
    if (r.critical_speeds.size() > 12)
      fmt::print("  ... {} more in the JSON\n", r.critical_speeds.size() - 12);
  }
  if (r.housing) {
    fmt::print(
        "\n  housing point ({}): peak acceleration over the speeds the table covers, dB re "
        "1e-6 m/s²\n",
        r.housing->source);
    for (size_t l = 0; l < r.lines.size(); ++l) {
      const std::vector<double>& a = r.housing->acceleration_m_s2[l];
      size_t at = a.size();
      for (size_t s = 0; s < a.size(); ++s) {
        if (!std::isnan(a[s]) && (at == a.size() || a[s] > a[at])) at = s;
      }
      if (at == a.size()) {
        fmt::print("  {:>10.6g}  {:<36}  outside the table's frequencies\n", r.lines[l].order,
                   r.lines[l].label);
      } else if (a[at] > 0.0) {
        fmt::print("  {:>10.6g}  {:<36}{:>10.1f} dB at {} {}\n", r.lines[l].order, r.lines[l].label,
                   20.0 * std::log10(a[at] / 1e-6), Significant(r.speed_rad_s[at] * unit.per_si, 5),
                   unit.symbol);
      } else {
        fmt::print("  {:>10.6g}  {:<36}  no response (its curves carry no force)\n",
                   r.lines[l].order, r.lines[l].label);
      }
    }
  }
  if (!r.bearings.empty()) {
    fmt::print("\n  bearings: peak force amplitude on the housing over the speeds, N\n");
    fmt::print("  {:<24}{:>10}  {:<36}{:>12}{:>12}{:>12}\n", "bearing", "order", "line", "x", "y",
               "z");
    for (const WhineBearing& b : r.bearings) {
      for (size_t l = 0; l < r.lines.size(); ++l) {
        const auto& f = b.force_amplitude_n[l];
        const double x = Peak(f[0], r).first, y = Peak(f[1], r).first, z = Peak(f[2], r).first;
        if (x == 0.0 && y == 0.0 && z == 0.0) continue;
        fmt::print("  {:<24}{:>10.6g}  {:<36}{:>12.4g}{:>12.4g}{:>12.4g}\n", WhineBearingName(b),
                   r.lines[l].order, r.lines[l].label, x, y, z);
      }
    }
  }
}

}  // namespace

std::string WhineBearingName(const WhineBearing& b) { return BearingName(b.shaft, b.index); }

std::string WhineMeshesCsv(const WhineResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "speed_rpm,mesh,order,line,te_amplitude_m,force_amplitude_n,contact_loss\n";
  const std::vector<double> rpm = SpeedsRpm(r);
  for (size_t s = 0; s < rpm.size(); ++s) {
    for (const WhineMesh& m : r.meshes) {
      for (size_t l = 0; l < r.lines.size(); ++l) {
        os << rpm[s] << ',' << m.name << ',' << r.lines[l].order << ",\"" << r.lines[l].label
           << "\"," << m.te_amplitude_m[l][s] << ',' << m.force_amplitude_n[l][s] << ','
           << (m.contact_loss[s] ? 1 : 0) << '\n';
      }
    }
  }
  return os.str();
}

std::string WhineBearingsCsv(const WhineResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "speed_rpm,bearing,at_m,order,line,force_x_n,force_y_n,force_z_n\n";
  const std::vector<double> rpm = SpeedsRpm(r);
  for (size_t s = 0; s < rpm.size(); ++s) {
    for (const WhineBearing& b : r.bearings) {
      for (size_t l = 0; l < r.lines.size(); ++l) {
        os << rpm[s] << ',' << WhineBearingName(b) << ',' << b.at << ',' << r.lines[l].order
           << ",\"" << r.lines[l].label << '"';
        for (int d = 0; d < 3; ++d) os << ',' << b.force_amplitude_n[l][static_cast<size_t>(d)][s];
        os << '\n';
      }
    }
  }
  return os.str();
}

namespace {

// dB re 1e-6 m/s^2.
double AccelerationDb(double a) { return 20.0 * std::log10(a / 1e-6); }

// Values, null where NaN (a line outside the housing table).
nlohmann::json OrNull(const std::vector<double>& values, bool db) {
  nlohmann::json out = nlohmann::json::array();
  for (double v : values) {
    // No level for no response (outside the table: NaN; a curve carrying no force: 0).
    const bool none = std::isnan(v) || (db && !(v > 0.0));
    out.push_back(none ? nlohmann::json(nullptr) : nlohmann::json(db ? AccelerationDb(v) : v));
  }
  return out;
}

// The housing point's response per line ([speed] arrays, null outside the table), or null.
nlohmann::json HousingJson(const WhineResult& r) {
  if (!r.housing) return nullptr;
  nlohmann::json orders = nlohmann::json::array();
  for (size_t l = 0; l < r.lines.size(); ++l) {
    orders.push_back({{"order", r.lines[l].order},
                      {"acceleration_m_s2", OrNull(r.housing->acceleration_m_s2[l], false)},
                      {"db_re_1e-6_m_s2", OrNull(r.housing->acceleration_m_s2[l], true)}});
  }
  return {{"file", r.housing->source}, {"orders", orders}};
}

nlohmann::json ModesJson(const WhineResult& r) {
  nlohmann::json modes = nlohmann::json::array();
  for (const WhineMode& m : r.modes) {
    nlohmann::json meshes, bearings = nlohmann::json::object();
    for (size_t i = 0; i < r.meshes.size(); ++i) meshes[r.meshes[i].name] = m.mesh_energy[i];
    for (size_t b = 0; b < r.bearings.size(); ++b)
      bearings[WhineBearingName(r.bearings[b])] = m.bearing_energy[b];
    modes.push_back(
        {{"frequency_hz", m.frequency_hz}, {"mesh_energy", meshes}, {"bearing_energy", bearings}});
  }
  return modes;
}

nlohmann::json CriticalSpeedsJson(const WhineResult& r) {
  nlohmann::json out = nlohmann::json::array();
  for (const WhineCriticalSpeed& c : r.critical_speeds) {
    out.push_back({{"speed_rpm", Rpm(c.speed_rad_s)},
                   {"order", r.lines[c.line].order},
                   {"line", r.lines[c.line].label},
                   {"mode", c.mode + 1},
                   {"frequency_hz", r.modes[c.mode].frequency_hz},
                   {"mesh_energy", r.modes[c.mode].MeshEnergy()}});
  }
  return out;
}

}  // namespace

std::string WhineHousingCsv(const WhineResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "speed_rpm,order,line,acceleration_m_s2,db_re_1e-6_m_s2\n";
  const std::vector<double> rpm = SpeedsRpm(r);
  for (size_t s = 0; s < rpm.size(); ++s) {
    for (size_t l = 0; l < r.lines.size(); ++l) {
      const double a = r.housing->acceleration_m_s2[l][s];
      os << rpm[s] << ',' << r.lines[l].order << ",\"" << r.lines[l].label << "\",";
      if (std::isnan(a)) {
        os << ',';
      } else {
        os << a << ',';
        if (a > 0.0) os << AccelerationDb(a);
      }
      os << '\n';
    }
  }
  return os.str();
}

nlohmann::json WhineJson(const WhineResult& r) {
  nlohmann::json lines = nlohmann::json::array();
  for (const WhineLine& l : r.lines)
    lines.push_back({{"order", l.order}, {"kind", LineKindName(l.kind)}, {"label", l.label}});
  nlohmann::json meshes = nlohmann::json::array();
  for (const WhineMesh& m : r.meshes) {
    nlohmann::json orders = nlohmann::json::array();
    for (size_t l = 0; l < r.lines.size(); ++l) {
      orders.push_back({{"order", r.lines[l].order},
                        {"te_amplitude_m", m.te_amplitude_m[l]},
                        {"force_amplitude_n", m.force_amplitude_n[l]}});
    }
    meshes.push_back({{"name", m.name},
                      {"loaded_flank", m.back_flank_loaded ? "back" : "drive"},
                      {"static_force_n", m.static_force},
                      {"mean_stiffness_n_per_m", m.mean_stiffness},
                      {"force_amplitude_sum_n", m.force_amplitude_sum_n},
                      {"contact_loss", m.contact_loss},
                      {"orders", orders}});
  }
  nlohmann::json bearings = nlohmann::json::array();
  for (const WhineBearing& b : r.bearings) {
    nlohmann::json orders = nlohmann::json::array();
    for (size_t l = 0; l < r.lines.size(); ++l) {
      nlohmann::json force;
      for (int d = 0; d < 3; ++d)
        force[kDirections[d]] = b.force_amplitude_n[l][static_cast<size_t>(d)];
      orders.push_back({{"order", r.lines[l].order}, {"force_amplitude_n", force}});
    }
    bearings.push_back({{"name", WhineBearingName(b)},
                        {"shaft", b.shaft},
                        {"index", b.index},
                        {"at_m", b.at},
                        {"orders", orders}});
  }
  nlohmann::json bodies = nlohmann::json::array();
  for (const WhineBody& b : r.bodies) {
    nlohmann::json orders = nlohmann::json::array();
    for (size_t l = 0; l < r.lines.size(); ++l) {
      orders.push_back(
          {{"order", r.lines[l].order}, {"speed_amplitude_rad_s", b.speed_amplitude_rad_s[l]}});
    }
    bodies.push_back({{"name", b.name}, {"orders", orders}});
  }
  return {{"model", "mean"},
          {"tier", TierName(r.tier)},
          {"dof", r.dof},
          {"speeds_rpm", SpeedsRpm(r)},
          {"speed_scale", r.speed_scale == AxisScale::kLog ? "log" : "linear"},
          {"lines", lines},
          {"meshes", meshes},
          {"bearings", bearings},
          {"shafts", bodies},
          {"modes", ModesJson(r)},
          {"critical_speeds", CriticalSpeedsJson(r)},
          {"housing", HousingJson(r)},
          {"contact_loss_speeds", r.ContactLossSpeeds()},
          {"warnings", r.warnings}};
}

int RunWhineCommand(const WhineCommandOptions& options) {
  return RunReportingErrors(options.file, [&](config::SourceLocations& where) -> int {
    const config::LoadedGearbox loaded = config::LoadAnyGearboxFile(options.file);
    where = loaded.locations;
    const TrainSpec& spec = loaded.train;
    WhineOptions whine;
    whine.tier = CheckTrainCommandOptions(options.tier, spec, LadderMethod::kFused).tier;
    whine.speeds = options.speeds;
    whine.mesh_harmonics = options.harmonics;
    whine.sideband_orders = options.sidebands;
    whine.threads = options.jobs;
    if (options.housing) whine.housing = ReadHousingTable(*options.housing);
    if (options.uff && spec.analysis.speed_sweep.scale == AxisScale::kLog) {
      throw InputError("--uff", 0, *options.uff,
                       "needs a linearly spaced analysis.speed_sweep (dataset 58's abscissa is "
                       "even); this one has scale: log");
    }
    const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", true);
    const bool on_terminal = ::isatty(STDERR_FILENO) != 0;
    WhineProgress progress;
    if (on_terminal) {
      progress = [](int done, int total) {
        if (done % 50 == 0 || done == total)
          fmt::print(stderr, "\rwhine: {:3d}% ({}/{} speeds)", 100 * done / total, done, total);
      };
    }
    const WhineResult result = RunWhine(spec, whine, progress);
    if (on_terminal) fmt::print(stderr, "\n");
    for (const std::string& w : result.warnings) std::cerr << "warning: " << w << "\n";
    nlohmann::json doc = WhineJson(result);
    doc["name"] = spec.name;
    doc["file"] = options.file;
    doc["input_shaft"] = spec.operating.input_shaft;
    RequireFinite(doc, "whine");
    if (out) {
      out->Write("whine.json", doc.dump(1) + "\n");
      out->Write("whine_meshes.csv", WhineMeshesCsv(result));
      if (!result.bearings.empty()) out->Write("whine_bearings.csv", WhineBearingsCsv(result));
      if (result.housing) out->Write("whine_housing.csv", WhineHousingCsv(result));
      out->Commit();
    }
    if (options.uff && !WriteUffFile(*options.uff, WhineOrderTracksUff(spec, result))) {
      fmt::print(stderr,
                 "note: --uff {}: not written ({} unchanged): UFF58 order tracks need evenly "
                 "spaced speeds, and analysis.speed_sweep is log-spaced\n",
                 *options.uff, *options.uff);
    }
    if (options.json) {
      std::cout << doc.dump(1) << "\n";
    } else {
      PrintWhine(result, spec, options.file);
    }
    return 0;
  });
}

}  // namespace gearnvh::app
