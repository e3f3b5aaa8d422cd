#include "gearnvh/model/manufacturing_errors.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace gearnvh {

namespace {

double Spread(const std::vector<double>& f) {
  if (f.empty()) return 0.0;
  const auto [lo, hi] = std::minmax_element(f.begin(), f.end());
  return *hi - *lo;
}

double LargestMagnitude(const std::vector<double>& f) {
  double m = 0.0;
  for (double v : f) m = std::max(m, std::abs(v));
  return m;
}

}  // namespace

MeshErrorExcitation::MeshErrorExcitation(const MeshPair& pair,
                                         const MeshSegmentation& segmentation) {
  const GearSpec* gears[2] = {&pair.a, &pair.b};
  speeds_[0] = pair.speed_a;
  speeds_[1] = pair.speed_a * pair.a.teeth / static_cast<double>(pair.b.teeth);
  for (int g = 0; g < 2; ++g) {
    teeth_[g] = gears[g]->teeth;
    if (gears[g]->runout && gears[g]->runout->amplitude > 0.0) {
      runout_[g] = *gears[g]->runout;
      active_ = true;
    }
    if (!gears[g]->pitch_errors.empty() && LargestMagnitude(gears[g]->pitch_errors) > 0.0) {
      pitch_[g] = gears[g]->pitch_errors;
      active_ = true;
    }
    // The weights of one sample sum to 1, so the pitch part is bounded by the largest deviations.
    bound_ += runout_[g].amplitude + LargestMagnitude(pitch_[g]);
    spread_ += Spread(pitch_[g]);
  }
  if (!active_) return;
  // Whole revolutions of every gear that carries an error.
  for (int g = 0; g < 2; ++g) {
    if (runout_[g].amplitude > 0.0 || !pitch_[g].empty()) {
      period_ = std::lcm(period_, static_cast<long>(teeth_[g]));
    }
  }
  weights_.reserve(segmentation.segments.size());
  for (const MeshSegment& s : segmentation.segments) weights_.push_back(s.error_weights);
}

double MeshErrorExcitation::SegmentMean(long cycle, int segment, double t0, double h) const {
  if (!active_) return 0.0;
  double e = 0.0;
  for (int g = 0; g < 2; ++g) {
    const Runout& r = runout_[g];
    if (r.amplitude > 0.0) {
      const double w = speeds_[g];
      e += r.amplitude * (std::cos(w * t0 + r.phase) - std::cos(w * (t0 + h) + r.phase)) / (w * h);
    }
  }
  for (const auto& [q, weight] : weights_[static_cast<size_t>(segment)]) {
    for (int g = 0; g < 2; ++g) {
      if (pitch_[g].empty()) continue;
      const long tooth = ((cycle - q) % teeth_[g] + teeth_[g]) % teeth_[g];
      e += weight * pitch_[g][static_cast<size_t>(tooth)];
    }
  }
  return e;
}

MeshErrorExcitation MeshErrorExcitation::AtSpeed(double speed_a) const {
  MeshErrorExcitation out = *this;
  if (speed_a == speeds_[0]) return out;  // bit for bit as built
  out.speeds_[0] = speed_a;
  out.speeds_[1] = speed_a * teeth_[0] / static_cast<double>(teeth_[1]);  // as the constructor
  return out;
}

}  // namespace gearnvh
