#include "gearnvh/solver/cycle_output_rows.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "gearnvh/solver/exact_recorder.h"
#include "gearnvh/solver/solver_options.h"
#include "ordered_schur.h"
#include "polynomial_statistics.h"

namespace gearnvh {

namespace {

constexpr int K = ExactRecorder::kTerms;
constexpr double kDeadFraction = 0x1p-56;  // of an output's scale: below rounding
// Extremum candidates: the orbit's chunk extremum is exact to rounding; this margin (relative to
// the orbit's size) keeps the candidate test conservative.
constexpr double kCandidateMargin = 1e-13;

// sum_k |C[k][j]| L^k per column j: a bound of |p_j(s)| on [0, L].
Eigen::VectorXd ColumnBounds(const Eigen::MatrixXd& c, double length) {
  Eigen::VectorXd bound = Eigen::VectorXd::Zero(c.cols());
  double power = 1.0;
  for (int k = 0; k < c.rows(); ++k, power *= length) bound += power * c.row(k).cwiseAbs();
  return bound;
}

// The derivative's coefficients (k + 1) C[k + 1] (the last row zero).
Eigen::MatrixXd Derivative(const Eigen::MatrixXd& c) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(c.rows(), c.cols());
  for (int k = 0; k + 1 < c.rows(); ++k) d.row(k) = (k + 1) * c.row(k + 1);
  return d;
}

// The rows of sum_k C[k] s^k (value) or its derivative at s.
Eigen::RowVectorXd ValueRow(const Eigen::MatrixXd& c, double s) {
  Eigen::RowVectorXd v = c.row(c.rows() - 1);
  for (int k = static_cast<int>(c.rows()) - 2; k >= 0; --k) v = (v * s + c.row(k)).eval();
  return v;
}

}  // namespace

CycleOutputRows::CycleOutputRows(const SegmentTables& t, const ConstantContactCycle& cycle,
                                 const ExactRecorder& recorder, int samples_per_cycle,
                                 const std::atomic<bool>* cancel)
    : t_(t), cycle_(cycle) {
  const int n = t.n, m = t.m, e = 2 * n;
  const Eigen::VectorXcd& lambda = cycle.eigenvalues();
  const Eigen::MatrixXcd& V = cycle.eigenvectors();
  if (!cycle.has_orbit() || lambda.size() != e) return;
  const Eigen::FullPivLU<Eigen::MatrixXcd> lu(V);
  if (!lu.isInvertible()) return;
  const Eigen::MatrixXcd Vinv = lu.inverse();
  if ((V * Vinv - Eigen::MatrixXcd::Identity(e, e)).cwiseAbs().maxCoeff() > 1e-10) return;

  // The orbit refined to a fixed point of the stored map (residual in extended precision, then one
  // solve): the deviation from it is what the modal columns carry.
  orbit_ = cycle.orbit();
  const Eigen::MatrixXd& L = cycle.projector();
  const Eigen::MatrixXd Pq = L * cycle.map() * L;
  {
    const Eigen::MatrixXd B = Eigen::MatrixXd::Identity(e, e) - Pq.topLeftCorner(e, e) +
                              (Eigen::MatrixXd::Identity(e, e) - L.topLeftCorner(e, e));
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu_b(B);
    Eigen::VectorXd residual(e);
    for (int i = 0; i < e; ++i) {
      long double sum = -static_cast<long double>(orbit_[i]);
      for (int j = 0; j < m; ++j) sum += static_cast<long double>(Pq(i, j)) * orbit_[j];
      residual[i] = static_cast<double>(sum);
    }
    orbit_.head(e) += lu_b.solve(residual);
  }
  // In balanced coordinates (velocities over w_ref, as BalancedExpm): see the Schur basis below.
  const double w_ref = ReferenceFrequency(t.systems[0][static_cast<int>(cycle.state())].A, n);
  Eigen::VectorXd balance = Eigen::VectorXd::Ones(e);
  balance.tail(n).setConstant(1.0 / w_ref);
  // Amplitudes (Enter only): a_i = rows of V^-1, a complex pair as one mode.
  // The moduli |lambda_i| (EigenSolver on Pq) and those of the Schur blocks (dgees on the balanced
  // Pq) are two computations of one spectrum: each is exact for a matrix within ~e eps |Pq| of
  // Pq, so an eigenvalue moves by at most its condition number kappa_i (|left| |right| / |left^H
  // right|, here |V^-1 row| |V col|) times that (first order; LAPACK's error bound
  // eps |A| / s_i). Eigenvalues at that level (the mesh modes of a slow mesh cycle, ~1e-30) are
  // rounding: the two computations give unrelated values (4e-30 against 8e-31 and 2e-31 on
  // the quasi-static pair), so a mode belongs to a tail, and decays, within that tolerance.
  const double eigen_error = std::numeric_limits<double>::epsilon() * e;
  const double norm = Pq.topLeftCorner(e, e).norm();
  const double balanced_norm =
      (balance.asDiagonal() * Pq.topLeftCorner(e, e) * balance.cwiseInverse().asDiagonal()).norm();
  std::vector<int> order;
  for (int i = 0; i < e; ++i) {
    if (lambda[i].imag() >= 0.0) order.push_back(i);
  }
  Eigen::MatrixXd rows_e(e, e);
  int row = 0;
  for (int i : order) {
    rows_e.row(row++) = Vinv.row(i).real();
    if (lambda[i].imag() > 0.0) rows_e.row(row++) = Vinv.row(i).imag();
    amplitude_end_.push_back(row);
    mode_decay_.push_back(std::abs(lambda[i]));
    const double kappa = Vinv.row(i).norm() * V.col(i).norm();
    const double balanced_kappa = (Vinv.row(i) * balance.cwiseInverse().asDiagonal()).norm() *
                                  (balance.asDiagonal() * V.col(i)).norm();
    mode_tolerance_.push_back(eigen_error * (kappa * norm + balanced_kappa * balanced_norm));
  }
  modal_rows_ = rows_e.topRows(row) * L.topRows(e);
  // The columns: an ordered real Schur basis of the quotient map, Pq_e = U T U^T with the diagonal
  // blocks by |lambda| descending (LAPACK dgees, then dtrexc). The first K columns of U span the
  // invariant subspace of the K slowest eigenvalues (to rounding: U is orthonormal and T's lower
  // part is zero), so the coordinates y = U^T L (z - y*) of a dropped tail see only the tail's
  // modes and the state's rounding, unamplified. (Coordinates on the eigenvectors themselves carry
  // the rounding times cond(V), 1e5..1e7 here, which cancels only when every column is kept.)
  // In balanced coordinates (velocities over w_ref, as BalancedExpm): unbalanced, |Pq| ~ w_ref and
  // the computed invariant subspaces leak ~eps |Pq| / sep of the slow modes into the tail.
  const OrderedSchur schur = OrderedRealSchur(balance.asDiagonal() * Pq.topLeftCorner(e, e) *
                                              balance.cwiseInverse().asDiagonal());
  if (schur.info != OrderedSchur::Info::kSuccess) return;
  const Eigen::MatrixXd& U = schur.U;
  for (size_t b = 0; b < schur.block_start.size(); ++b) {
    block_start_.push_back(3 + schur.block_start[b]);
    block_decay_.push_back(schur.block_modulus[b]);
  }
  columns_ = 3 + e;
  Eigen::MatrixXd basis = Eigen::MatrixXd::Zero(m, columns_);
  basis.col(0) = orbit_;
  basis.col(1).head(n) = t.rigid_rotation;
  basis.col(2).segment(n, n) = t.rigid_rotation;
  basis.block(0, 3, e, e) = balance.cwiseInverse().asDiagonal() * U;
  projection_ = U.transpose() * balance.asDiagonal() * L.topRows(e);

  if (!PropagateColumns(recorder, samples_per_cycle, basis, cancel)) return;
  for (int j = 0; j < t.segments(); ++j) cycle_length_ += t.SegmentLength(j);
  candidate_.assign(chunks_.size(), 0);
  x_ = Eigen::VectorXd::Zero(columns_);
  d_ = Eigen::VectorXd::Zero(m);
  values_ = Eigen::VectorXd::Zero(samples_.rows());
  poly_ = Eigen::VectorXd::Zero(K + 1);
  usable_ = true;
}

// Propagates the basis columns through one cycle, chunk by chunk as the recorder cuts its pieces:
// samples, integrals, extremum data and the tail weights. False when a sample falls in no chunk.
bool CycleOutputRows::PropagateColumns(const ExactRecorder& recorder, int samples_per_cycle,
                                       const Eigen::MatrixXd& basis,
                                       const std::atomic<bool>* cancel) {
  const SegmentTables& t = t_;
  const ConstantContactCycle& cycle = cycle_;
  // Propagate the columns through one cycle, chunk by chunk as the recorder cuts its pieces.
  const ContactState state = cycle.state();
  const int s = static_cast<int>(state);
  const int P = std::max(samples_per_cycle, 1);
  const double sample_step = t.mesh_period / P;
  std::vector<double> sample_time(static_cast<size_t>(P));
  for (int k = 0; k < P; ++k) sample_time[static_cast<size_t>(k)] = k * sample_step;
  sample_chunk_.assign(static_cast<size_t>(P), -1);
  samples_ = Eigen::MatrixXd::Zero(kSampleValues * P, columns_);
  std::array<Eigen::VectorXd, kSampleValues> gains;
  for (auto& g : gains) g = Eigen::VectorXd::Zero(columns_);
  std::array<double, kSampleValues> scale{};
  for (Statistic& st : stats_) {
    st.integral = Eigen::RowVectorXd::Zero(columns_);
    st.square = Eigen::MatrixXd::Zero(columns_, columns_);
    st.gain = Eigen::VectorXd::Zero(columns_);
  }
  Eigen::MatrixXd X = basis, chunk_X;
  int next_sample = 0;
  for (int j = 0; j < t.segments(); ++j) {
    ThrowIfCancelled(cancel);
    const SegmentSystem& sys = t.systems[static_cast<size_t>(j)][s];
    const Eigen::MatrixXd& rows = recorder.chunk_rows(j, state);
    const double seg_length = t.SegmentLength(j);
    const double step = seg_length / t.substeps[static_cast<size_t>(j)];
    const int count = std::max(1, static_cast<int>(std::ceil(seg_length / step - 1e-9)));
    chunk_X = X;
    for (int c = 0; c < count; ++c) {
      const double offset = c * step;
      const double length = c + 1 == count ? seg_length - offset : step;
      const Eigen::MatrixXd coef = rows * chunk_X;  // 4 (K + 1) x columns
      const Eigen::MatrixXd te = coef.topRows(K + 1), force = coef.middleRows(K + 1, K + 1);
      const Eigen::MatrixXd pinion = coef.middleRows(2 * (K + 1), K + 1);
      const Eigen::MatrixXd wheel = coef.middleRows(3 * (K + 1), K + 1);
      const Eigen::MatrixXd te_rate = Derivative(te), accel = Derivative(wheel);
      const std::array<const Eigen::MatrixXd*, kSampleValues> values = {&te,     &te_rate, &force,
                                                                        &pinion, &wheel,   &accel};
      for (int o = 0; o < kSampleValues; ++o) {
        const Eigen::VectorXd bound = ColumnBounds(*values[o], length);
        gains[o] = gains[o].cwiseMax(bound);
        scale[o] = std::max(scale[o], std::abs((*values[o])(0, 0)));
      }
      const int chunk = static_cast<int>(chunks_.size());
      chunks_.push_back({j, offset, length});
      // Statistics relative to the orbit's value at the cycle start.
      const std::array<const Eigen::MatrixXd*, 3> stat_values = {&te, &force, &accel};
      for (int o = 0; o < 3; ++o) {
        Statistic& st = stats_[o];
        if (chunk == 0) {
          st.reference = (*stat_values[o])(0, 0);
          st.start_row = stat_values[o]->row(0);
        }
        Eigen::MatrixXd shifted = *stat_values[o];
        shifted(0, 0) -= st.reference;
        double power = length;
        for (int k = 0; k <= K; ++k, power *= length)
          st.integral += power / (k + 1) * shifted.row(k);
        Eigen::MatrixXd H(K + 1, K + 1);
        for (int k = 0; k <= K; ++k) {
          for (int l = 0; l <= K; ++l) H(k, l) = std::pow(length, k + l + 1) / (k + l + 1);
        }
        st.square += shifted.transpose() * H * shifted;
        st.scale = std::max(st.scale, ColumnBounds(*stat_values[o], length)[0]);
        if (o < 2) {
          st.gain = st.gain.cwiseMax(ColumnBounds(*stat_values[o], length));
          OutputStatistics orbit;
          const Eigen::VectorXd a = stat_values[o]->col(0);
          const polynomial_statistics::Poly p =
              polynomial_statistics::Trimmed(a.data(), ExactRecorder::kTerms, length);
          polynomial_statistics::UpdateExtrema(p, length, 0.0, orbit, true);
          st.coefficients.push_back(*stat_values[o]);
          st.orbit_max.push_back(orbit.max);
          st.orbit_min.push_back(orbit.min);
        }
      }
      // Samples in this chunk (one on its end belongs to the next, as in ExactRecorder).
      const double end =
          t.boundaries[static_cast<size_t>(j)] + offset + length - 1e-9 * sample_step;
      for (; next_sample < P && sample_time[static_cast<size_t>(next_sample)] < end;
           ++next_sample) {
        const double at = sample_time[static_cast<size_t>(next_sample)] -
                          (t.boundaries[static_cast<size_t>(j)] + offset);
        sample_chunk_[static_cast<size_t>(next_sample)] = chunk;
        for (int o = 0; o < kSampleValues; ++o) {
          samples_.row(kSampleValues * next_sample + o) = ValueRow(*values[o], at);
        }
      }
      if (c + 1 < count) chunk_X = (sys.substep * chunk_X).eval();
    }
    X = (sys.full * X).eval();
  }
  if (next_sample < P) return false;  // every sample must fall in a chunk
  // Per Schur block i, the largest output of the tail of columns from it, relative to each
  // output's scale: W_i = max_o (sum_{j >= start_i} g_{o,j}) / scale_o.
  for (int start : block_start_) {
    double weight = 0.0;
    for (int o = 0; o < kSampleValues; ++o) {
      const double g = gains[o].tail(columns_ - start).sum();
      if (g > 0.0) {
        weight = std::max(weight,
                          scale[o] > 0.0 ? g / scale[o] : std::numeric_limits<double>::infinity());
      }
    }
    tail_weight_.push_back(weight);
  }
  for (Statistic& st : stats_) {
    const int chunks = static_cast<int>(st.orbit_max.size());
    st.by_max.resize(static_cast<size_t>(chunks));
    std::iota(st.by_max.begin(), st.by_max.end(), 0);
    st.by_min = st.by_max;
    std::sort(st.by_max.begin(), st.by_max.end(),
              [&](int a, int b) { return st.orbit_max[a] > st.orbit_max[b]; });
    std::sort(st.by_min.begin(), st.by_min.end(),
              [&](int a, int b) { return st.orbit_min[a] < st.orbit_min[b]; });
  }
  return true;
}

size_t CycleOutputRows::bytes() const {
  size_t total = sizeof(double) * (projection_.size() + modal_rows_.size() + samples_.size());
  for (const Statistic& st : stats_) {
    total += sizeof(double) * (st.integral.size() + st.square.size());
    for (const Eigen::MatrixXd& c : st.coefficients) total += sizeof(double) * c.size();
  }
  return total;
}

void CycleOutputRows::Enter(long cycle, const Eigen::VectorXd& z) {
  d_ = z - orbit_;
  const Eigen::VectorXd a = modal_rows_ * d_;
  // The last cycle in which a mode of amplitude `size` (times its weight) is still alive.
  auto last_live = [&](double size, double decay) {
    if (!(size > kDeadFraction)) return cycle - 1;
    if (decay >= 1.0 || !std::isfinite(size)) return std::numeric_limits<long>::max();
    if (decay == 0.0) return cycle;
    const double cycles = std::log(kDeadFraction / size) / std::log(decay);
    return cycles > 1e15 ? std::numeric_limits<long>::max()
                         : cycle + static_cast<long>(std::ceil(cycles));
  };
  std::vector<double> amplitude(mode_decay_.size());
  int begin = 0;
  for (size_t j = 0; j < mode_decay_.size(); ++j) {
    amplitude[j] = a.segment(begin, amplitude_end_[j] - begin).norm();
    begin = amplitude_end_[j];
  }
  // The tail from block i holds the modes with |lambda| <= |lambda_i| (their span is orthogonal to
  // the blocks before i); each contributes at most |a_j| |lambda_j|^k W_i to an output.
  const size_t blocks = block_start_.size();
  tail_last_.assign(blocks + 1, cycle - 1);
  // A mode counts in the tail when its modulus may be the block's (both known to the mode's
  // tolerance, constructor), and decays at its modulus plus that tolerance.
  auto in_tail = [&](size_t j, size_t i) {
    return mode_decay_[j] <= block_decay_[i] * (1.0 + 1e-9) + mode_tolerance_[j];
  };
  for (size_t i = blocks; i-- > 0;) {
    int count = 0;
    for (size_t j = 0; j < mode_decay_.size(); ++j) count += in_tail(j, i) ? 1 : 0;
    long last = tail_last_[i + 1];
    for (size_t j = 0; j < mode_decay_.size(); ++j) {
      if (!in_tail(j, i)) continue;
      last = std::max(last, last_live(amplitude[j] * count * tail_weight_[i],
                                      mode_decay_[j] + mode_tolerance_[j]));
    }
    tail_last_[i] = last;
  }
  tail_block_ = blocks;
  entered_ = true;
}

void CycleOutputRows::Record(long cycle, double cycle_start, const Eigen::VectorXd& z,
                             double window_start, long& next_sample, long& dropped,
                             Trajectory& out) {
  // Columns 0 .. live - 1: the rigid ones and the Schur blocks before the first dead tail.
  while (tail_block_ > 0 && tail_last_[tail_block_ - 1] < cycle) --tail_block_;
  const int live = tail_block_ < block_start_.size() ? block_start_[tail_block_] : columns_;
  live_ = live;
  const int n = t_.n;
  d_ = z - orbit_;
  x_[0] = 1.0;
  x_[1] = t_.recenter_row.dot(d_.head(n));
  x_[2] = t_.recenter_row.dot(d_.segment(n, n));
  auto q = x_.segment(3, live - 3);
  q.noalias() = projection_.topRows(live - 3) * d_;
  const auto x = x_.head(live);

  // Samples.
  const int P = static_cast<int>(sample_chunk_.size());
  values_.noalias() = samples_.leftCols(live) * x;
  const double sample_step = t_.mesh_period / P;
  std::vector<TrajectorySample>& samples = out.samples;
  for (int k = 0; k < P; ++k, ++next_sample) {
    if (samples.size() >= samples.capacity()) {
      ++dropped;
      continue;
    }
    const double* v = values_.data() + kSampleValues * k;
    TrajectorySample sample;
    sample.time = window_start + static_cast<double>(next_sample) * sample_step;
    sample.te = v[0];
    sample.te_rate = v[1];
    sample.mesh_force = v[2];
    sample.pinion_speed = v[3];
    sample.wheel_speed = v[4];
    sample.wheel_acceleration = v[5];
    sample.state = cycle_.state();
    samples.push_back(sample);
  }

  // Statistics: extrema first (in time order, as the chunk-by-chunk recorder meets them).
  TrajectoryStatistics& stats = out.statistics;
  Extrema(stats_[0], stats.te, cycle_start, true, live);
  Extrema(stats_[1], stats.mesh_force, cycle_start, false, live);
  Accumulate(stats_[0], stats.te, live);
  Accumulate(stats_[1], stats.mesh_force, live);
  Accumulate(stats_[2], stats.wheel_acceleration, live);
  // Each piece's length as the stepping loop forms it (its end time minus its start time).
  for (int j = 0; j < t_.segments(); ++j) {
    const double start = cycle_start + t_.boundaries[static_cast<size_t>(j)];
    stats.duration += (start + t_.SegmentLength(j)) - start;
  }
  stats.pieces += t_.segments();
  stats.chunks += static_cast<long>(chunks_.size());
  ++stats.row_cycles;
}

void CycleOutputRows::Accumulate(const Statistic& st, OutputStatistics& out, int live) {
  const auto x = x_.head(live);
  const double first = st.integral.head(live).dot(x);
  const double second =
      x.dot(st.square.topLeftCorner(live, live).selfadjointView<Eigen::Upper>() * x);
  if (!out.has_offset) {
    out.offset = st.start_row.head(live).dot(x);
    out.has_offset = true;
  }
  // int (y - o) = int (y - y0) + (y0 - o) T and int (y - o)^2 likewise, with y0 - o small.
  const double shift = st.reference - out.offset;
  out.integral += static_cast<long double>(first + shift * cycle_length_);
  out.square_integral +=
      static_cast<long double>(second + 2.0 * shift * first + shift * shift * cycle_length_);
}

void CycleOutputRows::Extrema(Statistic& st, OutputStatistics& out, double cycle_start,
                              bool want_min, int live) {
  const auto x = x_.head(live);
  const double bound =
      st.gain.segment(1, live - 1).dot(x.tail(live - 1).cwiseAbs()) + kCandidateMargin * st.scale;
  const int chunks = static_cast<int>(chunks_.size());
  for (int c : st.by_max) {
    if (!(st.orbit_max[static_cast<size_t>(c)] + bound >= out.max)) break;
    candidate_[static_cast<size_t>(c)] = 1;
  }
  if (want_min) {
    for (int c : st.by_min) {
      if (!(st.orbit_min[static_cast<size_t>(c)] - bound <= out.min)) break;
      candidate_[static_cast<size_t>(c)] = 1;
    }
  }
  for (int c = 0; c < chunks; ++c) {
    if (!candidate_[static_cast<size_t>(c)]) continue;
    candidate_[static_cast<size_t>(c)] = 0;
    const Chunk& chunk = chunks_[static_cast<size_t>(c)];
    poly_.noalias() = st.coefficients[static_cast<size_t>(c)].leftCols(live) * x;
    const polynomial_statistics::Poly p =
        polynomial_statistics::Trimmed(poly_.data(), ExactRecorder::kTerms, chunk.length);
    const double start =
        (cycle_start + t_.boundaries[static_cast<size_t>(chunk.segment)]) + chunk.in_segment;
    polynomial_statistics::UpdateExtrema(p, chunk.length, start, out, want_min);
  }
}

}  // namespace gearnvh
