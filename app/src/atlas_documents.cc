#include "atlas_documents.h"

#include <map>
#include <sstream>
#include <stdexcept>

#include "display_units.h"
#include "gearnvh/nvh/rattle.h"

namespace gearnvh::app {

nlohmann::json AtlasAxisJson(const AtlasAxis& a) {
  nlohmann::json values = nlohmann::json::array();
  for (int i = 0; i < a.range.points; ++i) values.push_back(AxisValue(a, i));
  return {{"parameter", a.parameter},
          {"from", a.range.from},
          {"to", a.range.to},
          {"points", a.range.points},
          {"scale", a.range.scale == AxisScale::kLog ? "log" : "linear"},
          {"values_si", values}};
}

nlohmann::json AtlasCellJson(const AtlasCell& c) {
  return {{"ix", c.ix},
          {"iy", c.iy},
          {"x", c.x},
          {"y", c.y},
          {"ok", c.ok},
          {"message", c.message},
          {"lyapunov_per_s", c.lyapunov_per_s},
          {"lyapunov_per_forcing_cycle", c.lyapunov_per_forcing_cycle},
          {"lyapunov_standard_error", c.lyapunov_standard_error},
          {"drive_impacts_per_cycle", c.drive_impacts_per_cycle},
          {"back_impacts_per_cycle", c.back_impacts_per_cycle},
          {"rattle_index_j", c.rattle_index},
          {"impact_velocity_rms", c.impact_velocity_rms},
          {"separation_fraction", c.separation_fraction},
          {"regime", c.ok ? RattleRegimeName(c.regime) : ""},
          {"wall_s", c.wall_s}};
}

AtlasCell AtlasCellFromJson(const nlohmann::json& j) {
  AtlasCell c;
  c.ix = j.at("ix").get<int>();
  c.iy = j.at("iy").get<int>();
  c.x = j.at("x").get<double>();
  c.y = j.at("y").get<double>();
  c.ok = j.at("ok").get<bool>();
  c.message = j.at("message").get<std::string>();
  c.lyapunov_per_s = j.at("lyapunov_per_s").get<double>();
  c.lyapunov_per_forcing_cycle = j.at("lyapunov_per_forcing_cycle").get<double>();
  c.lyapunov_standard_error = j.at("lyapunov_standard_error").get<double>();
  c.drive_impacts_per_cycle = j.at("drive_impacts_per_cycle").get<double>();
  c.back_impacts_per_cycle = j.at("back_impacts_per_cycle").get<double>();
  c.rattle_index = j.at("rattle_index_j").get<double>();
  c.impact_velocity_rms = j.at("impact_velocity_rms").get<double>();
  c.separation_fraction = j.at("separation_fraction").get<double>();
  if (c.ok) c.regime = RegimeFromJson(j.at("regime"));
  c.wall_s = j.at("wall_s").get<double>();
  return c;
}

nlohmann::json AtlasJson(const AtlasResult& r, const AtlasOptions& o) {
  nlohmann::json cells = nlohmann::json::array();
  std::map<std::string, int> regimes;
  for (const AtlasCell& c : r.cells) {
    cells.push_back(AtlasCellJson(c));
    ++regimes[c.ok ? RattleRegimeName(c.regime) : "failed"];
  }
  nlohmann::json doc = AtlasRunJson(regimes, r.Failed(), o, r.threads, r.wall_s);
  doc["x"] = AtlasAxisJson(r.x);
  doc["y"] = AtlasAxisJson(r.y);
  doc["cells"] = cells;
  return doc;
}

std::string AtlasCsv(const AtlasResult& r, const GearboxSpec& spec) {
  const DisplayAxis ax = DisplayAxisFor(r.x.parameter, spec);
  const DisplayAxis ay = DisplayAxisFor(r.y.parameter, spec);
  auto header = [](const std::string& parameter, const DisplayAxis& a) {
    return a.unit.empty() ? parameter : parameter + " [" + a.unit + "]";
  };
  std::ostringstream os;
  os.precision(12);
  os << "ix,iy," << header(r.x.parameter, ax) << ',' << header(r.y.parameter, ay)
     << ",ok,lyapunov_per_s,lyapunov_per_forcing_cycle,lyapunov_standard_error,"
        "drive_impacts_per_cycle,back_impacts_per_cycle,rattle_index_j,impact_velocity_rms,"
        "separation_fraction,regime,message\n";
  for (const AtlasCell& c : r.cells) {
    os << c.ix << ',' << c.iy << ',' << c.x * ax.scale << ',' << c.y * ay.scale << ','
       << (c.ok ? 1 : 0) << ',' << c.lyapunov_per_s << ',' << c.lyapunov_per_forcing_cycle << ','
       << c.lyapunov_standard_error << ',' << c.drive_impacts_per_cycle << ','
       << c.back_impacts_per_cycle << ',' << c.rattle_index << ',' << c.impact_velocity_rms << ','
       << c.separation_fraction << ',' << (c.ok ? RattleRegimeName(c.regime) : "") << ','
       << CsvQuoted(c.message) << '\n';
  }
  return os.str();
}

std::string CsvQuoted(std::string text) {
  for (char& ch : text) {
    if (ch == '"' || ch == '\n') ch = '\'';
  }
  return '"' + text + '"';
}

RattleRegime RegimeFromJson(const nlohmann::json& regime) {
  const std::string name = regime.get<std::string>();
  const std::optional<RattleRegime> r = RattleRegimeFromName(name);
  if (!r) throw std::runtime_error("unknown rattle regime \"" + name + "\"");
  return *r;
}

}  // namespace gearnvh::app
