#include "gearnvh/solver/train_statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "polynomial_statistics.h"

namespace gearnvh {

TrainRecorder::TrainRecorder(const TrainTables& tables, int samples_per_cycle, double start_time)
    : t_(tables), start_(start_time), next_(start_time) {
  double shortest = std::numeric_limits<double>::infinity();
  for (const TrainMeshTable& mt : tables.meshes) shortest = std::min(shortest, mt.period);
  dt_ = shortest / std::max(samples_per_cycle, 1);
  const size_t meshes = tables.meshes.size();
  te_.resize(meshes);
  force_.resize(meshes);
  acceleration_.resize(static_cast<size_t>(tables.bodies()));
  taylor_.resize(tables.m, kTerms + 1);
  tracked_rows_.resize(0, tables.m);
  chunk_z_.resize(tables.m);
  const int n = tables.n;
  te_rows_.resize(static_cast<Eigen::Index>(meshes), n);
  back_rows_.resize(static_cast<Eigen::Index>(meshes), n);
  for (size_t i = 0; i < meshes; ++i) {
    const TrainMeshTable& mt = tables.meshes[i];
    te_rows_.row(static_cast<Eigen::Index>(i)) = mt.v.transpose();
    back_rows_.row(static_cast<Eigen::Index>(i)) = (mt.distinct_back ? mt.v_back : mt.v).transpose();
  }
  for (int b = 0; b < tables.bodies(); ++b) {
    if (tables.loose[static_cast<size_t>(b)]) loose_bodies_.push_back(b);
  }
  loose_rows_.resize(static_cast<Eigen::Index>(loose_bodies_.size()), n);
  for (size_t l = 0; l < loose_bodies_.size(); ++l)
    loose_rows_.row(static_cast<Eigen::Index>(l)) = tables.body_angles.row(loose_bodies_[l]);
  te_coefficients_.resize(te_rows_.rows(), kTerms + 1);
  back_coefficients_.resize(back_rows_.rows(), kTerms + 1);
  acceleration_coefficients_.resize(loose_rows_.rows(), kTerms);
  free_time_.assign(meshes, 0.0);
  impact_sum2_.assign(meshes, 0.0);
  impact_max_.assign(meshes, 0.0);
  drive_impacts_.assign(meshes, 0);
  back_impacts_.assign(meshes, 0);
  separations_.assign(meshes, 0);
  grazing_.assign(meshes, 0);
}

void TrainRecorder::KeepSeries(double from_time, long max_samples, bool histories,
                               Eigen::Index tracked_rows) {
  keep_from_ = from_time;
  keep_max_ = std::max(0L, max_samples);
  keep_histories_ = histories;
  const size_t meshes = static_cast<size_t>(t_.gear_meshes),
               reserved = static_cast<size_t>(keep_max_);
  te_series_.assign(meshes, {});
  force_series_.assign(histories ? meshes : 0, {});
  contact_series_.assign(histories ? meshes : 0, {});
  for (std::vector<double>& series : te_series_) series.reserve(reserved);
  for (std::vector<double>& series : force_series_) series.reserve(reserved);
  for (std::vector<ContactState>& series : contact_series_) series.reserve(reserved);
  const Eigen::Index rows = std::clamp<Eigen::Index>(tracked_rows, 0, tracked_rows_.rows());
  tracked_series_.assign(static_cast<size_t>(rows), {});
  for (std::vector<double>& series : tracked_series_) series.reserve(reserved);
  tracked_values_.resize(rows);
}

void TrainRecorder::Track(const RowMatrix& rows, Eigen::Index at) {
  // No block of an empty matrix: its null data pointer may not be offset (UBSan).
  const Eigen::Index after = tracked_rows_.rows() - at;
  RowMatrix all(at + rows.rows() + after, t_.m);
  if (at > 0) all.topRows(at) = tracked_rows_.topRows(at);
  if (rows.rows() > 0) all.middleRows(at, rows.rows()) = rows;
  if (after > 0) all.bottomRows(after) = tracked_rows_.bottomRows(after);
  tracked_rows_ = std::move(all);
  for (ContactTerm& term : contact_terms_) {  // rows after `at` moved down
    if (term.row >= at) term.row += rows.rows();
  }
  tracked_coefficients_.resize(tracked_rows_.rows(), kTerms + 1);
  tracked_.assign(static_cast<size_t>(tracked_rows_.rows()), {});
}

void TrainRecorder::TrackBearingForces() {
  if (bearing_rows_ > 0) return;
  bearing_rows_ = t_.bearing_force_rows.rows();
  Track(t_.bearing_force_rows, 0);
}

void TrainRecorder::TrackOutputs(const Eigen::MatrixXd& rows,
                                 const std::vector<ContactTerm>& terms) {
  const Eigen::Index at = tracked_rows_.rows();
  Track(rows, at);
  for (ContactTerm term : terms) {
    term.row += at;
    contact_terms_.push_back(term);
  }
}

void TrainRecorder::TakeSeries(std::vector<std::vector<double>>& te,
                               std::vector<std::vector<double>>& force,
                               std::vector<std::vector<ContactState>>& contact,
                               std::vector<std::vector<double>>& tracked) {
  te = std::move(te_series_);
  force = std::move(force_series_);
  contact = std::move(contact_series_);
  tracked = std::move(tracked_series_);
  te_series_.clear();
  force_series_.clear();
  contact_series_.clear();
  tracked_series_.clear();
  keep_max_ = 0;
}

void TrainRecorder::KeepEvents(long max_events) {
  keep_events_ = std::max(0L, max_events);
  events_.clear();
  events_.reserve(static_cast<size_t>(keep_events_));
}

double TrainRecorder::ForceAt(size_t mesh, const Eigen::VectorXd& z, int segment,
                              ContactState state) const {
  if (state == ContactState::kFree) return 0.0;
  // k (delta - wall) + c delta', the wall of the flank in contact (as Chunk).
  const TrainMeshTable& mt = t_.meshes[mesh];
  const bool drive = state == ContactState::kDrive;
  const Eigen::VectorXd& row = !drive && mt.distinct_back ? mt.v_back : mt.v;
  const int n = t_.n;
  const size_t j = static_cast<size_t>(segment);
  const double k_mesh = drive ? mt.k_drive[j] : mt.k_back[j];
  const double wall = t_.Wall(static_cast<int>(mesh), segment, drive, z);
  return k_mesh * (row.dot(z.head(n)) - wall) + mt.damping * row.dot(z.segment(n, n));
}

void TrainRecorder::Sample(double time, const Eigen::VectorXd& z, const std::vector<int>& segments,
                           const std::vector<ContactState>& states) {
  // Half a sample interval of slack: sample times are start + k dt, rounded.
  if (keep_max_ > 0 && time >= keep_from_ - 0.5 * dt_) {
    for (size_t i = 0; i < te_series_.size(); ++i) {
      if (static_cast<long>(te_series_[i].size()) >= keep_max_) continue;
      te_series_[i].push_back(t_.meshes[i].v.dot(z.head(t_.n)));
      if (!keep_histories_) continue;
      force_series_[i].push_back(ForceAt(i, z, segments[i], states[i]));
      contact_series_[i].push_back(states[i]);
    }
    if (!tracked_series_.empty() && static_cast<long>(tracked_series_.front().size()) < keep_max_) {
      tracked_values_.noalias() = tracked_rows_.topRows(tracked_values_.size()) * z;
      for (const ContactTerm& term : contact_terms_) {
        if (term.row >= tracked_values_.size()) continue;
        const auto c = static_cast<size_t>(term.contact);
        tracked_values_[term.row] += term.factor * ForceAt(c, z, segments[c], states[c]);
      }
      for (size_t r = 0; r < tracked_series_.size(); ++r) {
        tracked_series_[r].push_back(tracked_values_[static_cast<Eigen::Index>(r)]);
      }
    }
  }
  ++samples_;
  next_ = start_ + static_cast<double>(samples_) * dt_;
}

void TrainRecorder::TaylorColumns(const TrainSystem& system, const Eigen::VectorXd& z) {
  taylor_.col(0) = z;
  for (int k = 1; k <= kTerms; ++k) {
    taylor_.col(k).noalias() = system.A * taylor_.col(k - 1);
    taylor_.col(k) /= static_cast<double>(k);
  }
}

void TrainRecorder::MoveOnColumns(double tau, Eigen::VectorXd& z) const {
  z = taylor_.col(kTerms);
  for (int k = kTerms - 1; k >= 0; --k) {
    z *= tau;
    z += taylor_.col(k);
  }
}

void TrainRecorder::Piece(const TrainSystem& system, const Eigen::Ref<const Eigen::VectorXd>& z,
                          double start, double length, const std::vector<int>& segments,
                          const std::vector<ContactState>& states) {
  const double end = start + length;
  if (!(length > 0.0) || end <= start_) return;
  chunk_z_ = z;
  // Before the window: move the state to its start on sub-steps.
  if (start < start_) {
    const double skip = start_ - start;
    const int steps = std::max(1, static_cast<int>(std::ceil(skip / system.substep - 1e-9)));
    for (int c = 0; c < steps; ++c) {
      TaylorColumns(system, chunk_z_);
      MoveOnColumns(skip / steps, chunk_z_);
    }
    start = start_;
    length = end - start_;
  }
  const int chunks = std::max(1, static_cast<int>(std::ceil(length / system.substep - 1e-9)));
  const double step = length / chunks;
  for (int c = 0; c < chunks; ++c) {
    TaylorColumns(system, chunk_z_);
    Chunk(start + c * step, step, segments, states);
    if (c + 1 < chunks) MoveOnColumns(step, chunk_z_);
  }
}

void TrainRecorder::Chunk(double start, double length, const std::vector<int>& segments,
                          const std::vector<ContactState>& states) {
  namespace ps = polynomial_statistics;
  const int n = t_.n;
  const auto positions = taylor_.topRows(n);
  te_coefficients_.noalias() = te_rows_ * positions;
  // The tracked rows (bearing forces, couplings) act on positions and velocities: one product
  // with the Taylor columns; their contact terms are added with the contacts' forces below.
  if (tracked_rows_.rows() > 0) tracked_coefficients_.noalias() = tracked_rows_ * taylor_;
  double force[kTerms + 1];
  for (size_t i = 0; i < t_.meshes.size(); ++i) {
    const TrainMeshTable& mt = t_.meshes[i];
    const Eigen::Index row = static_cast<Eigen::Index>(i);
    const double* te = te_coefficients_.row(row).data();
    const ps::Poly delta = ps::Trimmed(te, kTerms, length);
    ps::Accumulate(te_[i], delta, length);
    ps::UpdateExtrema(delta, length, start, te_[i], true);
    if (states[i] == ContactState::kFree) {
      const double zero = 0.0;
      ps::Accumulate(force_[i], ps::Poly{&zero, 0}, length);
      ps::Consider(force_[i], 0.0, start, false);
      continue;
    }
    // k (delta - wall) + c delta', the wall of the flank in contact.
    const bool drive = states[i] == ContactState::kDrive;
    const size_t j = static_cast<size_t>(segments[i]);
    const double k_mesh = drive ? mt.k_drive[j] : mt.k_back[j];
    const double wall = t_.Wall(static_cast<int>(i), segments[i], drive, taylor_.col(0));
    // The back flank's own row from tier 2 on (its lateral terms differ from the TE row's).
    const double* flank = te;
    if (!drive && mt.distinct_back) {
      back_coefficients_.row(row).noalias() = back_rows_.row(row) * positions;
      flank = back_coefficients_.row(row).data();
    }
    for (int k = 0; k <= kTerms; ++k) {
      const double rate = k < kTerms ? (k + 1) * flank[k + 1] : 0.0;
      force[k] = k_mesh * flank[k] + mt.damping * rate;
    }
    force[0] -= k_mesh * wall;
    const ps::Poly f = ps::Trimmed(force, kTerms, length);
    ps::Accumulate(force_[i], f, length);
    ps::UpdateExtrema(f, length, start, force_[i], false);
    for (const ContactTerm& term : contact_terms_) {
      if (term.contact != static_cast<int>(i)) continue;
      for (int k = 0; k <= kTerms; ++k)
        tracked_coefficients_(term.row, k) += term.factor * force[k];
    }
  }
  // A loose body's acceleration is its velocity's derivative: (k + 1) times the next coefficient
  // of its angle row (body_angles; tier 1: its own coordinate) on the velocities.
  acceleration_coefficients_.noalias() = loose_rows_ * taylor_.block(n, 1, n, kTerms);
  for (size_t l = 0; l < loose_bodies_.size(); ++l) {
    double* accel = acceleration_coefficients_.row(static_cast<Eigen::Index>(l)).data();
    for (int k = 0; k < kTerms; ++k) accel[k] *= k + 1;
    ps::Accumulate(acceleration_[static_cast<size_t>(loose_bodies_[l])],
                   ps::Trimmed(accel, kTerms - 1, length), length);
  }
  if (tracked_rows_.rows() > 0) {
    for (size_t r = 0; r < tracked_.size(); ++r) {
      const ps::Poly f = ps::Trimmed(tracked_coefficients_.row(static_cast<Eigen::Index>(r)).data(),
                                     kTerms, length);
      ps::Accumulate(tracked_[r], f, length);
      ps::UpdateExtrema(f, length, start, tracked_[r], true);
    }
  }
  exact_duration_ += length;
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
  ++window_events_;
  if (static_cast<long>(events_.size()) < keep_events_)
    events_.push_back({mesh, {time, from, to, rate}});
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
  const double T = exact_duration_;
  for (size_t i = 0; i < static_cast<size_t>(t_.gear_meshes); ++i) {
    TrainMeshStatistics s;
    s.name = t_.meshes[i].name;
    if (T > 0.0) {
      s.te_mean = te_[i].Mean(T);
      s.te_rms = te_[i].Rms(T);
      s.te_peak_to_peak = te_[i].max - te_[i].min;
      s.force_mean = force_[i].Mean(T);
      s.force_max = force_[i].max;
    }
    s.drive_impacts = drive_impacts_[i];
    s.back_impacts = back_impacts_[i];
    s.separations = separations_[i];
    s.grazing = grazing_[i];
    s.free_time_fraction = recorded_ > 0.0 ? free_time_[i] / recorded_ : 0.0;
    const long impacts = s.drive_impacts + s.back_impacts;
    s.impact_velocity_max = impact_max_[i];
    s.impact_velocity_rms =
        impacts > 0 ? std::sqrt(impact_sum2_[i] / static_cast<double>(impacts)) : 0.0;
    s.impact_energy = 0.5 * t_.meshes[i].effective_mass * impact_sum2_[i];
    out.meshes.push_back(s);
  }
  for (size_t i = static_cast<size_t>(t_.gear_meshes); i < t_.meshes.size(); ++i) {
    const TrainMeshTable& mt = t_.meshes[i];
    out.coupling_stages.push_back(
        {mt.name, mt.coupling, mt.stage, drive_impacts_[i] + back_impacts_[i], drive_impacts_[i],
         back_impacts_[i], recorded_ > 0.0 ? 1.0 - free_time_[i] / recorded_ : 0.0});
  }
  for (int b = 0; b < t_.bodies(); ++b) {
    if (!t_.loose[static_cast<size_t>(b)]) continue;
    TrainLooseGearStatistics g;
    g.name = t_.body_names[static_cast<size_t>(b)];
    g.body = b;
    g.rattle_index = acceleration_[static_cast<size_t>(b)].Rms(T);
    double sum2 = 0.0, energy = 0.0;
    for (size_t i = 0; i < out.meshes.size(); ++i) {
      if (t_.meshes[i].body_a != b && t_.meshes[i].body_b != b) continue;
      const TrainMeshStatistics& m = out.meshes[i];
      g.drive_impacts += m.drive_impacts;
      g.back_impacts += m.back_impacts;
      g.impact_velocity_max = std::max(g.impact_velocity_max, m.impact_velocity_max);
      sum2 += impact_sum2_[i];
      energy += m.impact_energy;
    }
    g.impacts = g.drive_impacts + g.back_impacts;
    g.impact_velocity_rms = g.impacts > 0 ? std::sqrt(sum2 / static_cast<double>(g.impacts)) : 0.0;
    if (recorded_ > 0.0) {
      g.drive_impacts_per_second = static_cast<double>(g.drive_impacts) / recorded_;
      g.back_impacts_per_second = static_cast<double>(g.back_impacts) / recorded_;
      g.impact_energy_per_second = energy / recorded_;
    }
    out.loose_gears.push_back(g);
  }
  for (size_t r = 0; r < tracked_.size(); ++r) {
    const OutputStatistics& f = tracked_[r];
    (static_cast<Eigen::Index>(r) < bearing_rows_ ? out.bearing_forces : out.outputs)
        .push_back(T > 0.0 ? TrainOutputSummary{f.Mean(T), f.Rms(T), f.min, f.max}
                           : TrainOutputSummary{});
  }
  // Impacting gears by impact energy per second; the others after them, in body order, rank 0.
  std::stable_sort(out.loose_gears.begin(), out.loose_gears.end(), [](const auto& a, const auto& b) {
    if ((a.impacts > 0) != (b.impacts > 0)) return a.impacts > 0;
    return a.impact_energy_per_second > b.impact_energy_per_second;
  });
  for (size_t k = 0; k < out.loose_gears.size(); ++k) {
    if (out.loose_gears[k].impacts > 0) out.loose_gears[k].rank = static_cast<int>(k) + 1;
  }
  return out;
}

}  // namespace gearnvh
