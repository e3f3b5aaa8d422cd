#include "gearnvh/model/gearbox_spec_limits.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/mesh_pair.h"
#include "gearnvh/model/mesh_segmentation.h"

namespace gearnvh {

namespace {

using L = GearboxLimits;

void GearLimits(const GearSpec& gear, const std::string& p) {
  // A helical gear's teeth are generated on its transverse section (m_t, alpha_t, and h_a*, x
  // scaled by cos beta), so undercut (z_min = 2 h_a* cos(beta) / sin^2 alpha_t, ISO 21771) and the
  // tip thickness are those of the section.
  const GearSpec section = TransverseSection(gear);
  const GearSpec& g = section;
  const double a = g.pressure_angle, z = g.teeth, m = g.module;
  // Undercut: the generating rack's tip line cuts below the base circle (no profile shift
  // needed above z_min = 2 (h_a* - x) / sin^2 alpha); the involute-only tooth model then
  // overstates the root thickness and the contact path.
  const double z_min = 2.0 * (g.addendum_coefficient - g.profile_shift) / std::pow(std::sin(a), 2);
  if (z < z_min - 1e-9) {
    throw InputError(p + ".teeth", 0, std::to_string(g.teeth),
                     {fmt::format("is undercut at a {{}} pressure angle with profile shift "
                                  "{:.4g}: needs at least {:.3g} teeth (z >= 2 (h_a* - x) / "
                                  "sin^2 alpha), or more profile shift",
                                  g.profile_shift, z_min),
                      {InputError::Angle(a, p + ".pressure_angle", 4)}});
  }
  // Pointed teeth: the tooth thickness at the tip circle,
  // s_a = d_a ((pi/2 + 2 x tan alpha) / z + inv alpha - inv alpha_a), cos alpha_a = d_b / d_a.
  const double d = m * z, d_b = d * std::cos(a);
  const double d_a = d + 2.0 * m * (g.addendum_coefficient + g.profile_shift);
  const double alpha_a = std::acos(std::min(1.0, d_b / d_a));
  const double s_a = d_a * ((std::numbers::pi / 2.0 + 2.0 * g.profile_shift * std::tan(a)) / z +
                            Involute(a) - Involute(alpha_a));
  if (!(s_a >= L::kMinTipThickness * m)) {
    throw InputError(p + ".pressure_angle", 0, {"{}", {InputError::Angle(a)}},
                     {fmt::format("gives pointed teeth: the tip thickness is {{}}, below {} x "
                                  "module = {{}} (lower the pressure angle, the addendum or the "
                                  "profile shift)",
                                  L::kMinTipThickness),
                      {InputError::Length(s_a, p + ".module", 3),
                       InputError::Length(L::kMinTipThickness * m, p + ".module", 3)}});
  }
}

long ShaftElements(const ShaftSpec& s) {
  double min_diameter = std::numeric_limits<double>::infinity();
  for (const ShaftSegment& seg : s.segments)
    min_diameter = std::min(min_diameter, seg.outer_diameter);
  const double length = s.Length();
  // As the component model meshes it (30 elements or the thinnest diameter by default).
  const double h = s.element_length.value_or(std::min(length / 30.0, min_diameter));
  return static_cast<long>(std::ceil(length / h)) + static_cast<long>(s.segments.size()) +
         static_cast<long>(s.bearings.size() + s.inertias.size()) + 1;
}

// Lengths of a mesh against its module: the backlash against the tooth thickness, the static
// transmission error and the gears' tip relief against the module (as runout and pitch errors:
// beyond a module they describe another gear, not an error of this one).
void MeshLengthLimits(const GearboxSpec& spec) {
  const double m = spec.pinion.module;  // both gears' (equal by now)
  const double thickness = std::numbers::pi * m / 2.0;
  const double max_backlash = L::kMaxBacklashPerToothThickness * thickness;
  if (!(spec.mesh.backlash <= max_backlash)) {
    throw InputError(
        "mesh.backlash", 0, {"{}", {InputError::Length(spec.mesh.backlash)}},
        {fmt::format("must be at most {{}}, {:g} of the tooth thickness at the pitch circle (pi "
                     "m / 2 = {{}} at module {{}}): real backlash is a few hundredths of the "
                     "module (is the unit right?)",
                     L::kMaxBacklashPerToothThickness),
         {InputError::Length(max_backlash), InputError::Length(thickness),
          InputError::Length(m, "gears.pinion.module")}});
  }
  const auto within_module = [&](const std::string& path, double v) {
    if (std::abs(v) <= m) return;
    throw InputError(
        path, 0, {"{}", {InputError::Length(v)}},
        {"must be at most the module ({}) in size: a larger deviation describes another gear, "
         "not an error of this one (is the unit right?)",
         {InputError::Length(m, "gears.pinion.module")}});
  };
  const auto& ste = spec.mesh.static_transmission_error.amplitudes;
  for (size_t i = 0; i < ste.size(); ++i) {
    within_module("mesh.static_transmission_error.amplitudes[" + std::to_string(i) + "]", ste[i]);
  }
  for (const auto& [gear, path] :
       {std::pair{&spec.pinion, "gears.pinion"}, std::pair{&spec.wheel, "gears.wheel"}}) {
    if (gear->tip_relief)
      within_module(std::string(path) + ".tip_relief.amount", gear->tip_relief->amount);
    if (gear->lead) {
      within_module(std::string(path) + ".lead.crowning", gear->lead->crowning);
      within_module(std::string(path) + ".lead.end_relief.amount", gear->lead->end_relief_amount);
      within_module(std::string(path) + ".lead.slope", gear->lead->slope);
    }
  }
  within_module("mesh.misalignment", spec.mesh.misalignment);
}

}  // namespace

void RequireGearScale(const GearSpec& gear, const std::string& p) {
  if (!(gear.module >= L::kMinModule && gear.module <= L::kMaxModule)) {
    throw InputError(p + ".module", 0, {"{}", {InputError::Length(gear.module)}},
                     {"must be in [{#}, {#}] {unit}: the tooth stiffness and FE models are for "
                      "gears of that size",
                      {InputError::Length(L::kMinModule), InputError::Length(L::kMaxModule)}});
  }
  const double ratio = gear.face_width / gear.module;
  if (!(ratio >= L::kMinFaceWidthPerModule && ratio <= L::kMaxFaceWidthPerModule)) {
    const auto width = [&](double per_module) {
      return InputError::Length(per_module * gear.module);
    };
    throw InputError(
        p + ".face_width", 0, {"{}", {InputError::Length(gear.face_width)}},
        {fmt::format("gives b/m = {:.6g} face widths per module; must be in [{:g}, {:g}] (here "
                     "[{{#}}, {{#}}] {{unit}}): gears span narrow instrument gears to wide "
                     "industrial helical gears (is the unit right?)",
                     ratio, L::kMinFaceWidthPerModule, L::kMaxFaceWidthPerModule),
         {width(L::kMinFaceWidthPerModule), width(L::kMaxFaceWidthPerModule)}});
  }
}

double PitchRadius(const GearSpec& gear) {
  return 0.5 * gear.module / std::cos(gear.helix_angle) * gear.teeth;
}

double ToothUnitLoad(const GearSpec& a, const GearSpec& b, double torque_on_b) {
  return torque_on_b / PitchRadius(b) / std::min(a.face_width, b.face_width);
}

std::string InUnit(double value_si, const DisplayUnit& unit) {
  return fmt::format("{:.6g} {}", value_si * unit.per_si, unit.symbol);
}

void RequirePitchLineVelocity(const std::string& path, double speed, const DisplayUnit& unit,
                              double velocity_per_speed, const std::string& mesh) {
  const double velocity = speed * velocity_per_speed;
  if (velocity <= L::kMaxPitchLineVelocity) return;
  throw InputError(
      path, 0, InUnit(speed, unit),
      fmt::format("gives {} a pitch-line velocity of {:.4g} m/s, above the limit of {} m/s (a "
                  "speed of {} here): faster than any gear in service (high-speed turbo gear "
                  "units run at up to about 150-200 m/s), where centrifugal, windage and "
                  "oil-trapping effects the quasi-static mesh model leaves out dominate",
                  mesh, velocity, L::kMaxPitchLineVelocity,
                  InUnit(L::kMaxPitchLineVelocity / velocity_per_speed, unit)));
}

void RequireInertiaWithinLimit(const std::string& path, double inertia) {
  if (inertia <= L::kMaxInertia) return;
  throw InputError(path, 0, MessageNumber(inertia),
                   fmt::format("must be <= {:g} kg m^2: heavier than any rotating machine (a "
                               "15 MW wind-turbine rotor is about 3e8 kg m^2), and the modal "
                               "analysis loses its precision (1e300 overflowed to NaN)",
                               L::kMaxInertia));
}

void ValidateGearboxLimits(const GearboxSpec& spec, OperatingLimits operating) {
  for (const auto& [key, m] : spec.materials) {
    const std::string p = "materials." + key;
    if (!(m.youngs_modulus >= L::kMinYoungsModulus && m.youngs_modulus <= L::kMaxYoungsModulus)) {
      throw InputError(p + ".youngs_modulus", 0, MessageNumber(m.youngs_modulus),
                       fmt::format("must be in [{:g}, {:g}] GPa: gear and shaft materials span "
                                   "gear plastics to tungsten carbide (steel: 206 GPa; is the "
                                   "unit missing?)",
                                   L::kMinYoungsModulus * 1e-9, L::kMaxYoungsModulus * 1e-9));
    }
    if (!(m.density >= L::kMinDensity && m.density <= L::kMaxDensity)) {
      throw InputError(p + ".density", 0, MessageNumber(m.density),
                       fmt::format("must be in [{:g}, {:g}] kg/m^3: gear and shaft materials span "
                                   "gear plastics to the densest metals (steel: 7850 kg/m^3; is "
                                   "the unit right?)",
                                   L::kMinDensity, L::kMaxDensity));
    }
  }
  GearLimits(spec.pinion, "gears.pinion");
  GearLimits(spec.wheel, "gears.wheel");
  MeshLengthLimits(spec);

  // FE size: the full model's modal analysis is dense (stiffness, mass and the eigen solver's
  // workspace: about 6 n^2 doubles for n DOF).
  long elements = 0;
  std::string largest;
  double largest_elements = -1.0;
  for (const auto& [shaft, path] : {std::pair{&spec.input_shaft, "shafts.input"},
                                    std::pair{&spec.output_shaft, "shafts.output"}}) {
    if (!*shaft) continue;
    const long e = ShaftElements(**shaft);
    elements += e;
    if (e > largest_elements) {
      largest_elements = static_cast<double>(e);
      largest = path;
    }
  }
  if (elements > 0) {
    const double dofs = 6.0 * static_cast<double>(elements + 2);
    const double bytes = 6.0 * 8.0 * dofs * dofs;
    if (bytes > L::kMaxModalBytes) {
      const ShaftSpec& s = largest == "shafts.input" ? *spec.input_shaft : *spec.output_shaft;
      const std::string path = largest + (s.element_length ? ".element_length" : ".segments");
      throw InputError(
          path, 0, s.element_length ? MessageNumber(*s.element_length) : std::string("(default)"),
          fmt::format("gives {} shaft elements in all ({:.0f} DOF): the modal analysis of the full "
                      "model would need about {:.3g} GB, the limit is {:.3g} GB (use longer "
                      "elements)",
                      elements, dofs, bytes * 1e-9, L::kMaxModalBytes * 1e-9));
    }
  }

  const AnalysisSpec& a = spec.analysis;
  if (a.cycles > L::kMaxRecordedCycles) {
    throw InputError("analysis.cycles", 0, std::to_string(a.cycles),
                     fmt::format("must be <= {}: each recorded cycle keeps 32 trajectory samples "
                                 "in memory",
                                 L::kMaxRecordedCycles));
  }
  if (operating == OperatingLimits::kLeftToTheTrain) return;

  // Load: a linear-elastic tooth model (small deflections, no yield, no contact-area growth).
  const double unit_load = ToothUnitLoad(spec.pinion, spec.wheel, spec.operating.torque);
  if (!(unit_load <= L::kMaxUnitLoad)) {
    throw InputError("operating.torque", 0, MessageNumber(spec.operating.torque),
                     fmt::format("gives a tooth load of {:.3g} N/um of face width, above {} N/um: "
                                 "the mesh-stiffness and LSTE models assume small linear-elastic "
                                 "tooth deflections, and real teeth yield long before",
                                 unit_load * 1e-6, L::kMaxUnitLoad * 1e-6));
  }
  // Excitation: the model runs about a steady mean speed; an acceleration whose speed
  // fluctuation a / (k Omega) reaches the mean speed Omega would turn the pinion backwards.
  const double omega = spec.operating.speed;
  const DisplayUnit& speed_unit = spec.operating.speed_unit;
  for (size_t i = 0; i < spec.operating.excitation.size(); ++i) {
    const ExcitationOrder& e = spec.operating.excitation[i];
    const double fluctuation = e.amplitude / (e.order * omega);
    if (!(fluctuation <= omega)) {
      throw InputError(
          "operating.excitation[" + std::to_string(i) + "].amplitude", 0,
          MessageNumber(e.amplitude),
          fmt::format("makes the speed fluctuation a / (order x speed) = {} exceed the mean "
                      "speed {}: the shaft would turn backwards, and the model assumes a steady "
                      "mean speed",
                      InUnit(fluctuation, speed_unit), InUnit(omega, speed_unit)));
    }
  }

  // Speed: the pitch-line velocity (equal on both gears) at the operating speed. A written speed
  // sweep is held to it by the loader, which knows the sweep's unit and whether it was written.
  RequirePitchLineVelocity("operating.speed", omega, speed_unit, PitchRadius(spec.pinion),
                           "the mesh");

  // Run length.
  for (const auto& [speed, path] : {std::pair{omega, "operating.speed"},
                                    std::pair{a.speed_sweep.from, "analysis.speed_sweep.from"}}) {
    const double hz = spec.pinion.teeth * speed / (2.0 * std::numbers::pi);
    const double seconds = static_cast<double>(a.cycles + a.transient_cycles) / hz;
    if (!(seconds <= L::kMaxSimulatedSeconds)) {
      throw InputError(
          path, 0, MessageNumber(speed),
          fmt::format("is so low that the {} mesh cycles of analysis.cycles + "
                      "transient_cycles last {:.3g} s of simulated time (mesh "
                      "frequency {:.3g} Hz); the limit is {} s",
                      a.cycles + a.transient_cycles, seconds, hz, L::kMaxSimulatedSeconds));
    }
  }
}

}  // namespace gearnvh
