#include "atlas_documents.h"

#include <map>
#include <sstream>
#include <stdexcept>

#include "display_units.h"
#include "finite_results.h"
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
          {"lyapunov_per_s", ResultOrNull(c.ok, c.lyapunov_per_s)},
          {"lyapunov_per_forcing_cycle", ResultOrNull(c.ok, c.lyapunov_per_forcing_cycle)},
          {"lyapunov_standard_error", ResultOrNull(c.ok, c.lyapunov_standard_error)},
          {"drive_impacts_per_cycle", ResultOrNull(c.ok, c.drive_impacts_per_cycle)},
          {"back_impacts_per_cycle", ResultOrNull(c.ok, c.back_impacts_per_cycle)},
          {"rattle_index_j", ResultOrNull(c.ok, c.rattle_index)},
          {"impact_velocity_rms", ResultOrNull(c.ok, c.impact_velocity_rms)},
          {"separation_fraction", ResultOrNull(c.ok, c.separation_fraction)},
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
  c.lyapunov_per_s = ResultFromJson(j.at("lyapunov_per_s"));
  c.lyapunov_per_forcing_cycle = ResultFromJson(j.at("lyapunov_per_forcing_cycle"));
  c.lyapunov_standard_error = ResultFromJson(j.at("lyapunov_standard_error"));
  c.drive_impacts_per_cycle = ResultFromJson(j.at("drive_impacts_per_cycle"));
  c.back_impacts_per_cycle = ResultFromJson(j.at("back_impacts_per_cycle"));
  c.rattle_index = ResultFromJson(j.at("rattle_index_j"));
  c.impact_velocity_rms = ResultFromJson(j.at("impact_velocity_rms"));
  c.separation_fraction = ResultFromJson(j.at("separation_fraction"));
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
       << (c.ok ? 1 : 0) << ',';
    // A failed cell's results are empty fields.
    for (double v : {c.lyapunov_per_s, c.lyapunov_per_forcing_cycle, c.lyapunov_standard_error,
                     c.drive_impacts_per_cycle, c.back_impacts_per_cycle, c.rattle_index,
                     c.impact_velocity_rms, c.separation_fraction}) {
      os << CsvNumber(v, 12) << ',';
    }
    os << (c.ok ? RattleRegimeName(c.regime) : "") << ',' << CsvQuoted(c.message) << '\n';
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
