#include "gearnvh/model/mesh_stiffness.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <numeric>
#include <tuple>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/mesh_segmentation.h"
#include "gearnvh/model/tooth_stiffness.h"

namespace gearnvh {

void MeshStiffnessOptions::Validate() const {
  if (samples_per_cycle < 64) {
    throw InputError("MeshStiffnessOptions.samples_per_cycle", 0, std::to_string(samples_per_cycle),
                     "must be >= 64");
  }
  if (!(path_extension_pitches > 0.0)) {
    throw InputError("MeshStiffnessOptions.path_extension_pitches", 0,
                     std::to_string(path_extension_pitches), "must be > 0");
  }
  if (face_slices < 2) {
    throw InputError("MeshStiffnessOptions.face_slices", 0, std::to_string(face_slices),
                     "must be >= 2");
  }
}

struct PairStiffness::Impl {
  ToothStiffnessModel pinion, wheel;
  double hertz_compliance, line_length, start, end;
  // Helical pairs (slice method on the normal section): the virtual spur gears of z / cos^3(beta)
  // teeth per unit face width, and the map of a transverse contact point to the point at the same
  // depth below the tip of the virtual tooth.
  bool helical = false;
  double cos_base_helix = 1.0, face_width = 0.0;
  double base_a = 0.0, base_b = 0.0, tip_a = 0.0, tip_b = 0.0;  // transverse section
  double virtual_base_a = 0.0, virtual_base_b = 0.0, virtual_tip_a = 0.0, virtual_tip_b = 0.0;
  // Tabulated stiffness (helical pairs: N slices evaluate it N times more often): natural cubic
  // spline through kTableNodes points over the path, relative error ~1e-12.
  std::vector<double> table, second;

  Impl(const MeshPair& pair, const PairGeometry& g)
      : pinion(Section(pair, pair.a, pair.normal_a), pair.material_a, VirtualTeeth(pair, pair.a)),
        wheel(Section(pair, pair.b, pair.normal_b), pair.material_b, VirtualTeeth(pair, pair.b)),
        hertz_compliance(
            1.0 / HertzContactStiffness(
                      pair.material_a, pair.material_b,
                      pair.helical() ? 1.0 : std::min(pair.a.face_width, pair.b.face_width))),
        line_length(g.line_of_action_length),
        start(g.contact_start),
        end(g.contact_end),
        helical(pair.helical()),
        cos_base_helix(std::cos(g.base_helix_angle)),
        face_width(pair.face_width) {
    if (!helical) return;
    base_a = g.pinion.base;
    base_b = g.wheel.base;
    tip_a = g.pinion.tip;
    tip_b = g.wheel.tip;
    for (auto [gear, vb, vt] : {std::tuple{&pair.normal_a, &virtual_base_a, &virtual_tip_a},
                                {&pair.normal_b, &virtual_base_b, &virtual_tip_b}}) {
      const double pitch = 0.5 * gear->module * VirtualTeeth(pair, *gear);
      *vb = pitch * std::cos(gear->pressure_angle);
      *vt = pitch + (gear->addendum_coefficient + gear->profile_shift) * gear->module;
    }
  }
  // The normal section per unit width for a helical pair, the transverse section otherwise.
  static GearSpec Section(const MeshPair& pair, const GearSpec& transverse,
                          const GearSpec& normal) {
    if (!pair.helical()) return transverse;
    GearSpec v = normal;
    v.helix_angle = 0.0;
    v.face_width = 1.0;
    // The body keeps its proportions: the bore scales with the virtual pitch radius.
    v.bore_diameter = normal.bore_diameter / std::pow(std::cos(pair.helix_angle), 2);
    return v;
  }
  static double VirtualTeeth(const MeshPair& pair, const GearSpec& gear) {
    return pair.helical() ? gear.teeth / std::pow(std::cos(pair.helix_angle), 3)
                          : static_cast<double>(gear.teeth);
  }
  // Roll on the virtual gear of the point at the same depth below the tip as the transverse
  // contact point at roll `s` (from this gear's base tangent point).
  static double VirtualRoll(double s, double base, double tip, double virtual_base,
                            double virtual_tip) {
    const double depth = tip - std::sqrt(base * base + s * s);
    const double r = std::max(virtual_tip - depth, virtual_base);
    return std::sqrt(r * r - virtual_base * virtual_base);
  }
  double Exact(double s) const {
    if (!helical) {
      return 1.0 /
             (hertz_compliance + pinion.AtRoll(s).Total() + wheel.AtRoll(line_length - s).Total());
    }
    // Per unit length of contact line on the normal section; the slice's contact line is
    // b / cos(beta_b) long over the face, and its transverse stiffness k_t = k_n cos^2(beta_b).
    const double sa = VirtualRoll(s, base_a, tip_a, virtual_base_a, virtual_tip_a);
    const double sb = VirtualRoll(line_length - s, base_b, tip_b, virtual_base_b, virtual_tip_b);
    const double per_length =
        1.0 / (hertz_compliance + pinion.AtRoll(sa).Total() + wheel.AtRoll(sb).Total());
    return per_length * face_width * cos_base_helix;
  }
};

namespace {
constexpr int kTableNodes = 1025;
}  // namespace

PairStiffness::PairStiffness(const MeshPair& pair, const PairGeometry& geometry, bool tabulate) {
  auto impl = std::make_shared<Impl>(pair, geometry);
  if (tabulate) {
    // Natural cubic spline (tridiagonal solve for the second derivatives).
    Impl& p = *impl;
    const int n = kTableNodes;
    const double h = (p.end - p.start) / (n - 1);
    p.table.resize(n);
    for (int i = 0; i < n; ++i) p.table[i] = p.Exact(p.start + h * i);
    p.second.assign(n, 0.0);
    std::vector<double> c(n, 0.0), d(n, 0.0);
    for (int i = 1; i + 1 < n; ++i) {
      const double rhs = 6.0 * (p.table[i + 1] - 2.0 * p.table[i] + p.table[i - 1]) / (h * h);
      const double m = 4.0 - c[i - 1];
      c[i] = 1.0 / m;
      d[i] = (rhs - d[i - 1]) / m;
    }
    for (int i = n - 2; i >= 1; --i) p.second[i] = d[i] - c[i] * p.second[i + 1];
  }
  impl_ = impl;
  for (const auto& w : impl_->pinion.warnings()) warnings_.push_back(pair.path_a + ": " + w);
  for (const auto& w : impl_->wheel.warnings()) warnings_.push_back(pair.path_b + ": " + w);
}

double PairStiffness::At(double roll) const {
  const Impl& p = *impl_;
  const double s = std::clamp(roll, p.start, p.end);
  if (p.table.empty()) return p.Exact(s);
  const int n = static_cast<int>(p.table.size());
  const double h = (p.end - p.start) / (n - 1);
  const int i = std::clamp(static_cast<int>((s - p.start) / h), 0, n - 2);
  const double t = (s - p.start) / h - i, u = 1.0 - t;
  return u * p.table[i] + t * p.table[i + 1] +
         h * h / 6.0 * ((u * u * u - u) * p.second[i] + (t * t * t - t) * p.second[i + 1]);
}

double OverrideStiffness(const StiffnessModel& model, double tau) {
  tau -= std::floor(tau);
  if (const auto* r = std::get_if<RectangularStiffness>(&model)) {
    return tau < r->contact_ratio - 1.0 ? r->double_pair : r->single;
  }
  if (const auto* t = std::get_if<TableStiffness>(&model)) {
    // Periodic linear interpolation through (phase_i, k_i).
    const auto& ph = t->phase;
    const auto& k = t->stiffness;
    const size_t n = ph.size();
    size_t hi = std::upper_bound(ph.begin(), ph.end(), tau) - ph.begin();
    const size_t lo = hi == 0 ? n - 1 : hi - 1;
    hi = hi % n;
    double p_lo = ph[lo], p_hi = ph[hi];
    double x = tau;
    if (p_hi <= p_lo) {  // wraps around 1
      p_hi += 1.0;
      if (x < p_lo) x += 1.0;
    }
    const double w = (x - p_lo) / (p_hi - p_lo);
    return k[lo] + w * (k[hi] - k[lo]);
  }
  if (const auto* f = std::get_if<FourierStiffness>(&model)) {
    double k = f->mean;
    const double w = 2.0 * std::numbers::pi * tau;
    for (size_t n = 0; n < f->cos_coefficients.size(); ++n)
      k += f->cos_coefficients[n] * std::cos(static_cast<double>(n + 1) * w);
    for (size_t n = 0; n < f->sin_coefficients.size(); ++n)
      k += f->sin_coefficients[n] * std::sin(static_cast<double>(n + 1) * w);
    return k;
  }
  return 0.0;
}

namespace {

// An element's load k / s * integral over [e, e + s] of (delta - u)_+ du and its derivative
// (s = spread; s = 0: k (delta - e)_+).
struct ElementLoad {
  double load = 0.0, tangent = 0.0;
};
ElementLoad LoadOf(const ContactElement& p, double delta) {
  const double over = delta - p.separation;
  if (!(over > 0.0)) return {};
  if (over >= p.spread) return {p.stiffness * (over - 0.5 * p.spread), p.stiffness};
  return {0.5 * p.stiffness * over * over / p.spread, p.stiffness * over / p.spread};
}

}  // namespace

double ShareLoad(std::vector<ContactElement>& elements, double load) {
  // Events in increasing approach: an element starts to carry load at its smallest separation and
  // carries it over its whole width from its largest (one event when it is uniform). Between two
  // events the total load is a polynomial of degree <= 2 in delta, tracked from event to event.
  struct Event {
    double at;
    int element;
    bool whole;
  };
  const int n = static_cast<int>(elements.size());
  std::vector<Event> events;
  events.reserve(2 * static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const ContactElement& p = elements[static_cast<size_t>(i)];
    events.push_back({p.separation, i, !(p.spread > 0.0)});
    if (p.spread > 0.0) events.push_back({p.separation + p.spread, i, true});
  }
  // Stable (equal separations keep their order). Not an insertion sort: a helical pair has ~200
  // elements (40 slices), whose quadratic sort dominated the mesh-cycle build.
  std::stable_sort(events.begin(), events.end(),
                   [](const Event& a, const Event& b) { return a.at < b.at; });
  std::vector<char> started(static_cast<size_t>(n), 0), whole(static_cast<size_t>(n), 0);
  // Whole elements' sum k and sum k * (mean separation); the load, its slope and its curvature
  // (sum k / s of the partly loaded elements) at the current event.
  double sum_k = 0.0, sum_ke = 0.0, total = 0.0, slope = 0.0, curvature = 0.0, at = 0.0;
  int partial = 0;
  double delta = 0.0;
  const int count = static_cast<int>(events.size());
  for (int m = 0; m < count; ++m) {
    const Event& ev = events[static_cast<size_t>(m)];
    if (m > 0) {
      const double h = ev.at - at;
      total += slope * h + 0.5 * curvature * h * h;
      slope += curvature * h;
    }
    at = ev.at;
    const ContactElement& p = elements[static_cast<size_t>(ev.element)];
    started[static_cast<size_t>(ev.element)] = 1;
    whole[static_cast<size_t>(ev.element)] = ev.whole ? 1 : 0;
    if (ev.whole) {
      sum_k += p.stiffness;
      sum_ke += p.spread > 0.0 ? p.stiffness * (p.separation + 0.5 * p.spread)
                               : p.stiffness * p.separation;
      if (p.spread > 0.0) {
        curvature -= p.stiffness / p.spread;
        --partial;
      } else {
        slope += p.stiffness;
      }
    } else {
      curvature += p.stiffness / p.spread;
      ++partial;
    }
    const bool last = m + 1 == count;
    if (partial == 0) {
      // No partly loaded element: drop what the curvature's +k/s and -k/s left by rounding.
      curvature = 0.0;
      // Only whole elements carry load: the linear solve (a uniform face's only case).
      delta = (load + sum_ke) / sum_k;
      // Stop once delta is below the next event; an element with e == delta adds nothing under
      // load and must join at zero load (ties share by stiffness).
      if (last || delta < events[static_cast<size_t>(m) + 1].at) break;
      continue;
    }
    if (curvature < 0.0) curvature = 0.0;  // rounding as the last partial element turns whole
    const double h = events[static_cast<size_t>(m) + 1].at - at;
    if (total + slope * h + 0.5 * curvature * h * h < load) continue;
    // The tracked polynomial carries every event's rounding (k / s added, later taken off): its
    // coefficients again from the elements themselves before the bracket is trusted.
    total = slope = curvature = 0.0;
    for (int i = 0; i < n; ++i) {
      const ContactElement& e = elements[static_cast<size_t>(i)];
      if (!started[static_cast<size_t>(i)]) continue;
      if (whole[static_cast<size_t>(i)]) {
        total += e.stiffness * (at - e.separation - 0.5 * e.spread);
        slope += e.stiffness;
      } else {
        const double over = at - e.separation;
        total += 0.5 * e.stiffness * over * over / e.spread;
        slope += e.stiffness * over / e.spread;
        curvature += e.stiffness / e.spread;
      }
    }
    if (total + slope * h + 0.5 * curvature * h * h < load) continue;
    // load = total + slope x + curvature x^2 / 2 on [at, next event], in its stable root form.
    const double r = std::max(load - total, 0.0);
    const double root = slope + std::sqrt(slope * slope + 2.0 * curvature * r);
    delta = at + (root > 0.0 ? 2.0 * r / root : 0.0);
    break;
  }
  double total_share = 0.0;
  const double tie = 1e-15 + 1e-12 * std::abs(delta);
  for (int i = 0; i < n; ++i) {
    ContactElement& p = elements[static_cast<size_t>(i)];
    p.loaded = started[static_cast<size_t>(i)] != 0 &&
               (load > 0.0 ? delta > p.separation : p.separation <= delta + tie);
    p.load_share = 0.0;
    p.tangent = 0.0;
    if (!p.loaded) continue;
    if (load > 0.0) {
      const ElementLoad f = LoadOf(p, delta);
      p.load_share = p.spread > 0.0 ? f.load / load : p.stiffness * (delta - p.separation) / load;
      p.tangent = f.tangent;
    } else {
      p.load_share = p.stiffness;
      p.tangent = p.stiffness;
    }
    total_share += p.load_share;
  }
  if (load <= 0.0 && total_share > 0.0) {
    for (ContactElement& p : elements) p.load_share /= total_share;
  }
  return delta;
}

std::vector<double> LineLoadAtSliceEdges(const std::vector<ContactElement>& elements, double delta,
                                         int slices, double face_width) {
  const double width = face_width / slices;
  std::vector<double> start(static_cast<size_t>(slices), 0.0), end(start);
  for (const ContactElement& p : elements) {
    const double far = p.separation + p.spread;
    const double u_start = p.grows_toward_end ? p.separation : far;
    const double u_end = p.grows_toward_end ? far : p.separation;
    start[static_cast<size_t>(p.slice)] += p.stiffness / width * std::max(delta - u_start, 0.0);
    end[static_cast<size_t>(p.slice)] += p.stiffness / width * std::max(delta - u_end, 0.0);
  }
  std::vector<double> edges(static_cast<size_t>(slices) + 1);
  edges.front() = start.front();
  edges.back() = end.back();
  for (int i = 1; i < slices; ++i) {
    edges[static_cast<size_t>(i)] =
        std::max(end[static_cast<size_t>(i) - 1], start[static_cast<size_t>(i)]);
  }
  return edges;
}

namespace {

double Frac(double x) { return x - std::floor(x); }

// A strip whose separation changes by less than this fraction of the face's largest mismatch
// across it counts as uniform (MeshEvaluator::Elements).
constexpr double kUniformSpread = 1e-9;

constexpr double kUniformMismatch = 1e-12;  // m

// The material a gear's lead modification removes at face position y of the common face b (the
// gear's own face, of width b_g >= b, centred on it).
double LeadRemoval(const GearSpec& gear, double y, double face, bool symmetric_only) {
  if (!gear.lead) return 0.0;
  const LeadModification& lead = *gear.lead;
  const double b = gear.face_width;
  const double yg = y + 0.5 * (b - face);
  const double centred = 2.0 * yg / b - 1.0;
  double removed = lead.crowning * centred * centred;
  if (lead.end_relief_amount > 0.0) {
    const double length = lead.end_relief_length;
    removed += lead.end_relief_amount *
               (std::max(length - yg, 0.0) + std::max(yg - (b - length), 0.0)) / length;
  }
  if (!symmetric_only) removed += lead.slope * yg / b;
  return removed;
}

// The separation the face adds at the N + 1 slice edges, shifted so its smallest value is 0;
// empty when it is uniform.
std::vector<double> FaceMismatch(const MeshPair& pair, int slices, bool drive) {
  const double face = pair.face_width;
  const double linear = drive ? pair.mesh.misalignment + pair.shaft_misalignment : 0.0;
  std::vector<double> m(static_cast<size_t>(slices) + 1);
  for (int i = 0; i <= slices; ++i) {
    const double y = face * i / slices;
    m[static_cast<size_t>(i)] = linear * y / face + LeadRemoval(pair.a, y, face, !drive) +
                                LeadRemoval(pair.b, y, face, !drive);
  }
  const double low = *std::min_element(m.begin(), m.end());
  for (double& v : m) v -= low;
  // Uniform below a picometre: what remains of a slope cancelling a misalignment is rounding.
  if (*std::max_element(m.begin(), m.end()) <= kUniformMismatch) m.clear();
  return m;
}

bool FaceModified(const MeshPair& pair) {
  const auto modified = [](const GearSpec& gear) {
    return gear.lead && *gear.lead != LeadModification{};
  };
  return pair.mesh.misalignment != 0.0 || pair.shaft_misalignment != 0.0 || modified(pair.a) ||
         modified(pair.b);
}

}  // namespace

MeshEvaluator::MeshEvaluator(const MeshPair& pair, const PairGeometry& g,
                             const MeshStiffnessOptions& options)
    : stiffness_(pair.mesh.stiffness),
      g_(g),
      pair_(pair, g, pair.helical()),
      face_width_(pair.face_width) {
  options.Validate();
  const GearSpec& pinion = pair.a;
  const GearSpec& wheel = pair.b;
  overridden_ = !std::holds_alternative<PotentialEnergyStiffness>(stiffness_);
  load_ = pair.transmitted_torque / g.wheel.base;
  // The face is modelled strip by strip only under load (the contact width at zero load is a
  // point; an impact's width depends on its force, which the piecewise-linear model does not
  // carry) and without an override (the user's k(tau) is the whole face's).
  const bool face = load_ > 0.0 && !overridden_ && FaceModified(pair);
  slices_ = pair.helical() || face ? options.face_slices : 1;
  if (face) {
    drive_mismatch_ = FaceMismatch(pair, slices_, true);
    back_mismatch_ = FaceMismatch(pair, slices_, false);
    if (drive_mismatch_.empty() && back_mismatch_.empty() && !pair.helical()) slices_ = 1;
    face_ = !drive_mismatch_.empty() || !back_mismatch_.empty();
    for (const std::vector<double>* m : {&drive_mismatch_, &back_mismatch_}) {
      for (double v : *m) mismatch_scale_ = std::max(mismatch_scale_, v);
    }
  }
  reach_ = options.path_extension_pitches * g.base_pitch;
  if (wheel.tip_relief) {
    relief_start_amount_ = wheel.tip_relief->amount;
    relief_start_length_ = wheel.tip_relief->length;
  }
  if (pinion.tip_relief) {
    relief_end_amount_ = pinion.tip_relief->amount;
    relief_end_length_ = pinion.tip_relief->length;
  }
  // Pinion half-tooth angle at the working pitch circle, for the back-flank mirror offset.
  const double alpha0 = pinion.pressure_angle;
  const double alpha2 = std::numbers::pi / (2.0 * pinion.teeth) + Involute(alpha0) +
                        2.0 * pinion.profile_shift * std::tan(alpha0) / pinion.teeth;
  const double theta_w = alpha2 - Involute(g.working_pressure_angle);
  mirror_ = 2.0 * (g.pitch_point + g.pinion.base * theta_w);
  back_phase_ = mirror_ - 2.0 * g.contact_start;
}

double MeshEvaluator::Separation(double s) const {
  const double start = g_.contact_start, end = g_.contact_end;
  double e = 0.0;
  // Linear tip relief: the wheel tip meets the path start, the pinion tip the path end.
  if (relief_start_length_ > 0.0 && s < start + relief_start_length_) {
    e += relief_start_amount_ * (start + relief_start_length_ - s) / relief_start_length_;
  }
  if (relief_end_length_ > 0.0 && s > end - relief_end_length_) {
    e += relief_end_amount_ * (s - (end - relief_end_length_)) / relief_end_length_;
  }
  // Outside the path: tip corner against the mating flank's curvature.
  if (s < start) {
    const double rho = std::max(start, 1e-6);
    e += (start - s) * (start - s) / (2.0 * rho);
  } else if (s > end) {
    const double rho = std::max(g_.line_of_action_length - end, 1e-6);
    e += (s - end) * (s - end) / (2.0 * rho);
  }
  return e;
}

double MeshEvaluator::PitchCrossing(Flank flank) const {
  const double s_drive = flank == Flank::kDrive ? g_.pitch_point : mirror_ - g_.pitch_point;
  return Frac((s_drive - g_.contact_start) / g_.base_pitch);
}

std::vector<double> MeshEvaluator::OverrideBreaks(Flank flank) const {
  std::vector<double> law;  // phases of the override's own cycle
  if (const auto* r = std::get_if<RectangularStiffness>(&stiffness_)) {
    law = {0.0, r->contact_ratio - 1.0};
  } else if (const auto* t = std::get_if<TableStiffness>(&stiffness_)) {
    law = t->phase;
  }
  // The drive flank reads the law at tau, the back flank at back_phase / p_b - tau (Evaluate).
  for (double& phase : law) {
    phase = Frac(flank == Flank::kDrive ? phase : back_phase_ / g_.base_pitch - phase);
  }
  return law;
}

std::vector<ContactElement> MeshEvaluator::Elements(double tau, Flank flank) const {
  const PairGeometry& g = g_;
  // Contact elements: every tooth pair near the path, on every face slice (one slice for an
  // aligned spur pair). Slice k of a helical pair sits eps_beta (k + 1/2) / N mesh cycles ahead of
  // the face's edge, and carries 1/N of the pair stiffness (all compliances scale with the width).
  std::vector<ContactElement> elements;
  const std::vector<double>& mismatch = flank == Flank::kDrive ? drive_mismatch_ : back_mismatch_;
  const double slice_weight = 1.0 / slices_;
  // A spur face's slices all see the same rolls: each pair's stiffness (a quadrature) and
  // separation once, from the first slice.
  const bool same_rolls = g.overlap_ratio == 0.0;
  std::array<double, FlankSample::kMaxPairs> first_stiffness{}, first_separation{};
  for (int k = 0; k < slices_; ++k) {
    const double shift = slices_ > 1 ? g.overlap_ratio * (k + 0.5) / slices_ : 0.0;
    const double s_drive = g.contact_start + (tau + shift) * g.base_pitch;
    const double s0 = flank == Flank::kDrive ? s_drive : mirror_ - s_drive;
    // Shift by whole pitches to the first position at or after start - reach.
    const double first =
        s0 - std::floor((s0 - (g.contact_start - reach_)) / g.base_pitch) * g.base_pitch;
    int count = 0;
    for (double s = first; s <= g.contact_end + reach_ && count < FlankSample::kMaxPairs;
         s += g.base_pitch, ++count) {
      ContactElement e;
      e.roll = s;
      const auto pair = static_cast<size_t>(count);
      if (k == 0 || !same_rolls) {
        first_stiffness[pair] = slices_ > 1 ? slice_weight * pair_.At(s) : pair_.At(s);
        first_separation[pair] = Separation(s);
      }
      e.stiffness = first_stiffness[pair];
      e.separation = first_separation[pair];
      e.slice = k;
      if (!mismatch.empty()) {
        const double at_start = mismatch[static_cast<size_t>(k)];
        const double at_end = mismatch[static_cast<size_t>(k) + 1];
        e.separation += std::min(at_start, at_end);
        e.spread = std::abs(at_end - at_start);
        e.grows_toward_end = at_end >= at_start;
        // A spread at the rounding of the mismatch (a crowning's vertex against a slope) is
        // uniform: its k / s would swamp the other strips' curvature in the sweep.
        if (e.spread <= kUniformSpread * mismatch_scale_) {
          e.separation += 0.5 * e.spread;
          e.spread = 0.0;
        }
      }
      // The tooth pair: cycles since it entered the path of contact at this slice (drive flank),
      // the same integer on every slice.
      const double s_pair = flank == Flank::kDrive ? s : mirror_ - s;
      e.pair =
          static_cast<int>(std::lround((s_pair - g.contact_start) / g.base_pitch - tau - shift));
      elements.push_back(e);
    }
  }
  return elements;
}

void MeshEvaluator::FaceAt(const std::vector<ContactElement>& elements, double delta,
                           FaceSample& face) const {
  // A slice's elements all grow toward the same edge, so the loaded parts nest: the slice's
  // loaded width is the largest.
  const double width = face_width_ / slices_;
  std::vector<double> loaded(static_cast<size_t>(slices_), 0.0);
  for (const ContactElement& e : elements) {
    const double over = delta - e.separation;
    const double part = !(over > 0.0) ? 0.0 : (over >= e.spread ? 1.0 : over / e.spread);
    loaded[static_cast<size_t>(e.slice)] = std::max(loaded[static_cast<size_t>(e.slice)], part);
  }
  face.loaded_width = 0.0;
  for (double part : loaded) face.loaded_width += part * width;
  face.line_load = LineLoadAtSliceEdges(elements, delta, slices_, face_width_);
  // The same pairs with the mismatch taken off: the full face's stiffness.
  std::vector<ContactElement> full = elements;
  for (ContactElement& e : full) {
    const auto k = static_cast<size_t>(e.slice);
    e.separation -= std::min(drive_mismatch_[k], drive_mismatch_[k + 1]);
    e.spread = 0.0;
  }
  ShareLoad(full, load_);
  face.full_face_stiffness = 0.0;
  for (const ContactElement& e : full) face.full_face_stiffness += e.tangent;
}

FlankSample MeshEvaluator::Evaluate(double tau, Flank flank, FaceSample* face) const {
  const PairGeometry& g = g_;
  std::vector<ContactElement> elements = Elements(tau, flank);
  FlankSample out;
  out.lste = ShareLoad(elements, load_);
  if (face != nullptr && flank == Flank::kDrive && !drive_mismatch_.empty()) {
    FaceAt(elements, out.lste, *face);
  }
  if (overridden_) {
    // User data replaces the stiffness; share equally among elements inside the path.
    const double tau_flank = flank == Flank::kDrive ? tau : back_phase_ / g.base_pitch - tau;
    int in_path = 0;
    for (const ContactElement& e : elements) {
      in_path += (e.roll >= g.contact_start && e.roll <= g.contact_end);
    }
    for (ContactElement& e : elements) {
      const bool in = e.roll >= g.contact_start && e.roll <= g.contact_end;
      e.loaded = in;
      e.load_share = in && in_path > 0 ? 1.0 / in_path : 0.0;
    }
    out.stiffness = OverrideStiffness(stiffness_, tau_flank);
    out.lste = load_ / out.stiffness;
  }
  // Tooth pairs: the elements of one pair summed (the pair's loaded stiffness, its load share);
  // roll is that of the pair's first slice.
  for (const ContactElement& e : elements) {
    if (e.loaded && !overridden_) out.stiffness += e.tangent;
    PairState* p = nullptr;
    for (int m = 0; m < out.pair_count; ++m) {
      if (out.pairs[m].offset == e.pair) p = &out.pairs[m];
    }
    if (p == nullptr) {
      if (out.pair_count == FlankSample::kMaxPairs) continue;
      p = &out.pairs[out.pair_count++];
      p->offset = e.pair;
      p->roll = e.roll;
      p->separation = e.separation;
    }
    // A pair's stiffness is the tangent stiffness of its loaded elements (the full stiffness of
    // all of them while it is unloaded).
    const bool first_loaded = e.loaded && !p->loaded;
    if (first_loaded) p->stiffness = 0.0;
    if (e.loaded || !p->loaded) p->stiffness += e.loaded ? e.tangent : e.stiffness;
    p->loaded = p->loaded || e.loaded;
    p->load_share += e.load_share;
    p->separation = std::min(p->separation, e.separation);
  }
  for (int m = 0; m < out.pair_count; ++m) out.loaded_pairs += out.pairs[m].loaded ? 1 : 0;
  // Friction: sliding reverses at the pitch point, element by element.
  for (const ContactElement& e : elements) {
    const double sgn = e.roll > g.pitch_point ? 1.0 : (e.roll < g.pitch_point ? -1.0 : 0.0);
    out.friction_sigma += e.load_share * sgn;
    out.friction_arm_pinion += e.load_share * sgn * e.roll;
    out.friction_arm_wheel += e.load_share * sgn * (g.line_of_action_length - e.roll);
  }
  return out;
}

namespace {

// A FaceLoad with the misalignment components set, the face uniform.
FaceLoad MismatchComponents(const MeshPair& pair) {
  FaceLoad face;
  face.manufacturing_misalignment = pair.mesh.misalignment;
  face.shaft_misalignment = pair.shaft_misalignment;
  // A gear's slope grows over its own face; the common face sees b / b_gear of it.
  for (const GearSpec* gear : {&pair.a, &pair.b}) {
    if (gear->lead) face.lead_slopes += gear->lead->slope * pair.face_width / gear->face_width;
  }
  face.linear_mismatch =
      face.manufacturing_misalignment + face.shaft_misalignment + face.lead_slopes;
  face.face_width = pair.face_width;
  face.loaded_width = pair.face_width;
  return face;
}

// The drive flank's load across the face from the cycle's face samples.
FaceLoad ComputeFaceLoad(const MeshPair& pair, const MeshEvaluator& evaluator,
                         const std::vector<FaceSample>& samples) {
  FaceLoad face = MismatchComponents(pair);
  const int slices = evaluator.slices();
  const double b = pair.face_width;
  face.mismatch = evaluator.face_mismatch();
  face.position.resize(static_cast<size_t>(slices) + 1);
  for (int i = 0; i <= slices; ++i) face.position[static_cast<size_t>(i)] = b * i / slices;
  face.line_load.assign(face.position.size(), 0.0);
  double full_face_stiffness = 0.0;
  const double n = static_cast<double>(samples.size());
  for (const FaceSample& sample : samples) {
    for (size_t i = 0; i < sample.line_load.size(); ++i)
      face.line_load[i] += sample.line_load[i] / n;
    face.loaded_width = std::min(face.loaded_width, sample.loaded_width);
    full_face_stiffness += sample.full_face_stiffness / n;
  }
  const double mean = evaluator.load() / b;
  face.factor = *std::max_element(face.line_load.begin(), face.line_load.end()) / mean;
  // ISO 6336-1 method C: x = F_beta_y c_gamma_beta / (2 F / b); K = 1 + x up to 2, 2 sqrt(x)
  // beyond, with c_gamma_beta = 0.85 times the full face's mean stiffness per unit width.
  face.model = FaceLoad::Model::kModelled;
  face.full_face_stiffness = full_face_stiffness;
  const double x = std::abs(face.linear_mismatch) * 0.85 * full_face_stiffness / b / (2.0 * mean);
  face.iso_method_c = x <= 1.0 ? 1.0 + x : 2.0 * std::sqrt(x);
  return face;
}

}  // namespace

MeshCycle ComputeMeshCycle(const MeshPair& pair, const PairGeometry& g,
                           const MeshStiffnessOptions& options) {
  const MeshEvaluator evaluator(pair, g, options);
  MeshCycle cycle;
  cycle.warnings = evaluator.warnings();
  cycle.overridden = evaluator.overridden();
  cycle.load = evaluator.load();
  cycle.back_phase = evaluator.back_phase();
  const int n = options.samples_per_cycle;
  cycle.tau.resize(n);
  cycle.drive.resize(n);
  cycle.back.resize(n);
  // The drive flank's face samples where only the drive flank's face is uniform: none.
  const bool face = evaluator.face_modelled() && !evaluator.face_mismatch().empty();
  std::vector<FaceSample> face_samples(face ? static_cast<size_t>(n) : 0);
  for (int i = 0; i < n; ++i) {
    const double tau = (i + 0.5) / n;
    cycle.tau[i] = tau;
    cycle.drive[i] = evaluator.Evaluate(tau, Flank::kDrive,
                                        face ? &face_samples[static_cast<size_t>(i)] : nullptr);
    cycle.back[i] = evaluator.Evaluate(tau, Flank::kBack);
  }
  cycle.face = MismatchComponents(pair);
  if (face) {
    cycle.face = ComputeFaceLoad(pair, evaluator, face_samples);
    const FaceLoad& f = cycle.face;
    if (f.loaded_width < 0.5 * f.face_width) {
      double mean = 0.0;
      for (const FlankSample& d : cycle.drive) mean += d.stiffness / n;
      cycle.warnings.push_back(fmt::format(
          "{}: carries its static load ({:.4g} N) on {:.3g} mm of its {:.3g} mm face (K_Hβ "
          "{:.3g}): its mesh stiffness is that of the static load, {:.4g} N/µm against {:.4g} "
          "N/µm over the full face; a dynamic load well above it (impacts) loads more of the face",
          pair.path_mesh, cycle.load, f.loaded_width * 1e3, f.face_width * 1e3, f.factor,
          mean * 1e-6, f.full_face_stiffness * 1e-6));
    }
  } else if (FaceModified(pair) && evaluator.overridden()) {
    cycle.face.model = FaceLoad::Model::kOverridden;
    cycle.warnings.push_back(pair.path_mesh +
                             ": the stiffness override gives the whole face's stiffness: the "
                             "misalignment and lead modifications are not applied");
  } else if (FaceModified(pair) && !(cycle.load > 0.0)) {
    cycle.face.model = FaceLoad::Model::kUnloaded;
    cycle.warnings.push_back(pair.path_mesh +
                             ": carries no static load: the misalignment and lead modifications "
                             "are not applied (the loaded width at zero load is a point)");
  }
  return cycle;
}

MeshStiffnessSummary SummarizeMeshCycle(const MeshCycle& cycle, const PairGeometry& g,
                                        const MeshSegmentation& segmentation) {
  MeshStiffnessSummary s;
  s.contact_ratio = g.contact_ratio;
  s.min = s.max = cycle.drive[0].stiffness;
  double lste_min = cycle.drive[0].lste, lste_max = lste_min;
  double single_sum = 0.0, double_sum = 0.0;
  int single_n = 0, double_n = 0;
  for (const FlankSample& d : cycle.drive) {
    s.min = std::min(s.min, d.stiffness);
    s.max = std::max(s.max, d.stiffness);
    lste_min = std::min(lste_min, d.lste);
    lste_max = std::max(lste_max, d.lste);
    if (d.loaded_pairs == 1) single_sum += d.stiffness, ++single_n;
    if (d.loaded_pairs == 2) double_sum += d.stiffness, ++double_n;
    for (int m = 0; m < d.pair_count; ++m)
      s.load_sharing_max = std::max(s.load_sharing_max, d.pairs[m].load_share);
  }
  s.mean = CycleMeanStiffness(segmentation, Flank::kDrive);
  s.single_pair_mean = single_n ? single_sum / single_n : 0.0;
  s.double_pair_mean = double_n ? double_sum / double_n : 0.0;
  s.lste_peak_to_peak = lste_max - lste_min;
  s.face_load_factor = cycle.face.factor;
  return s;
}

}  // namespace gearnvh
