#include "gearnvh/model/mesh_segmentation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/quadrature.h"

namespace gearnvh {
namespace {

// Bisects the loaded-pair count change between a (count ca) and b.
double LocateTransition(const MeshEvaluator& ev, Flank flank, double a, double b) {
  const int ca = ev.Evaluate(a, flank).loaded_pairs;
  for (int it = 0; it < 60 && b - a > 1e-13; ++it) {
    const double m = 0.5 * (a + b);
    if (ev.Evaluate(m, flank).loaded_pairs == ca)
      a = m;
    else
      b = m;
  }
  return 0.5 * (a + b);
}

// Adds w * d delta / d e_i of every loaded pair at one sample to `weights` (keyed by the pair's
// offset q).
void AddErrorWeights(const MeshEvaluator& ev, const FlankSample& sample, double w,
                     std::vector<std::pair<int, double>>& weights) {
  double loaded_stiffness = 0.0;
  for (int i = 0; i < sample.pair_count; ++i) {
    if (sample.pairs[i].load_share > 0.0) loaded_stiffness += sample.pairs[i].stiffness;
  }
  for (int i = 0; i < sample.pair_count; ++i) {
    const PairState& p = sample.pairs[i];
    if (!(p.load_share > 0.0)) continue;
    // An override's pair stiffnesses are unknown: its pairs share equally (load_share = 1/count).
    const double sensitivity = ev.overridden() ? p.load_share : p.stiffness / loaded_stiffness;
    const int q = p.offset;
    auto it = std::find_if(weights.begin(), weights.end(),
                           [q](const std::pair<int, double>& e) { return e.first == q; });
    if (it == weights.end()) {
      weights.emplace_back(q, w * sensitivity);
    } else {
      it->second += w * sensitivity;
    }
  }
}

double UserSte(const StaticTransmissionError& ste, double tau) {
  double e = 0.0;
  for (size_t n = 0; n < ste.amplitudes.size(); ++n) {
    e += ste.amplitudes[n] *
         std::cos(2.0 * std::numbers::pi * static_cast<double>(n + 1) * tau + ste.phases[n]);
  }
  return e;
}

}  // namespace

MeshSegmentation SegmentMeshCycle(const MeshPair& pair, const MeshEvaluator& ev,
                                  int segments_per_cycle, int scan_samples) {
  MeshSegmentation out;
  std::vector<double> breaks{0.0};
  for (Flank flank : {Flank::kDrive, Flank::kBack}) {
    breaks.push_back(ev.PitchCrossing(flank));
    for (double b : ev.OverrideBreaks(flank)) breaks.push_back(b);
    int previous = ev.Evaluate(0.0, flank).loaded_pairs;
    for (int i = 1; i <= scan_samples; ++i) {
      const double tau = static_cast<double>(i) / scan_samples;
      const int count = ev.Evaluate(tau, flank).loaded_pairs;
      if (count != previous) {
        breaks.push_back(
            LocateTransition(ev, flank, static_cast<double>(i - 1) / scan_samples, tau));
      }
      previous = count;
    }
  }
  for (double& b : breaks) b -= std::floor(b);
  std::sort(breaks.begin(), breaks.end());
  std::vector<double> unique;
  for (double b : breaks) {
    if (unique.empty() || b - unique.back() > 1e-9) unique.push_back(b);
  }
  if (unique.size() > 1 && 1.0 - unique.back() < 1e-9) unique.pop_back();
  out.mandatory_breaks = unique;
  const int intervals = static_cast<int>(unique.size());
  if (segments_per_cycle < intervals) {
    throw InputError("analysis.segments_per_cycle", 0, std::to_string(segments_per_cycle),
                     "must be >= " + std::to_string(intervals) +
                         " (the contact-count transitions, pitch-point crossings and stiffness "
                         "override switches of this pair)");
  }
  // Largest-remainder allocation of segments to intervals, at least one each.
  std::vector<double> length(intervals);
  for (int i = 0; i < intervals; ++i) {
    length[i] = (i + 1 < intervals ? unique[i + 1] : 1.0) - unique[i];
  }
  std::vector<int> count(intervals, 1);
  int remaining = segments_per_cycle - intervals;
  std::vector<double> want(intervals);
  for (int i = 0; i < intervals; ++i) want[i] = length[i] * segments_per_cycle;
  while (remaining > 0) {
    int best = 0;
    double best_deficit = -1e300;
    for (int i = 0; i < intervals; ++i) {
      const double deficit = want[i] - count[i];
      if (deficit > best_deficit) best_deficit = deficit, best = i;
    }
    ++count[best];
    --remaining;
  }
  const GaussLegendreRule rule = MakeGaussLegendre(8);
  const double load = ev.load();
  for (int i = 0; i < intervals; ++i) {
    for (int c = 0; c < count[i]; ++c) {
      MeshSegment seg;
      seg.tau_begin = unique[i] + length[i] * c / count[i];
      seg.tau_end = unique[i] + length[i] * (c + 1) / count[i];
      const double h = seg.tau_end - seg.tau_begin;
      double lste = 0.0, user = 0.0;
      for (size_t q = 0; q < rule.nodes.size(); ++q) {
        const double tau = seg.tau_begin + 0.5 * h * (1.0 + rule.nodes[q]);
        const double w = 0.5 * rule.weights[q];  // weights of the mean over the segment
        const FlankSample d = ev.Evaluate(tau, Flank::kDrive);
        const FlankSample b = ev.Evaluate(tau, Flank::kBack);
        seg.drive.stiffness += w * d.stiffness;
        seg.drive.friction_sigma += w * d.friction_sigma;
        seg.drive.friction_arm_pinion += w * d.friction_arm_pinion;
        seg.drive.friction_arm_wheel += w * d.friction_arm_wheel;
        seg.back.stiffness += w * b.stiffness;
        seg.back.friction_sigma += w * b.friction_sigma;
        seg.back.friction_arm_pinion += w * b.friction_arm_pinion;
        seg.back.friction_arm_wheel += w * b.friction_arm_wheel;
        lste += w * d.lste;
        AddErrorWeights(ev, d, w, seg.error_weights);
        user += w * UserSte(pair.mesh.static_transmission_error, tau);
      }
      seg.lste = lste;
      seg.unloaded_error = lste - load / seg.drive.stiffness + user;
      out.segments.push_back(seg);
    }
  }
  return out;
}

double CycleMeanStiffness(const MeshSegmentation& segmentation, Flank flank) {
  double mean = 0.0;
  for (const MeshSegment& s : segmentation.segments) {
    const FlankSegment& f = flank == Flank::kDrive ? s.drive : s.back;
    mean += f.stiffness * (s.tau_end - s.tau_begin);
  }
  return mean;
}

}  // namespace gearnvh
