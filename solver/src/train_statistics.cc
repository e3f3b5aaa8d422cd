#include "gearnvh/solver/train_statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gearnvh {

void TrainRecorder::Running::Add(double x, bool first) {
  sum += x;
  sum2 += x * x;
  min = first ? x : std::min(min, x);
  max = first ? x : std::max(max, x);
}

TrainRecorder::TrainRecorder(const TrainTables& tables, int samples_per_cycle, double start_time)
    : t_(tables), start_(start_time), next_(start_time) {
  double shortest = std::numeric_limits<double>::infinity();
  for (const TrainMeshTable& mt : tables.meshes) shortest = std::min(shortest, mt.period);
  dt_ = shortest / std::max(samples_per_cycle, 1);
  const size_t meshes = tables.meshes.size();
  te_.resize(meshes);
  force_.resize(meshes);
  acceleration_.resize(static_cast<size_t>(tables.n));
  free_time_.assign(meshes, 0.0);
  impact_sum2_.assign(meshes, 0.0);
  impact_max_.assign(meshes, 0.0);
  drive_impacts_.assign(meshes, 0);
  back_impacts_.assign(meshes, 0);
  separations_.assign(meshes, 0);
  grazing_.assign(meshes, 0);
}

void TrainRecorder::KeepTeSeries(double from_time, long max_samples) {
  keep_from_ = from_time;
  keep_max_ = std::max(0L, max_samples);
  te_series_.assign(t_.meshes.size(), {});
  for (std::vector<double>& series : te_series_) series.reserve(static_cast<size_t>(keep_max_));
}

void TrainRecorder::Sample(double time, const Eigen::VectorXd& z, const TrainSystem& system,
                           const std::vector<int>& segments,
                           const std::vector<ContactState>& states) {
  const int n = t_.n;
  const bool first = samples_ == 0;
  for (size_t i = 0; i < t_.meshes.size(); ++i) {
    const TrainMeshTable& mt = t_.meshes[i];
    const double te = mt.v.dot(z.head(n));
    const double rate = mt.v.dot(z.segment(n, n));
    const size_t j = static_cast<size_t>(segments[i]);
    double force = 0.0;
    if (states[i] == ContactState::kDrive) {
      force = mt.k_drive[j] * (te - mt.error[j] - mt.half_backlash) + mt.damping * rate;
    } else if (states[i] == ContactState::kBack) {
      force = mt.k_back[j] * (te - mt.error[j] + mt.half_backlash) + mt.damping * rate;
    }
    te_[i].Add(te, first);
    // Half a sample interval of slack: sample times are start + k dt, rounded.
    if (keep_max_ > 0 && time >= keep_from_ - 0.5 * dt_ &&
        static_cast<long>(te_series_[i].size()) < keep_max_) {
      te_series_[i].push_back(te);
    }
    force_[i].Add(force, first);
  }
  for (int b = 0; b < n; ++b) {
    if (t_.loose[static_cast<size_t>(b)])
      acceleration_[static_cast<size_t>(b)].Add(system.A.row(n + b).dot(z), first);
  }
  ++samples_;
  next_ = start_ + static_cast<double>(samples_) * dt_;
}

void TrainRecorder::Interval(double start, double length, const std::vector<ContactState>& states) {
  const double counted = std::max(0.0, start + length - std::max(start, start_));
  if (counted <= 0.0) return;
  recorded_ += counted;
  for (size_t i = 0; i < states.size(); ++i)
    if (states[i] == ContactState::kFree) free_time_[i] += counted;
}

void TrainRecorder::Event(int mesh, ContactState from, ContactState to, double time, double rate) {
  if (time < start_) return;
  const size_t i = static_cast<size_t>(mesh);
  if (to == ContactState::kFree) {
    ++separations_[i];
    return;
  }
  if (from != ContactState::kFree) return;
  (to == ContactState::kDrive ? drive_impacts_ : back_impacts_)[i] += 1;
  impact_sum2_[i] += rate * rate;
  impact_max_[i] = std::max(impact_max_[i], std::abs(rate));
}

void TrainRecorder::Grazing(int mesh, double time) {
  if (time >= start_) ++grazing_[static_cast<size_t>(mesh)];
}

TrainStatistics TrainRecorder::Result() const {
  TrainStatistics out;
  out.recorded_time = recorded_;
  out.samples = samples_;
  const double count = static_cast<double>(std::max(samples_, 1L));
  const auto rms_about_mean = [&](const Running& r) {
    const double mean = r.sum / count;
    return std::sqrt(std::max(0.0, r.sum2 / count - mean * mean));
  };
  for (size_t i = 0; i < t_.meshes.size(); ++i) {
    TrainMeshStatistics s;
    s.name = t_.meshes[i].name;
    s.te_mean = te_[i].sum / count;
    s.te_rms = rms_about_mean(te_[i]);
    s.te_peak_to_peak = te_[i].max - te_[i].min;
    s.force_mean = force_[i].sum / count;
    s.force_max = force_[i].max;
    s.drive_impacts = drive_impacts_[i];
    s.back_impacts = back_impacts_[i];
    s.separations = separations_[i];
    s.grazing = grazing_[i];
    s.free_time_fraction = recorded_ > 0.0 ? free_time_[i] / recorded_ : 0.0;
    const long impacts = s.drive_impacts + s.back_impacts;
    s.impact_velocity_max = impact_max_[i];
    s.impact_velocity_rms =
        impacts > 0 ? std::sqrt(impact_sum2_[i] / static_cast<double>(impacts)) : 0.0;
    out.meshes.push_back(s);
  }
  for (int b = 0; b < t_.n; ++b) {
    if (!t_.loose[static_cast<size_t>(b)]) continue;
    TrainLooseGearStatistics g;
    g.name = t_.body_names[static_cast<size_t>(b)];
    g.body = b;
    g.rattle_index = rms_about_mean(acceleration_[static_cast<size_t>(b)]);
    for (size_t i = 0; i < t_.meshes.size(); ++i) {
      if (t_.meshes[i].body_a == b || t_.meshes[i].body_b == b)
        g.impacts += out.meshes[i].drive_impacts + out.meshes[i].back_impacts;
    }
    out.loose_gears.push_back(g);
  }
  std::stable_sort(out.loose_gears.begin(), out.loose_gears.end(),
                   [](const auto& a, const auto& b) { return a.rattle_index > b.rattle_index; });
  for (size_t k = 0; k < out.loose_gears.size(); ++k)
    out.loose_gears[k].rank = static_cast<int>(k) + 1;
  return out;
}

}  // namespace gearnvh
