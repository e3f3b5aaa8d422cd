#include "uff_export.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ctime>

#include "atomic_file.h"
#include "gearnvh/analysis/order_tracks.h"
#include "gearnvh/analysis/written_numbers.h"
#include "result_documents.h"

namespace gearnvh::app {
namespace {

// The data lines of a dataset 58 of n values (4E20.12: 20 characters each, a line end per 4).
size_t DataTextBytes(size_t n) { return 20 * n + (n + 3) / 4; }

// ID lines and labels are plain ASCII in fixed columns.
std::string Ascii(const std::string& s, size_t width) {
  std::string out;
  for (unsigned char c : s) {
    if (out.size() == width) break;
    out += c >= 32 && c < 127 ? static_cast<char>(c) : '_';
  }
  return out.empty() ? "NONE" : out;
}

std::string AxisRecord(const UffAxis& a) {
  return fmt::format("{:10d}{:5d}{:5d}{:5d} {:<20} {:<20}\n", a.data_type, a.length_exponent,
                     a.force_exponent, a.temperature_exponent, Ascii(a.label, 20),
                     Ascii(a.units, 20));
}

// Fortran E format: d.ddddE+xx with `digits` after the point, right-aligned in `width`.
std::string FortranE(double v, int width, int digits) {
  return fmt::format("{:>{}.{}E}", v, width, digits);
}

std::string Today() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%d-%b-%y %H:%M:%S", &tm);
  return buffer;
}

UffAxis TimeAxis() { return {17, 0, 0, 0, "time", "s"}; }
UffAxis TeAxis() { return {8, 1, 0, 0, "transmission error", "m"}; }

UffFunction Base(const std::string& gearbox, const std::string& what, int id) {
  UffFunction f;
  f.id1 = what;
  f.id2 = gearbox;
  f.id3 = Today();
  f.id4 = "gearnvh";
  f.id5 = "NONE";
  f.function_id = id;
  return f;
}

}  // namespace

std::string UffDataset58(const UffFunction& f) {
  std::string out;
  // Its whole length at once (20 characters per value, a line end per 4, ~1 KB of records): a
  // growing string would hold up to twice that while it reallocates.
  out.reserve(1024 + DataTextBytes(f.values.size()));
  out = "    -1\n    58\n";
  for (const std::string* id : {&f.id1, &f.id2, &f.id3, &f.id4, &f.id5}) {
    out += Ascii(*id, 80) + "\n";
  }
  out += fmt::format("{:5d}{:10d}{:5d}{:10d} {:<10}{:10d}{:4d} {:<10}{:10d}{:4d}\n",
                     f.function_type, f.function_id, 1, 0, Ascii(f.response_name, 10),
                     f.response_node, f.response_direction, "NONE", 0, 0);
  out += fmt::format("{:10d}{:10d}{:10d}{}{}{}\n", 4, f.values.size(), 1, FortranE(f.x_min, 13, 5),
                     FortranE(f.dx, 13, 5), FortranE(f.z_value, 13, 5));
  out +=
      AxisRecord(f.abscissa) + AxisRecord(f.ordinate) + AxisRecord(f.denominator) + AxisRecord(f.z);
  for (size_t i = 0; i < f.values.size(); ++i) {
    out += FortranE(f.values[i], 20, 11);
    if (i % 4 == 3 || i + 1 == f.values.size()) out += '\n';
  }
  out += "    -1\n";
  return out;
}

std::vector<UffFunction> MeshUff(const std::string& gearbox, MeshUffSource m, int& next_id) {
  std::vector<UffFunction> out;
  const std::string of = m.label.empty() ? "" : ", mesh " + m.label;
  if (m.te.size() >= 2) {
    UffFunction te = Base(gearbox, "dynamic transmission error" + of, next_id++);
    te.function_type = 1;
    te.response_name = "TE";
    te.response_node = m.node;
    te.abscissa = TimeAxis();
    te.ordinate = TeAxis();
    te.x_min = m.start;
    te.dx = m.dt;
    UffFunction force = te;
    force.id1 = "mesh force (drive flank positive)" + of;
    force.function_id = next_id++;
    force.response_name = "MESH";
    force.ordinate = {9, 0, 1, 0, "mesh force", "N"};
    te.values = std::move(m.te);
    force.values = std::move(m.force);
    out.push_back(std::move(te));
    out.push_back(std::move(force));
  }
  if (!m.spectrum.amplitude.empty()) {
    UffFunction s =
        Base(gearbox, fmt::format("TE amplitude spectrum, Hann, {}{}", m.spectrum_window, of),
             next_id++);
    s.function_type = 12;
    s.response_name = "TE";
    s.response_node = m.node;
    s.abscissa = {18, 0, 0, 0, "frequency", "Hz"};
    s.ordinate = TeAxis();
    s.x_min = 0.0;
    s.dx = m.spectrum.bin_hz;
    s.values = std::move(m.spectrum.amplitude);
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<UffFunction> OperatingPointUff(const GearboxSpec& spec,
                                           const OperatingPointAnalysis& op, int first_id) {
  MeshUffSource mesh;
  const std::vector<TrajectorySample>& samples = op.result.trajectory.samples;
  if (!samples.empty()) mesh.start = samples.front().time;
  mesh.dt = op.tables.mesh_period / op.solver.samples_per_cycle;
  mesh.te.reserve(samples.size());
  mesh.force.reserve(samples.size());
  for (const TrajectorySample& s : samples) {
    mesh.te.push_back(s.te);
    mesh.force.push_back(s.mesh_force);
  }
  mesh.spectrum = op.spectrum;
  mesh.spectrum_window = fmt::format("{} mesh cycles", op.sideband_window);
  return MeshUff(spec.name, std::move(mesh), first_id);
}

namespace {

// A bearing's force on the housing in x, y, z (response node: its number from 1, direction
// 1..3): its time history (2 samples or more) and its window spectrum (when there is one).
void AppendBearingUff(const TrainSpec& spec, const TrainOperatingPoint& op, int& next_id,
                      std::vector<UffFunction>& out) {
  const TrainHistories& h = op.histories;
  constexpr std::array<char, 3> kAxis{'x', 'y', 'z'};
  for (size_t b = 0; b < op.bearing_forces.size(); ++b) {
    const TrainBearingForce& bearing = op.bearing_forces[b];
    const std::string name = BearingName(
        spec.shafts[static_cast<size_t>(bearing.bearing.shaft)].name, bearing.bearing.index);
    for (size_t d = 0; d < 3; ++d) {
      UffFunction f = Base(spec.name, fmt::format("bearing force {}, {}", kAxis[d], name), 0);
      f.response_name = "BRG";
      f.response_node = static_cast<int>(b) + 1;
      f.response_direction = static_cast<int>(d) + 1;
      f.ordinate = {9, 0, 1, 0, "bearing force", "N"};
      const size_t row = 3 * b + d;
      if (row < h.bearing_force.size() && h.bearing_force[row].size() >= 2) {
        UffFunction history = f;
        history.function_id = next_id++;
        history.function_type = 1;
        history.abscissa = TimeAxis();
        history.x_min = h.start;
        history.dx = h.dt;
        history.values = h.bearing_force[row];
        out.push_back(std::move(history));
      }
      const AmplitudeSpectrum& s = bearing.spectrum[d];
      if (s.amplitude.empty()) continue;
      UffFunction spectrum = f;
      spectrum.id1 = fmt::format("bearing force {} amplitude spectrum, Hann, {}", kAxis[d], name);
      spectrum.function_id = next_id++;
      spectrum.function_type = 12;
      spectrum.abscissa = {18, 0, 0, 0, "frequency", "Hz"};
      spectrum.x_min = 0.0;
      spectrum.dx = s.bin_hz;
      spectrum.values = s.amplitude;
      out.push_back(std::move(spectrum));
    }
  }
}

// A coupling's twist and torque time histories (response "CPL", node: its number from 1,
// direction 6: about the shaft axis), when the histories hold them (2 samples or more).
void AppendCouplingUff(const TrainSpec& spec, const TrainOperatingPoint& op, int& next_id,
                       std::vector<UffFunction>& out) {
  const TrainHistories& h = op.histories;
  for (size_t c = 0; c < h.coupling_twist.size(); ++c) {
    if (h.coupling_twist[c].size() < 2) continue;
    const std::string& name = spec.couplings[c].name;
    const std::pair<const std::vector<double>*, UffAxis> rows[] = {
        {&h.coupling_twist[c], UffAxis{8, 0, 0, 0, "coupling twist", "rad"}},
        {&h.coupling_torque[c], UffAxis{9, 1, 1, 0, "coupling torque", "N m"}}};
    for (const auto& [values, axis] : rows) {
      UffFunction f = Base(spec.name, axis.label + ", " + name, next_id++);
      f.function_type = 1;
      f.response_name = "CPL";
      f.response_node = static_cast<int>(c) + 1;
      f.response_direction = 6;
      f.abscissa = TimeAxis();
      f.ordinate = axis;
      f.x_min = h.start;
      f.dx = h.dt;
      f.values = *values;
      out.push_back(std::move(f));
    }
  }
}

}  // namespace

std::vector<UffFunction> TrainOperatingPointUff(const TrainSpec& spec,
                                                const TrainOperatingPoint& op, int first_id) {
  std::vector<UffFunction> out;
  const TrainHistories& h = op.histories;
  for (size_t i = 0; i < static_cast<size_t>(op.tables.gear_meshes); ++i) {
    MeshUffSource mesh;
    mesh.label = op.tables.meshes[i].name;
    mesh.node = static_cast<int>(i) + 1;
    mesh.start = h.start;
    mesh.dt = h.dt;
    if (i < h.te.size()) {
      mesh.te = h.te[i];
      mesh.force = h.force[i];
    }
    if (i < op.sidebands.size()) {
      mesh.spectrum = op.sidebands[i].spectrum;
      mesh.spectrum_window = fmt::format("{} mesh cycles", op.sidebands[i].window_cycles);
    }
    for (UffFunction& f : MeshUff(spec.name, std::move(mesh), first_id))
      out.push_back(std::move(f));
  }
  AppendBearingUff(spec, op, first_id, out);
  AppendCouplingUff(spec, op, first_id, out);
  return out;
}

namespace {

// Order tracks as dataset 58 over an even speed axis (`reference`: the shaft whose speed and
// orders they are on); none unless every speed succeeded (`all_ok`: even spacing needs every
// speed), with fewer than 2 speeds, or when the sweep is log-spaced (its tracks are in the
// report's order_tracks.csv only). An order beyond the waterfall's order range reads as 0.
// The tracks over the speeds whose run succeeded (`ok` per speed): one dataset per track and run
// of consecutive such speeds (a dataset's abscissa is even), ID line 5 saying which speeds it
// holds when a speed failed.
void AppendOrderTracksUff(const std::string& gearbox, const std::vector<OrderTrack>& tracks,
                          const std::vector<bool>& ok, AxisScale scale,
                          const std::string& reference, const std::string& mesh, int& next_id,
                          std::vector<UffFunction>& out) {
  if (tracks.empty() || scale == AxisScale::kLog) return;
  const std::vector<double>& speeds = tracks.front().speed_rpm;
  if (speeds.size() < 2) return;
  const auto failed = static_cast<size_t>(std::count(ok.begin(), ok.end(), false));
  int k = 0;
  for (const OrderTrack& track : tracks) {
    ++k;
    for (size_t from = 0; from < speeds.size(); ++from) {
      if (!ok[from]) continue;
      size_t to = from;
      while (to < speeds.size() && ok[to]) ++to;
      UffFunction f = Base(gearbox,
                           fmt::format("order track: TE at mesh order {}{} ({} order {:g})", k,
                                       mesh.empty() ? "" : " of " + mesh, reference, track.order),
                           next_id++);
      if (failed > 0) {
        f.id5 = fmt::format("speeds {:g} to {:g} rpm only: {} of {} speeds failed", speeds[from],
                            speeds[to - 1], failed, speeds.size());
      }
      f.function_type = 12;
      f.response_name = "TE";
      f.abscissa = {19, 0, 0, 0, reference + " speed", "rpm"};
      f.ordinate = TeAxis();
      f.z = {20, 0, 0, 0, reference + " order", "NONE"};
      f.z_value = track.order;
      f.x_min = speeds[from];
      f.dx = speeds[1] - speeds[0];
      for (size_t i = from; i < to; ++i) {
        const double a = track.amplitude_m[i];
        f.values.push_back(std::isfinite(a) ? a : 0.0);
      }
      out.push_back(std::move(f));
      from = to;
    }
  }
}

}  // namespace

std::vector<UffFunction> SweepOrderTracksUff(const GearboxSpec& spec, const SpeedSweepResult& sweep,
                                             int first_id) {
  std::vector<UffFunction> out;
  std::vector<bool> ok;
  for (const SpeedPoint& p : sweep.points) ok.push_back(p.ok);
  if (!(sweep.order_step > 0.0)) return out;
  // Bin k z1 / order_step = k * window cycles lies exactly on the mesh order.
  AppendOrderTracksUff(spec.name, MeshOrderTracks(PairWaterfall(sweep), spec.pinion.teeth, 3), ok,
                       sweep.speed_scale, "pinion", "", first_id, out);
  return out;
}

std::vector<UffFunction> TrainSweepOrderTracksUff(const TrainSpec& spec,
                                                  const TrainSweepResult& sweep, int first_id) {
  std::vector<UffFunction> out;
  std::vector<bool> ok;
  for (const TrainSweepPoint& p : sweep.points) ok.push_back(p.ok);
  if (!(sweep.order_step > 0.0)) return out;
  for (size_t i = 0; i < sweep.mesh_names.size(); ++i) {
    AppendOrderTracksUff(spec.name,
                         MeshOrderTracks(MeshWaterfall(sweep, i), sweep.mesh_orders[i], 3), ok,
                         sweep.speed_scale, "input", sweep.mesh_names[i], first_id, out);
  }
  return out;
}

std::vector<UffFunction> WhineOrderTracksUff(const TrainSpec& spec, const WhineResult& r,
                                             int first_id) {
  std::vector<UffFunction> out;
  if (r.speed_scale == AxisScale::kLog || r.speed_rad_s.size() < 2) return out;
  const std::string reference = spec.operating.input_shaft;
  for (size_t i = 0; i < r.meshes.size(); ++i) {
    const WhineMesh& m = r.meshes[i];
    for (size_t l = 0; l < r.lines.size(); ++l) {
      UffFunction te = Base(spec.name,
                            fmt::format("whine order track: TE at {} of {} ({} order {:g})",
                                        r.lines[l].label, m.name, reference, r.lines[l].order),
                            first_id++);
      te.function_type = 12;
      te.response_name = "TE";
      te.response_node = static_cast<int>(i) + 1;
      te.abscissa = {19, 0, 0, 0, reference + " speed", "rpm"};
      te.ordinate = TeAxis();
      te.z = {20, 0, 0, 0, reference + " order", "NONE"};
      te.z_value = r.lines[l].order;
      te.x_min = Rpm(r.speed_rad_s.front());
      te.dx = Rpm(r.speed_rad_s[1]) - Rpm(r.speed_rad_s[0]);
      UffFunction force = te;
      force.id1 = fmt::format("whine order track: mesh force at {} of {} ({} order {:g})",
                              r.lines[l].label, m.name, reference, r.lines[l].order);
      force.function_id = first_id++;
      force.response_name = "MESH";
      force.ordinate = {9, 0, 1, 0, "mesh force", "N"};
      te.values = m.te_amplitude_m[l];
      force.values = m.force_amplitude_n[l];
      out.push_back(std::move(te));
      out.push_back(std::move(force));
    }
  }
  return out;
}

bool WriteUffFile(const std::string& path, const std::vector<UffFunction>& functions) {
  if (functions.empty()) return false;
  WriteFileAtomically(path, [&functions](std::FILE* f) {
    for (const UffFunction& function : functions) {
      const std::string dataset = UffDataset58(function);
      std::fwrite(dataset.data(), 1, dataset.size(), f);
    }
  });
  return true;
}

MemoryPart OperatingPointUffMemory(long recorded_samples) {
  const auto n = static_cast<size_t>(std::max(recorded_samples, 0L));
  return {"UFF export", 2 * n * sizeof(double) + DataTextBytes(n)};
}

}  // namespace gearnvh::app
