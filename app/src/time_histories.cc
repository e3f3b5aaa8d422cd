#include "time_histories.h"

#include <fmt/format.h>

#include <sstream>

#include "gearnvh/solver/segment_tables.h"
#include "result_documents.h"

namespace gearnvh::app {

void WriteTrajectoryCsv(const Trajectory& t, std::FILE* f) {
  fmt::print(f, "time_s,te_m,mesh_force_n,pinion_speed_rad_s,wheel_speed_rad_s,contact\n");
  for (const TrajectorySample& s : t.samples) {
    fmt::print(f, "{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{}\n", s.time, s.te, s.mesh_force,
               s.pinion_speed, s.wheel_speed, ContactStateName(s.state));
  }
}

std::string EventsCsv(const Trajectory& t) {
  std::ostringstream os;
  os.precision(17);
  os << "time_s,from,to,gap_rate_m_s\n";
  for (const EventRecord& e : t.events) {
    os << e.time << ',' << ContactStateName(e.from) << ',' << ContactStateName(e.to) << ','
       << e.gap_rate << '\n';
  }
  return os.str();
}

void WriteTrainTrajectoryCsv(const TrainHistories& h, const TrainTables& tables,
                             const TrainSpec& spec, std::FILE* f) {
  fmt::print(f, "time_s");
  for (int i = 0; i < tables.gear_meshes; ++i)
    fmt::print(f, ",{0}.te_m,{0}.mesh_force_n,{0}.contact",
               tables.meshes[static_cast<size_t>(i)].name);
  const bool bearings = !h.bearing_force.empty();
  for (size_t b = 0; bearings && b < tables.bearings.size(); ++b) {
    const StructureBearing& sb = tables.bearings[b];
    fmt::print(f, ",{0}.force_x_n,{0}.force_y_n,{0}.force_z_n",
               BearingName(spec.shafts[static_cast<size_t>(sb.shaft)].name, sb.index));
  }
  for (size_t c = 0; c < h.coupling_twist.size(); ++c)
    fmt::print(f, ",{0}.twist_rad,{0}.torque_n_m", spec.couplings[c].name);
  fmt::print(f, "\n");
  const size_t samples = h.te.empty() ? 0 : h.te.front().size();
  for (size_t k = 0; k < samples; ++k) {
    fmt::print(f, "{:.17g}", h.start + static_cast<double>(k) * h.dt);
    for (size_t i = 0; i < h.te.size(); ++i) {
      fmt::print(f, ",{:.17g},{:.17g},{}", h.te[i][k], h.force[i][k],
                 ContactStateName(h.contact[i][k]));
    }
    for (const std::vector<double>& row : h.bearing_force) fmt::print(f, ",{:.17g}", row[k]);
    for (size_t c = 0; c < h.coupling_twist.size(); ++c)
      fmt::print(f, ",{:.17g},{:.17g}", h.coupling_twist[c][k], h.coupling_torque[c][k]);
    fmt::print(f, "\n");
  }
}

std::string TrainEventsCsv(const TrainHistories& h, const TrainTables& tables) {
  std::ostringstream os;
  os.precision(17);
  os << "time_s,mesh,from,to,gap_rate_m_s\n";
  for (const TrainEventRecord& e : h.events) {
    os << e.event.time << ',' << tables.meshes[static_cast<size_t>(e.mesh)].name << ','
       << ContactStateName(e.event.from) << ',' << ContactStateName(e.event.to) << ','
       << e.event.gap_rate << '\n';
  }
  return os.str();
}

}  // namespace gearnvh::app
