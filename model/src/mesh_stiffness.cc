#include "gearnvh/model/mesh_stiffness.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <numeric>

#include "gearnvh/model/input_error.h"
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
}

struct PairStiffness::Impl {
  ToothStiffnessModel pinion, wheel;
  double hertz_compliance, line_length, start, end;
  Impl(const MeshPair& pair, const PairGeometry& g)
      : pinion(*pair.a, *pair.material_a),
        wheel(*pair.b, *pair.material_b),
        hertz_compliance(1.0 /
                         HertzContactStiffness(*pair.material_a, *pair.material_b,
                                               std::min(pair.a->face_width, pair.b->face_width))),
        line_length(g.line_of_action_length),
        start(g.contact_start),
        end(g.contact_end) {}
};

PairStiffness::PairStiffness(const MeshPair& pair, const PairGeometry& geometry)
    : impl_(std::make_shared<Impl>(pair, geometry)) {
  for (const auto& w : impl_->pinion.warnings()) warnings_.push_back(pair.path_a + ": " + w);
  for (const auto& w : impl_->wheel.warnings()) warnings_.push_back(pair.path_b + ": " + w);
}

double PairStiffness::At(double roll) const {
  const Impl& p = *impl_;
  const double s = std::clamp(roll, p.start, p.end);
  const double compliance =
      p.hertz_compliance + p.pinion.AtRoll(s).Total() + p.wheel.AtRoll(p.line_length - s).Total();
  return 1.0 / compliance;
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

// Solves sum k_j (delta - e_j)_+ = F exactly and fills the sample.
void ShareLoad(FlankSample& out, double load) {
  const int n = out.pair_count;
  std::array<int, FlankSample::kMaxPairs> order{};
  // Insertion sort by separation (at most kMaxPairs entries).
  for (int m = 0; m < n; ++m) {
    int k = m;
    while (k > 0 && out.pairs[order[k - 1]].separation > out.pairs[m].separation) {
      order[k] = order[k - 1];
      --k;
    }
    order[k] = m;
  }
  double sum_k = 0.0, sum_ke = 0.0, delta = 0.0;
  int active = 0;
  for (int m = 0; m < n; ++m) {
    const PairState& p = out.pairs[order[m]];
    sum_k += p.stiffness;
    sum_ke += p.stiffness * p.separation;
    active = m + 1;
    delta = (load + sum_ke) / sum_k;
    // Stop once delta is below the next separation; a pair with e == delta adds nothing under
    // load and must join at zero load (ties share by stiffness).
    if (m + 1 == n || delta < out.pairs[order[m + 1]].separation) break;
  }
  out.lste = delta;
  out.stiffness = 0.0;
  out.loaded_pairs = 0;
  double total_share = 0.0;
  const double tie = 1e-15 + 1e-12 * std::abs(delta);
  for (int m = 0; m < n; ++m) {
    PairState& p = out.pairs[order[m]];
    const bool loaded =
        m < active && (load > 0.0 ? delta > p.separation : p.separation <= delta + tie);
    p.load_share =
        loaded ? (load > 0.0 ? p.stiffness * (delta - p.separation) / load : p.stiffness) : 0.0;
    if (loaded) {
      out.stiffness += p.stiffness;
      ++out.loaded_pairs;
      total_share += p.load_share;
    }
  }
  if (load <= 0.0 && total_share > 0.0) {
    for (int m = 0; m < n; ++m) out.pairs[m].load_share /= total_share;
  }
}

double Frac(double x) { return x - std::floor(x); }

}  // namespace

MeshEvaluator::MeshEvaluator(const MeshPair& pair, const PairGeometry& g,
                             const MeshStiffnessOptions& options)
    : mesh_(pair.mesh), g_(g), pair_(pair, g) {
  options.Validate();
  const GearSpec& pinion = *pair.a;
  const GearSpec& wheel = *pair.b;
  overridden_ = !std::holds_alternative<PotentialEnergyStiffness>(mesh_->stiffness);
  load_ = pair.transmitted_torque / g.wheel.base;
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
  if (const auto* r = std::get_if<RectangularStiffness>(&mesh_->stiffness)) {
    law = {0.0, r->contact_ratio - 1.0};
  } else if (const auto* t = std::get_if<TableStiffness>(&mesh_->stiffness)) {
    law = t->phase;
  }
  // The drive flank reads the law at tau, the back flank at back_phase / p_b - tau (Evaluate).
  for (double& phase : law) {
    phase = Frac(flank == Flank::kDrive ? phase : back_phase_ / g_.base_pitch - phase);
  }
  return law;
}

FlankSample MeshEvaluator::Evaluate(double tau, Flank flank) const {
  const PairGeometry& g = g_;
  FlankSample out;
  const double s_drive = g.contact_start + tau * g.base_pitch;
  const double s0 = flank == Flank::kDrive ? s_drive : mirror_ - s_drive;
  // Shift by whole pitches to the first position at or after start - reach.
  const double first =
      s0 - std::floor((s0 - (g.contact_start - reach_)) / g.base_pitch) * g.base_pitch;
  for (double s = first; s <= g.contact_end + reach_ && out.pair_count < FlankSample::kMaxPairs;
       s += g.base_pitch) {
    PairState& p = out.pairs[out.pair_count++];
    p.roll = s;
    p.stiffness = pair_.At(s);
    p.separation = Separation(s);
  }
  ShareLoad(out, load_);
  if (overridden_) {
    // User data replaces the stiffness; share equally among pairs inside the path.
    const double tau_flank = flank == Flank::kDrive ? tau : back_phase_ / g.base_pitch - tau;
    out.stiffness = OverrideStiffness(mesh_->stiffness, tau_flank);
    int in_path = 0;
    for (int m = 0; m < out.pair_count; ++m) {
      in_path += (out.pairs[m].roll >= g.contact_start && out.pairs[m].roll <= g.contact_end);
    }
    for (int m = 0; m < out.pair_count; ++m) {
      const bool in = out.pairs[m].roll >= g.contact_start && out.pairs[m].roll <= g.contact_end;
      out.pairs[m].load_share = in && in_path > 0 ? 1.0 / in_path : 0.0;
    }
    out.loaded_pairs = in_path;
    out.lste = load_ / out.stiffness;
  }
  for (int m = 0; m < out.pair_count; ++m) {
    const PairState& p = out.pairs[m];
    const double sgn = p.roll > g.pitch_point ? 1.0 : (p.roll < g.pitch_point ? -1.0 : 0.0);
    out.friction_sigma += p.load_share * sgn;
    out.friction_arm_pinion += p.load_share * sgn * p.roll;
    out.friction_arm_wheel += p.load_share * sgn * (g.line_of_action_length - p.roll);
  }
  return out;
}

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
  for (int i = 0; i < n; ++i) {
    const double tau = (i + 0.5) / n;
    cycle.tau[i] = tau;
    cycle.drive[i] = evaluator.Evaluate(tau, Flank::kDrive);
    cycle.back[i] = evaluator.Evaluate(tau, Flank::kBack);
  }
  return cycle;
}

MeshStiffnessSummary SummarizeMeshCycle(const MeshCycle& cycle, const PairGeometry& g) {
  MeshStiffnessSummary s;
  s.contact_ratio = g.contact_ratio;
  const size_t n = cycle.drive.size();
  s.min = s.max = cycle.drive[0].stiffness;
  double lste_min = cycle.drive[0].lste, lste_max = lste_min;
  double single_sum = 0.0, double_sum = 0.0, sum = 0.0;
  int single_n = 0, double_n = 0;
  for (const FlankSample& d : cycle.drive) {
    sum += d.stiffness;
    s.min = std::min(s.min, d.stiffness);
    s.max = std::max(s.max, d.stiffness);
    lste_min = std::min(lste_min, d.lste);
    lste_max = std::max(lste_max, d.lste);
    if (d.loaded_pairs == 1) single_sum += d.stiffness, ++single_n;
    if (d.loaded_pairs == 2) double_sum += d.stiffness, ++double_n;
    for (int m = 0; m < d.pair_count; ++m)
      s.load_sharing_max = std::max(s.load_sharing_max, d.pairs[m].load_share);
  }
  s.mean = sum / static_cast<double>(n);
  s.single_pair_mean = single_n ? single_sum / single_n : 0.0;
  s.double_pair_mean = double_n ? double_sum / double_n : 0.0;
  s.lste_peak_to_peak = lste_max - lste_min;
  return s;
}

}  // namespace gearnvh
