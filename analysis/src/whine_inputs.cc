#include "whine_inputs.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gearnvh::whine {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
const std::complex<double> kI(0.0, 1.0);

// 2 sum_j value_j integral over [begin_j, end_j] of e^{-i a u} du, scaled by 1 / period (u in the
// unit of the period): the X_n of a piecewise-constant signal at angular rate a per unit u.
std::complex<double> PiecewiseCoefficient(const std::vector<double>& begin,
                                          const std::vector<double>& end,
                                          const std::vector<double>& value, double a,
                                          double period) {
  std::complex<double> sum = 0.0;
  for (size_t j = 0; j < value.size(); ++j) {
    if (value[j] == 0.0) continue;
    sum += value[j] * (std::exp(-kI * (a * begin[j])) - std::exp(-kI * (a * end[j])));
  }
  return 2.0 * sum / (kI * a * period);
}

// Gear g's pitch error over a revolution (z_g mesh cycles): in cycle c segment j the pairs'
// weighted deviations of teeth (c - q) mod z_g.
void BuildPitchSignal(const MeshInput& in, GearInput& g) {
  const long z = g.teeth;
  const size_t segments = in.static_input.size();
  for (long c = 0; c < z; ++c) {
    for (size_t j = 0; j < segments; ++j) {
      double p = 0.0;
      for (const auto& [q, weight] : in.pitch_weights[j]) {
        const long tooth = ((c - q) % z + z) % z;
        p += weight * g.pitch[static_cast<size_t>(tooth)];
      }
      g.pitch_begin.push_back(static_cast<double>(c) + in.tau_begin[j]);
      g.pitch_end.push_back(static_cast<double>(c) + in.tau_end[j]);
      g.pitch_value.push_back(p);
    }
  }
}

// X_n of gear g's pitch error (period z_g mesh cycles).
std::complex<double> PitchCoefficient(const GearInput& g, long n) {
  return PiecewiseCoefficient(g.pitch_begin, g.pitch_end, g.pitch_value,
                              kTwoPi * static_cast<double>(n) / g.teeth,
                              static_cast<double>(g.teeth));
}

// The line at `order`, merged into `lines` (a label added to an existing order).
void AddLine(std::vector<WhineLine>& lines, double order, WhineLineKind kind,
             const std::string& label) {
  if (!(order > 0.0)) return;
  for (WhineLine& l : lines) {
    if (std::abs(l.order - order) <= 1e-9 * std::max(1.0, order)) {
      // Sources are joined by " = ": compare whole entries ("2x g1" is not "2x g10").
      const std::string joined = " = " + l.label + " = ";
      if (joined.find(" = " + label + " = ") == std::string::npos) l.label += " = " + label;
      return;
    }
  }
  lines.push_back({order, kind, label});
}

}  // namespace

bool WholeMultiple(double x) {
  const double r = std::round(x);
  return r >= 1.0 && std::abs(x - r) <= 1e-9 * std::max(1.0, x);
}

std::complex<double> MeshInput::Coefficient(double order) const {
  std::complex<double> x = 0.0;
  const double k = order / mesh_order;
  if (WholeMultiple(k)) {
    x += PiecewiseCoefficient(tau_begin, tau_end, static_input, kTwoPi * std::round(k), 1.0);
  }
  for (const GearInput& g : gears) {
    const double n = order / g.order;
    if (!WholeMultiple(n)) continue;
    const long whole = std::lround(n);
    if (whole == 1 && g.runout.amplitude > 0.0)
      x += -kI * g.runout.amplitude * std::exp(kI * g.runout.phase);
    if (!g.pitch.empty()) x += PitchCoefficient(g, whole);
  }
  return x;
}

MeshInput MeshInputOf(const TrainSpec& spec, const GearTrain& train, size_t mesh) {
  const TrainMeshModel& mm = train.meshes[mesh];
  const double input_speed = spec.operating.speed;
  MeshInput in;
  const int gear_index[2] = {mm.gear_a, mm.gear_b};
  const int body[2] = {mm.body_a, mm.body_b};
  const GearSpec* gear[2] = {&mm.pair.a, &mm.pair.b};
  for (int g = 0; g < 2; ++g) {
    GearInput& gi = in.gears[g];
    gi.name = spec.gears[static_cast<size_t>(gear_index[g])].name;
    gi.teeth = gear[g]->teeth;
    gi.order = std::abs(train.topology.bodies[static_cast<size_t>(body[g])].speed) / input_speed;
    if (gear[g]->runout) gi.runout = *gear[g]->runout;
    const bool any = std::any_of(gear[g]->pitch_errors.begin(), gear[g]->pitch_errors.end(),
                                 [](double f) { return f != 0.0; });
    if (any) gi.pitch = gear[g]->pitch_errors;
  }
  in.mesh_order = in.gears[0].teeth * in.gears[0].order;
  const double load = mm.cycle.load;
  for (const MeshSegment& s : mm.segmentation.segments) {
    in.tau_begin.push_back(s.tau_begin);
    in.tau_end.push_back(s.tau_end);
    const double k = mm.back_flank_loaded ? s.back.stiffness : s.drive.stiffness;
    const double deflection = k > 0.0 ? load / k : 0.0;
    in.static_input.push_back(s.unloaded_error + (mm.back_flank_loaded ? -deflection : deflection));
    in.pitch_weights.push_back(s.error_weights);
  }
  for (GearInput& g : in.gears) {
    if (!g.pitch.empty()) BuildPitchSignal(in, g);
  }
  return in;
}

std::vector<std::complex<double>> BodyTorques(const TrainSpec& spec, const GearTrain& train,
                                              double order) {
  std::vector<std::complex<double>> x;
  for (size_t i = 0; i < spec.operating.excitation.size(); ++i) {
    const ExcitationOrder& e = spec.operating.excitation[i];
    if (std::abs(ExcitationOrderOfInput(spec, train.topology, i) - order) >
        1e-9 * std::max(1.0, order))
      continue;
    const auto body = static_cast<size_t>(ExcitationBody(spec, train.topology, i));
    const double torque =
        e.kind == ExcitationKind::kTorque ? e.amplitude : train.body_inertia[body] * e.amplitude;
    x.resize(train.topology.bodies.size(), 0.0);
    x[body] += -kI * torque * std::exp(kI * e.phase);
  }
  return x;
}

std::vector<WhineLine> Lines(const TrainSpec& spec, const GearTrain& train,
                             const std::vector<MeshInput>& inputs, const WhineOptions& options) {
  std::vector<WhineLine> lines;
  for (size_t i = 0; i < inputs.size(); ++i) {
    for (int k = 1; k <= options.mesh_harmonics; ++k) {
      AddLine(lines, k * inputs[i].mesh_order, WhineLineKind::kMeshOrder,
              fmt::format("{}x mesh {}", k, train.meshes[i].name));
    }
  }
  for (size_t i = 0; i < spec.operating.excitation.size(); ++i) {
    const ExcitationOrder& e = spec.operating.excitation[i];
    AddLine(lines, ExcitationOrderOfInput(spec, train.topology, i), WhineLineKind::kExcitation,
            e.on.empty() ? fmt::format("excitation {:g}x", e.order)
                         : fmt::format("excitation {:g}x {}", e.order, e.on));
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    for (const GearInput& g : inputs[i].gears) {
      if (g.runout.amplitude > 0.0)
        AddLine(lines, g.order, WhineLineKind::kShaftOrder, fmt::format("1x {}", g.name));
      if (g.pitch.empty()) continue;
      for (int j = 1; j <= options.sideband_orders; ++j) {
        AddLine(lines, j * g.order, WhineLineKind::kShaftOrder, fmt::format("{}x {}", j, g.name));
        for (int k = 1; k <= options.mesh_harmonics; ++k) {
          const double mesh = k * inputs[i].mesh_order;
          const std::string name = train.meshes[i].name;
          AddLine(lines, mesh - j * g.order, WhineLineKind::kSideband,
                  fmt::format("{}x mesh {} - {}x {}", k, name, j, g.name));
          AddLine(lines, mesh + j * g.order, WhineLineKind::kSideband,
                  fmt::format("{}x mesh {} + {}x {}", k, name, j, g.name));
        }
      }
    }
  }
  std::sort(lines.begin(), lines.end(),
            [](const WhineLine& a, const WhineLine& b) { return a.order < b.order; });
  return lines;
}

}  // namespace gearnvh::whine
