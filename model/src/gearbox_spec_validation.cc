#include "gearnvh/model/gearbox_spec_validation.h"

#include <cmath>
#include <numbers>

#include "gearnvh/model/count_text.h"
#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh {

// The highest excitation order accepted (plausibility: an order above it is a slip).
constexpr double kMaxExcitationOrder = 1000.0;

namespace {

// "base[i]"; appends rather than chaining operator+ (GCC 12 PR 105651 false -Wrestrict).
std::string Indexed(const std::string& base, size_t i) {
  std::string s = base;
  s += '[';
  s += std::to_string(i);
  s += ']';
  return s;
}

// Small rule helpers: each throws InputError(path, value, rule) when the rule is broken.
void Positive(const std::string& path, double v) {
  if (!(v > 0.0) || !std::isfinite(v)) throw InputError(path, 0, MessageNumber(v), "must be > 0");
}
void NonNegative(const std::string& path, double v) {
  if (!(v >= 0.0) || !std::isfinite(v)) throw InputError(path, 0, MessageNumber(v), "must be >= 0");
}
bool Within(double v, double lo, double hi, bool lo_open, bool hi_open) {
  const bool ok_lo = lo_open ? v > lo : v >= lo;
  const bool ok_hi = hi_open ? v < hi : v <= hi;
  return ok_lo && ok_hi && std::isfinite(v);
}
std::string Interval(bool lo_open, bool hi_open, const std::string& lo, const std::string& hi) {
  return std::string("must be in ") + (lo_open ? "(" : "[") + lo + ", " + hi +
         (hi_open ? ")" : "]");
}
void InRange(const std::string& path, double v, double lo, double hi, bool lo_open, bool hi_open) {
  if (!Within(v, lo, hi, lo_open, hi_open)) {
    throw InputError(path, 0, MessageNumber(v),
                     Interval(lo_open, hi_open, MessageNumber(lo), MessageNumber(hi)));
  }
}
// The same for a length or an angle: the value and the bounds in the unit the file wrote.
void InRange(const std::string& path, InputError::Quantity v, double lo, double hi, bool lo_open,
             bool hi_open) {
  if (Within(v.si, lo, hi, lo_open, hi_open)) return;
  InputError::Quantity low = v, high = v;
  low.si = lo;
  high.si = hi;
  throw InputError(path, 0, {"{}", {v}},
                   {Interval(lo_open, hi_open, "{#}", "{#}") + " {unit}", {low, high}});
}

void ValidateGear(const GearboxSpec& spec, const GearSpec& g, const std::string& p) {
  ValidateGearAlone(g, p);
  NonNegative(p + ".bore_diameter", g.bore_diameter);
  if (spec.materials.find(g.material) == spec.materials.end()) {
    throw InputError(p + ".material", 0, g.material, "must name a key of materials");
  }
  Positive(p + ".addendum_coefficient", g.addendum_coefficient);
  if (!(g.dedendum_coefficient >= g.addendum_coefficient) ||
      !std::isfinite(g.dedendum_coefficient)) {
    throw InputError(p + ".dedendum_coefficient", 0, MessageNumber(g.dedendum_coefficient),
                     "must be >= addendum_coefficient (" + MessageNumber(g.addendum_coefficient) +
                         "): the root clearance c* cannot be negative");
  }
  InRange(p + ".profile_shift", g.profile_shift, -1.0, 1.5, false, false);
  if (g.inertia) {
    Positive(p + ".inertia", *g.inertia);
    RequireInertiaWithinLimit(p + ".inertia", *g.inertia);
  }
  if (g.mass) Positive(p + ".mass", *g.mass);
  if (g.tip_relief) {
    NonNegative(p + ".tip_relief.amount", g.tip_relief->amount);
    NonNegative(p + ".tip_relief.length", g.tip_relief->length);
    if (g.tip_relief->amount > 0.0 && !(g.tip_relief->length > 0.0)) {
      throw InputError(p + ".tip_relief.length", 0, MessageNumber(g.tip_relief->length),
                       "must be > 0 when the relief amount is > 0");
    }
  }
  if (g.lead) {
    const LeadModification& lead = *g.lead;
    NonNegative(p + ".lead.crowning", lead.crowning);
    NonNegative(p + ".lead.end_relief.amount", lead.end_relief_amount);
    if ((lead.end_relief_amount > 0.0 || lead.end_relief_length != 0.0) &&
        !(lead.end_relief_length > 0.0 && lead.end_relief_length <= 0.5 * g.face_width)) {
      throw InputError(p + ".lead.end_relief.length", 0,
                       {"{}", {InputError::Length(lead.end_relief_length)}},
                       {"must be in (0, {}]: half this gear's face width (the relief runs in "
                        "from both ends)",
                        {InputError::Length(0.5 * g.face_width)}});
    }
    if (!std::isfinite(lead.slope)) {
      throw InputError(p + ".lead.slope", 0, MessageNumber(lead.slope), "must be finite");
    }
  }
  // Manufacturing errors are small deviations of the geometry: beyond a module they describe a
  // different gear, not an error of this one.
  if (g.runout) {
    InRange(p + ".runout.amplitude", InputError::Length(g.runout->amplitude), 0.0, g.module, false,
            false);
    if (!std::isfinite(g.runout->phase)) {
      throw InputError(p + ".runout.phase", 0, MessageNumber(g.runout->phase),
                       "must be a finite angle");
    }
  }
  if (!g.pitch_errors.empty() && static_cast<int>(g.pitch_errors.size()) != g.teeth) {
    throw InputError(p + ".pitch_errors", 0, Count(g.pitch_errors.size(), "value", "values"),
                     "must list one deviation per tooth (" + std::to_string(g.teeth) + ")");
  }
  for (size_t i = 0; i < g.pitch_errors.size(); ++i) {
    InRange(Indexed(p + ".pitch_errors", i), InputError::Length(g.pitch_errors[i]), -g.module,
            g.module, false, false);
  }
  const GearRadii r = ComputeGearRadii(g);
  if (!(r.root > 0.0)) {
    throw InputError(p + ".dedendum_coefficient", 0, MessageNumber(g.dedendum_coefficient),
                     "gives a root radius <= 0");
  }
  if (!(g.bore_diameter < 2.0 * r.root)) {
    throw InputError(
        p + ".bore_diameter", 0, {"{}", {InputError::Length(g.bore_diameter)}},
        {"must be smaller than the root diameter ({})", {InputError::Length(2.0 * r.root)}});
  }
}

void ValidateShaft(const GearboxSpec& spec, const ShaftSpec& s, const std::string& p) {
  if (spec.materials.find(s.material) == spec.materials.end()) {
    throw InputError(p + ".material", 0, s.material, "must name a key of materials");
  }
  if (s.segments.empty()) throw InputError(p + ".segments", 0, "[]", "needs at least one segment");
  for (size_t i = 0; i < s.segments.size(); ++i) {
    const std::string q = Indexed(p + ".segments", i);
    Positive(q + ".length", s.segments[i].length);
    Positive(q + ".outer_diameter", s.segments[i].outer_diameter);
    NonNegative(q + ".inner_diameter", s.segments[i].inner_diameter);
    if (!(s.segments[i].inner_diameter < s.segments[i].outer_diameter)) {
      throw InputError(q + ".inner_diameter", 0, MessageNumber(s.segments[i].inner_diameter),
                       "must be smaller than outer_diameter");
    }
  }
  const double len = s.Length();
  auto within = [&](const std::string& path, double x) {
    if (!(x >= 0.0 && x <= len * (1.0 + 1e-12))) {
      throw InputError(path, 0, {"{}", {InputError::Length(x)}},
                       {"must lie on the shaft, in [0, {#}] {unit}", {InputError::Length(len)}});
    }
  };
  within(p + ".gear_at", s.gear_at);
  if (s.bearings.empty()) throw InputError(p + ".bearings", 0, "[]", "needs at least one bearing");
  bool axial = false;
  int radial = 0;
  for (size_t i = 0; i < s.bearings.size(); ++i) {
    const std::string q = Indexed(p + ".bearings", i);
    const BearingSpec& b = s.bearings[i];
    within(q + ".at", b.at);
    NonNegative(q + ".radial_stiffness", b.radial_stiffness);
    NonNegative(q + ".axial_stiffness", b.axial_stiffness);
    NonNegative(q + ".tilt_stiffness", b.tilt_stiffness);
    NonNegative(q + ".damping", b.damping);
    axial = axial || b.axial_stiffness > 0.0;
    radial += b.radial_stiffness > 0.0 ? 1 : 0;
    if (b.radial_stiffness > 0.0 && b.tilt_stiffness > 0.0) radial += 1;
  }
  if (!axial) {
    throw InputError(
        p + ".bearings", 0, "",
        "at least one bearing needs axial_stiffness > 0 (else the shaft floats axially)");
  }
  if (radial < 2) {
    throw InputError(p + ".bearings", 0, "",
                     "needs two bearings with radial_stiffness > 0, or one that also has "
                     "tilt_stiffness > 0 (else the shaft tips over)");
  }
  for (size_t i = 0; i < s.inertias.size(); ++i) {
    const std::string q = Indexed(p + ".inertias", i);
    within(q + ".at", s.inertias[i].at);
    NonNegative(q + ".polar", s.inertias[i].polar);
    NonNegative(q + ".diametral", s.inertias[i].diametral);
    RequireInertiaWithinLimit(q + ".polar", s.inertias[i].polar);
    RequireInertiaWithinLimit(q + ".diametral", s.inertias[i].diametral);
    NonNegative(q + ".mass", s.inertias[i].mass);
  }
  if (s.element_length) {
    Positive(p + ".element_length", *s.element_length);
    if (len / *s.element_length > 200000.0) {
      throw InputError(p + ".element_length", 0, MessageNumber(*s.element_length),
                       "gives more than 200000 elements on this shaft");
    }
  }
}

void ValidateRange(const SweepRange& r, const std::string& p) {
  const std::optional<SweepRangeViolation> v = FirstSweepRangeViolation(r);
  if (!v) return;
  switch (v->part) {
    case SweepRangePart::kPoints:
      throw InputError(p + ".points", 0, std::to_string(r.points), v->rule);
    case SweepRangePart::kTo:
      // `from` named by its path, not its SI number (rad/s for an rpm the file wrote).
      throw InputError(p + ".to", 0, MessageNumber(r.to), v->rule + " (" + p + ".from)");
    case SweepRangePart::kFrom:
      throw InputError(p + ".from", 0, MessageNumber(r.from), v->rule);
  }
}

}  // namespace

std::optional<SweepRangeViolation> FirstSweepRangeViolation(const SweepRange& r) {
  if (r.points < 2) return SweepRangeViolation{SweepRangePart::kPoints, "must be >= 2"};
  if (r.points > 100000) return SweepRangeViolation{SweepRangePart::kPoints, "must be <= 100000"};
  if (!std::isfinite(r.from) || !std::isfinite(r.to) || !(r.to > r.from)) {
    return SweepRangeViolation{SweepRangePart::kTo, "must be greater than from"};
  }
  if (r.scale == AxisScale::kLog && !(r.from > 0.0)) {
    return SweepRangeViolation{SweepRangePart::kFrom,
                               "must be > 0 with scale: log (the points are spaced geometrically)"};
  }
  return std::nullopt;
}

void ValidateGearAlone(const GearSpec& g, const std::string& p) {
  if (g.teeth < 6) throw InputError(p + ".teeth", 0, std::to_string(g.teeth), "must be >= 6");
  if (g.teeth > 10000)
    throw InputError(p + ".teeth", 0, std::to_string(g.teeth), "must be <= 10000");
  Positive(p + ".module", g.module);
  InRange(p + ".pressure_angle", InputError::Angle(g.pressure_angle), 0.0, std::numbers::pi / 4.0,
          true, true);
  Positive(p + ".face_width", g.face_width);
  InRange(p + ".helix_angle", InputError::Angle(g.helix_angle), 0.0, std::numbers::pi / 4.0, false,
          true);
  RequireGearScale(g, p);
}

void ValidateGearboxSpec(const GearboxSpec& spec, OperatingLimits operating) {
  if (spec.name.empty()) throw InputError("name", 0, "\"\"", "must not be empty");
  if (spec.materials.empty()) throw InputError("materials", 0, "{}", "needs at least one material");
  for (const auto& [key, m] : spec.materials) {
    const std::string p = "materials." + key;
    Positive(p + ".youngs_modulus", m.youngs_modulus);
    InRange(p + ".poisson_ratio", m.poisson_ratio, -1.0, 0.5, true, true);
    Positive(p + ".density", m.density);
  }
  ValidateGear(spec, spec.pinion, "gears.pinion");
  ValidateGear(spec, spec.wheel, "gears.wheel");
  // An external helical pair: equal helix angles, opposite hands.
  if (spec.pinion.helix_angle != spec.wheel.helix_angle) {
    throw InputError("gears.wheel.helix_angle", 0,
                     {"{}", {InputError::Angle(spec.wheel.helix_angle)}},
                     {"must equal the pinion's helix angle ({}): gears in mesh share it",
                      {InputError::Angle(spec.pinion.helix_angle)}});
  }
  if (spec.pinion.helix_angle > 0.0 && spec.pinion.hand == spec.wheel.hand) {
    throw InputError("gears.wheel.hand", 0, spec.wheel.hand == Hand::kRight ? "right" : "left",
                     "must be the opposite of the pinion's hand (an external helical pair)");
  }

  const MeshSpec& mesh = spec.mesh;
  Positive("mesh.backlash", mesh.backlash);
  InRange("mesh.damping_ratio", mesh.damping_ratio, 0.0, 1.0, false, true);
  InRange("mesh.friction_coefficient", mesh.friction_coefficient, 0.0, 1.0, false, false);
  if (mesh.center_distance) Positive("mesh.center_distance", *mesh.center_distance);
  if (const auto* r = std::get_if<RectangularStiffness>(&mesh.stiffness)) {
    Positive("mesh.stiffness.rectangular.single", r->single);
    Positive("mesh.stiffness.rectangular.double", r->double_pair);
    InRange("mesh.stiffness.rectangular.contact_ratio", r->contact_ratio, 1.0, 2.0, false, false);
  } else if (const auto* t = std::get_if<TableStiffness>(&mesh.stiffness)) {
    if (t->phase.size() < 2) {
      throw InputError("mesh.stiffness.table.phase", 0, Count(t->phase.size(), "entry", "entries"),
                       "needs at least 2 entries");
    }
    if (t->phase.size() != t->stiffness.size()) {
      throw InputError(
          "mesh.stiffness.table.stiffness", 0, Count(t->stiffness.size(), "entry", "entries"),
          "must have as many entries as phase (" + std::to_string(t->phase.size()) + ")");
    }
    for (size_t i = 0; i < t->phase.size(); ++i) {
      const std::string phase_path = Indexed("mesh.stiffness.table.phase", i);
      InRange(phase_path, t->phase[i], 0.0, 1.0, false, true);
      if (i > 0 && !(t->phase[i] > t->phase[i - 1])) {
        throw InputError(phase_path, 0, MessageNumber(t->phase[i]), "must be strictly increasing");
      }
      Positive(Indexed("mesh.stiffness.table.stiffness", i), t->stiffness[i]);
    }
  } else if (const auto* f = std::get_if<FourierStiffness>(&mesh.stiffness)) {
    Positive("mesh.stiffness.fourier.mean", f->mean);
    double amplitude_sum = 0.0;
    for (double c : f->cos_coefficients) amplitude_sum += std::abs(c);
    for (double s : f->sin_coefficients) amplitude_sum += std::abs(s);
    if (!(amplitude_sum < f->mean)) {
      throw InputError("mesh.stiffness.fourier", 0, MessageNumber(amplitude_sum),
                       "sum of |harmonic amplitudes| must be < mean (" + MessageNumber(f->mean) +
                           " N/m) so the stiffness stays positive");
    }
  }
  const auto& ste = mesh.static_transmission_error;
  if (ste.amplitudes.size() != ste.phases.size()) {
    throw InputError(
        "mesh.static_transmission_error.phases", 0, Count(ste.phases.size(), "entry", "entries"),
        "must have as many entries as amplitudes (" + std::to_string(ste.amplitudes.size()) + ")");
  }
  for (size_t i = 0; i < ste.amplitudes.size(); ++i) {
    NonNegative(Indexed("mesh.static_transmission_error.amplitudes", i), ste.amplitudes[i]);
  }

  if (spec.input_shaft) ValidateShaft(spec, *spec.input_shaft, "shafts.input");
  if (spec.output_shaft) ValidateShaft(spec, *spec.output_shaft, "shafts.output");

  Positive("operating.speed", spec.operating.speed);
  NonNegative("operating.torque", spec.operating.torque);
  for (size_t i = 0; i < spec.operating.excitation.size(); ++i) {
    const std::string q = Indexed("operating.excitation", i);
    Positive(q + ".order", spec.operating.excitation[i].order);
    if (spec.operating.excitation[i].order > kMaxExcitationOrder) {
      throw InputError(q + ".order", 0, MessageNumber(spec.operating.excitation[i].order),
                       "must be <= " + MessageNumber(kMaxExcitationOrder) +
                           ": an engine or motor order (a 16-cylinder four-stroke fires at order "
                           "8, an electric motor's slot harmonics reach a few hundred)");
    }
    NonNegative(q + ".amplitude", spec.operating.excitation[i].amplitude);
  }

  const AnalysisSpec& a = spec.analysis;
  if (a.segments_per_cycle < 4 || a.segments_per_cycle > 4096) {
    throw InputError("analysis.segments_per_cycle", 0, std::to_string(a.segments_per_cycle),
                     "must be in [4, 4096]");
  }
  if (a.cycles < 1 || a.cycles > 100000000) {
    throw InputError("analysis.cycles", 0, std::to_string(a.cycles), "must be in [1, 1e8]");
  }
  if (a.transient_cycles < 0 || a.transient_cycles > 100000000) {
    throw InputError("analysis.transient_cycles", 0, std::to_string(a.transient_cycles),
                     "must be in [0, 1e8]");
  }
  ValidateRange(a.speed_sweep, "analysis.speed_sweep");
  if (a.speed_sweep.from <= 0.0) {
    throw InputError("analysis.speed_sweep.from", 0, MessageNumber(a.speed_sweep.from),
                     "must be > 0");
  }
  if (a.atlas_x) ValidateRange(a.atlas_x->range, "analysis.atlas.x");
  if (a.atlas_y) ValidateRange(a.atlas_y->range, "analysis.atlas.y");

  // The pair must mesh: contact ratio, interference, centre distance.
  (void)ComputePairGeometry(spec);
  ValidateGearboxLimits(spec, operating);
}

}  // namespace gearnvh
