// V3: closed-form event location in decoupled coordinates (spectral_locator.h, spectral_gap.h).
#include "gearnvh/solver/spectral_locator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

namespace {

// out (P entries) = a w for a padded matrix a (P rows, m columns, 64-byte aligned columns; M: m
// when known at compile time): one pass over the columns with one sum per vector of rows. Eigen's
// product makes a pass per block of rows (48 rows: 32 then 16) and was ~15 % slower at 48 x 46
// (microbenchmark, AVX-512).
template <int P, int M = Eigen::Dynamic>
void PaddedProductSized(const double* a, int m, const double* w, double* out) {
  using Column = Eigen::Map<const Eigen::Matrix<double, P, 1>, Eigen::Aligned64>;
  const int columns = M == Eigen::Dynamic ? m : M;
  Eigen::Matrix<double, P, 1> sum = w[0] * Column(a);
  for (int k = 1; k < columns; ++k) sum.noalias() += w[k] * Column(a + static_cast<size_t>(k) * P);
  Eigen::Map<Eigen::Matrix<double, P, 1>>{out} = sum;
}

// out (padded entries) = a w for a padded matrix a (padded rows, m >= 1 columns). Sizes up to 56
// rows keep their sums in registers even with 16 AVX2 registers; larger ones take Eigen's product.
void PaddedProduct(const double* a, int padded, int m, const double* w, double* out) {
  switch (padded) {
    case 8:
      return PaddedProductSized<8>(a, m, w, out);
    case 16:
      return PaddedProductSized<16>(a, m, w, out);
    case 24:
      return PaddedProductSized<24>(a, m, w, out);
    case 32:
      return PaddedProductSized<32>(a, m, w, out);
    case 40:
      return PaddedProductSized<40>(a, m, w, out);
    case 48:
      return PaddedProductSized<48>(a, m, w, out);
    case 56:
      return PaddedProductSized<56>(a, m, w, out);
    default:
      Eigen::Map<Eigen::VectorXd>(out, padded).noalias() =
          Eigen::Map<const Eigen::MatrixXd, Eigen::Aligned64>(a, padded, m) *
          Eigen::Map<const Eigen::VectorXd>(w, m);
  }
}

static_assert(kMaxWalls < 32, "the screen's verdicts are bit sets in an unsigned");

constexpr int kLineDoubles = SpectralLocator::kLineDoubles;
// The padded length at compile time: one line when m (M) is known and fits it.
template <int M>
constexpr int kPadded = M == Eigen::Dynamic ? Eigen::Dynamic : kLineDoubles;

// out = C w for a carry matrix C stored by padded columns (padded rows, m columns; the pad rows
// are 0) and w of length >= m (its first m entries are used). At tier 1 two chains of M/2 vector
// FMAs (one per column) instead of one of M: the carry is the carried path's critical path (the
// next segment's entry waits for it).
template <int M, class In, class Out>
[[gnu::always_inline]] inline void CarryProductSized(const double* carry, int padded, int m,
                                                     const In& w, Out&& out) {
  static_assert(M == Eigen::Dynamic || M <= kLineDoubles);
  constexpr int P = kPadded<M>;
  if constexpr (M == Eigen::Dynamic) {
    PaddedProduct(carry, padded, m, w.data(), out.data());
  } else {
    constexpr int H = M / 2;
    using Low = Eigen::Map<const Eigen::Matrix<double, P, H>, Eigen::Aligned64>;
    using High = Eigen::Map<const Eigen::Matrix<double, P, M - H>, Eigen::Aligned64>;
    const Eigen::Matrix<double, P, 1> low = Low(carry) * w.template head<H>();
    const Eigen::Matrix<double, P, 1> high = High(carry + H * P) * w.template segment<M - H>(H);
    out = low + high;
  }
}

// out[0, count) = v[0, count) without a call to memcpy (which would keep v in memory, not in
// registers, on the carried path).
template <int M, class Vector>
[[gnu::always_inline]] inline void CopyHead(const Vector& v, int count, double* out) {
  if constexpr (M == Eigen::Dynamic) {
    Eigen::Map<Eigen::VectorXd>(out, count) = v.head(count);
  } else {
    for (int k = 0; k < M; ++k)
      if (k < count) out[k] = v[k];
  }
}

}  // namespace

void SpectralLocator::MultiplyDense(const double* a, const double* x,
                                    Eigen::Ref<Eigen::VectorXd> y) {
  // At tier 1 (m = 5 to 8: without or with one engine order, without or with errors; the sizes
  // of EnterCarriedSized) the column count is fixed too.
  if (t_.m == 5)
    PaddedProductSized<kLineDoubles, 5>(a, 5, x, product_.data());
  else if (t_.m == 6)
    PaddedProductSized<kLineDoubles, 6>(a, 6, x, product_.data());
  else if (t_.m == 7)
    PaddedProductSized<kLineDoubles, 7>(a, 7, x, product_.data());
  else if (t_.m == 8)
    PaddedProductSized<kLineDoubles, 8>(a, 8, x, product_.data());
  else
    PaddedProduct(a, padded_, t_.m, x, product_.data());
  y = product_.head(y.size());
}

void SpectralLocator::CarryProduct(const double* carry, const double* w) {
  const Eigen::Map<const Eigen::VectorXd> in(w, t_.m);
  Eigen::Map<Eigen::VectorXd, kBufferAlignment> out(carried_.data(), padded_);
  switch (t_.m) {
    case 5:
      return CarryProductSized<5>(carry, padded_, t_.m, in, out);
    case 6:
      return CarryProductSized<6>(carry, padded_, t_.m, in, out);
    case 7:
      return CarryProductSized<7>(carry, padded_, t_.m, in, out);
    case 8:
      return CarryProductSized<8>(carry, padded_, t_.m, in, out);
    default:
      return CarryProductSized<Eigen::Dynamic>(carry, padded_, t_.m, in, out);
  }
}

template <int M>
SpectralLocator::CarriedVector<M> SpectralLocator::CarriedView(Eigen::VectorXd& buffer) const {
  if constexpr (M == Eigen::Dynamic)
    return {buffer.data(), padded_};
  else
    return Eigen::Map<const CarriedVector<M>, kBufferAlignment>(buffer.data());
}

template <int M>
[[gnu::always_inline]] inline void SpectralLocator::WriteBack(const CarriedVector<M>& v,
                                                              Eigen::VectorXd& buffer) {
  // A map already is the buffer.
  if constexpr (M != Eigen::Dynamic)
    Eigen::Map<CarriedVector<M>, kBufferAlignment>(buffer.data()) = v;
}

void SpectralLocator::Materialise(LocatorState& state) {
  if (!state.z_stale) return;
  const int live = t_.m - t_.inputs;  // the input slots of z are the stepper's
  const System& sp = systems_[carry_segment_][static_cast<int>(carry_state_)];
  MultiplyDense(DenseMatrix(sp, Dense::kS), carried_.data(), state.z.head(live));
  ++state.matvecs;
  state.z_stale = false;
}

// Inlined into EnterCarriedSized (the carried path's loop).
template <int M, class Vector>
[[gnu::always_inline]] inline unsigned SpectralLocator::ClearWallsOf(const System& sp, int segment,
                                                                     const Vector& w) const {
  constexpr int P = kPadded<M>;
  using Column = Eigen::Map<const Eigen::Matrix<double, P, 1>, Eigen::Aligned64>;
  const int padded = padded_;
  unsigned clear_walls = 0;
  const double* screen = sp.block + static_cast<size_t>(t_.inputs) * padded;
  for (int i = 0; i < sp.walls; ++i, screen += 2 * padded) {
    // ClosedFormGap::ClearOfWall's linear test on the block's rows (the pads are 0) ...
    const double start = w.dot(Column(screen, padded));
    if (start + w.cwiseAbs().dot(Column(screen + padded, padded)) + gap_tolerance_ <= 0.0) {
      clear_walls |= 1u << i;
      continue;
    }
    // ... and where it fails its curved test on the copies of the closed form's rows.
    const double* rows = sp.curved + static_cast<size_t>(ClosedFormGap::kCurvedRows * i) * padded;
    auto row = [&](int k) { return Column(rows + static_cast<size_t>(k) * padded, padded); };
    if (start < -gap_tolerance_ &&
        ClosedFormGap::CurvedScreenClear(start, w.dot(row(0)), w.dot(row(1)), w.dot(row(2)),
                                         w.cwiseAbs().dot(row(3)), w.cwiseAbs().dot(row(4)),
                                         t_.SegmentLength(segment), gap_tolerance_))
      clear_walls |= 1u << i;
  }
  return clear_walls;
}

unsigned SpectralLocator::ClearWalls(const System& sp, int segment) const {
  switch (t_.m) {
    case 5:
      return ClearWallsOf<5>(sp, segment,
                             Eigen::Map<const CarriedVector<5>, kBufferAlignment>(entry_.data()));
    case 6:
      return ClearWallsOf<6>(sp, segment,
                             Eigen::Map<const CarriedVector<6>, kBufferAlignment>(entry_.data()));
    case 7:
      return ClearWallsOf<7>(sp, segment,
                             Eigen::Map<const CarriedVector<7>, kBufferAlignment>(entry_.data()));
    case 8:
      return ClearWallsOf<8>(sp, segment,
                             Eigen::Map<const CarriedVector<8>, kBufferAlignment>(entry_.data()));
    default:
      return ClearWallsOf<Eigen::Dynamic>(
          sp, segment, Eigen::Map<const Eigen::VectorXd, kBufferAlignment>(entry_.data(), padded_));
  }
}

// Inlined into CarryThroughSized's loop: no call and no 64-byte aligned frame per segment.
template <int M>
[[gnu::always_inline]] inline SpectralLocator::Entry SpectralLocator::EnterCarriedSized(
    int segment, LocatorState& state, CarriedVector<M>& carried) {
  constexpr int P = kPadded<M>;
  using Column = Eigen::Map<const Eigen::Matrix<double, P, 1>, Eigen::Aligned64>;
  const int m = t_.m, padded = padded_;
  // Entered carried: w = C_{j-1} w_{j-1} + sum_q u_q S_j^-1 e_q (the stepper has set the slots).
  // The previous segment's carry decomposed this (segment, state) and found it usable.
  const System& sp = systems_[segment][static_cast<int>(state.contact)];
  const double* block = sp.block;
  CarriedVector<M> w = EntryVector<M>();
  // One pass for the first input (a copy followed by an update would re-read w just stored);
  // without inputs (no engine order, no errors) the carried state alone.
  if (t_.inputs == 0)
    w = carried;
  else
    w = carried + state.z[t_.input_slot(0)] * Column(block, padded);
  for (int q = 1; q < t_.inputs; ++q) {
    const double u = state.z[t_.input_slot(q)];
    if (u != 0.0) w += u * Column(block + static_cast<size_t>(q) * padded, padded);
  }
  const unsigned clear_walls = ClearWallsOf<M>(sp, segment, w);
  const unsigned all_walls = (1u << sp.walls) - 1;
  const double* carry =
      clear_walls == all_walls && state.allow_carry ? Carry(segment, state.contact) : nullptr;
  if (carry == nullptr) {
    // Not settled: DoStep takes the entry state from w_ and the walls the screen cleared.
    WriteBack<M>(w, entry_);
    CopyHead<M>(w, m, w_.data());
    entered_clear_walls_ = clear_walls;
    return clear_walls == all_walls ? Entry::kClear : Entry::kNearWall;
  }
  CarryProductSized<M>(carry, padded, m, w, carried);
  ++state.matvecs;
  // (After the cycle's last segment carried holds z: the caller writes it, EndCarriedCycle.)
  carry_segment_ = segment + 1;
  carry_state_ = state.contact;
  return Entry::kSettled;
}

template <int M>
[[gnu::always_inline]] inline void SpectralLocator::EndCarriedCycle(const CarriedVector<M>& carried,
                                                                    LocatorState& state) {
  const int live = t_.m - t_.inputs;
  CopyHead<M>(carried, live, state.z.data());
  state.z_stale = false;
}

template <int M>
SpectralLocator::Entry SpectralLocator::EnterCarriedOnce(int segment, LocatorState& state) {
  CarriedVector<M> carried = CarriedView<M>(carried_);
  const Entry entry = EnterCarriedSized<M>(segment, state, carried);
  WriteBack<M>(carried, carried_);
  if (entry == Entry::kSettled && segment + 1 == t_.segments()) EndCarriedCycle<M>(carried, state);
  return entry;
}

SpectralLocator::Entry SpectralLocator::EnterCarried(int segment, LocatorState& state) {
  switch (t_.m) {
    case 5:
      return EnterCarriedOnce<5>(segment, state);
    case 6:
      return EnterCarriedOnce<6>(segment, state);
    case 7:
      return EnterCarriedOnce<7>(segment, state);
    case 8:
      return EnterCarriedOnce<8>(segment, state);
    default:
      return EnterCarriedOnce<Eigen::Dynamic>(segment, state);
  }
}

template <int M>
int SpectralLocator::CarryThroughSized(int segment, long cycle, SegmentTables::CyclePhase& phase,
                                       LocatorState& state) {
  // At tier 1 the carried state stays in registers from segment to segment.
  CarriedVector<M> carried = CarriedView<M>(carried_);
  const int segments = t_.segments();
  t_.PrepareCycle(cycle, phase);
  for (int j = segment; j < segments; ++j) {
    t_.SetPreparedInputs(j, state.z, phase);
    if (EnterCarriedSized<M>(j, state, carried) != Entry::kSettled) {
      // DoStep(j) takes w_ and the screen's verdict instead of entering again.
      entered_segment_ = j;
      WriteBack<M>(carried, carried_);
      return j;
    }
  }
  WriteBack<M>(carried, carried_);
  EndCarriedCycle<M>(carried, state);
  return segments;
}

int SpectralLocator::CarryThrough(int segment, long cycle, SegmentTables::CyclePhase& phase,
                                  LocatorState& state) {
  switch (t_.m) {
    case 5:
      return CarryThroughSized<5>(segment, cycle, phase, state);
    case 6:
      return CarryThroughSized<6>(segment, cycle, phase, state);
    case 7:
      return CarryThroughSized<7>(segment, cycle, phase, state);
    case 8:
      return CarryThroughSized<8>(segment, cycle, phase, state);
    default:
      return CarryThroughSized<Eigen::Dynamic>(segment, cycle, phase, state);
  }
}

bool SpectralLocator::DoStep(int segment, double start, LocatorState& state,
                             EventHandler& handler) {
  const double h = t_.SegmentLength(segment);
  bool carried = state.z_stale;
  const int entered = entered_segment_;
  entered_segment_ = -1;
  if (carried && entered != segment && EnterCarried(segment, state) == Entry::kSettled) return true;
  // Carried: the walls the screen cleared on the entry state are in entered_clear_walls_ (first
  // pass only; CarryThrough may have entered this segment and left w_ and the verdict set).
  bool screened = carried;
  // Entered with z valid: the time-triggered switch of a start outside a wall is still to decide
  // (carried: the closed form's start value decides it, below).
  bool start_checked = carried;
  enum class Start { kStopped, kSwitched, kKept };
  const auto check_start = [&] {
    start_checked = true;
    const ContactState before = state.contact;
    if (!SwitchIfOutsideAtStart(segment, start, state, handler)) return Start::kStopped;
    return state.contact != before ? Start::kSwitched : Start::kKept;
  };
  double done = 0.0;
  bool moved = false;  // z was advanced inside this segment (the full propagator no longer fits)
  Eigen::VectorXd& z = state.z;
  while (true) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state.contact)];
    System& sp = Prepared(segment, state.contact);
    if (!sp.ok) {
      if (!start_checked) {
        const Start verdict = check_start();
        if (verdict == Start::kStopped) return false;
        if (verdict == Start::kSwitched) continue;
      }
      return fallback_.AdvanceFrom(segment, start, done, state, handler);
    }
    const double remaining = h - done;
    if (!carried) {
      MultiplyDense(DenseMatrix(sp, Dense::kSInverse), z.data(), entry_.head(t_.m));  // pads stay 0
      w_ = entry_.head(t_.m);
      ++state.matvecs;
    }
    GapWall walls[kMaxWalls];
    const int count = ActiveWalls(sys, state.contact, walls);
    // A wall the screen clears for the whole segment (most segments: every wall) is not reached
    // in it: two dot products instead of loading the closed form and searching it.
    unsigned clear_walls = 0;
    if (screened) {
      clear_walls = entered_clear_walls_;
      screened = false;
    } else if (!moved) {
      clear_walls = ClearWalls(sp, segment);  // on entry_, w_ padded
    }
    const unsigned all_walls = (1u << count) - 1;
    // A wall the screen clears has sign g(0) <= -gap_tolerance_: the start is not outside it.
    if (!start_checked && clear_walls != all_walls) {
      const Start verdict = check_start();
      if (verdict == Start::kStopped) return false;
      if (verdict == Start::kSwitched) continue;
    }
    start_checked = true;
    const auto searched = [clear_walls](int i) { return (clear_walls >> i & 1u) == 0; };
    double best = -1.0;
    int best_wall = -1;
    if (clear_walls != all_walls) {
      bool near_wall = false;
      for (int i = 0; i < count; ++i) {
        if (!searched(i)) continue;
        ClosedFormGap& gap = sp.gaps[walls[i].gap];
        gap.Load(w_);
        // Carried: the time-triggered check on the closed form; near a wall it is decided on z.
        if (carried && walls[i].sign * gap.StartValue() > 0.5 * gap_tolerance_) near_wall = true;
      }
      if (near_wall) {
        Materialise(state);
        carried = false;
        if (!SwitchIfOutsideAtStart(segment, start, state, handler)) return false;
        continue;
      }
      for (int i = 0; i < count; ++i) {
        if (!searched(i)) continue;
        const double root = sp.gaps[walls[i].gap].FirstRise(walls[i].sign, remaining);
        if (root >= 0.0 && (best < 0.0 || root < best)) best = root, best_wall = i;
      }
    }
    if (best < 0.0) {
      const double* carry = !moved && state.allow_carry ? Carry(segment, state.contact) : nullptr;
      if (carry != nullptr && segment + 1 < t_.segments()) {
        CarryProduct(carry, w_.data());
        carry_segment_ = segment + 1;
        carry_state_ = state.contact;
        state.z_stale = true;
      } else if (carry != nullptr) {
        CarryProduct(carry, w_.data());  // z at the cycle end, through carried_
        z.head(t_.m - t_.inputs) = carried_.head(t_.m - t_.inputs);
        state.z_stale = false;
      } else if (!moved && !state.z_stale) {
        // The dense propagator: exact to rounding, cond-free.
        MultiplyDense(DenseMatrix(sp, Dense::kPropagator), z.data(), z1_);
        if (state.tangent != nullptr) state.tangent->Propagate(sys.full);
        z.swap(z1_);
      } else {
        PropagateDecoupled(sp.decomposition, w_, remaining, wt_, scratch_);
        MultiplyDense(DenseMatrix(sp, Dense::kS), wt_.data(), z);
        state.z_stale = false;
        if (state.tangent != nullptr)
          state.tangent->PropagateDecoupled(sp.decomposition, remaining);
      }
      ++state.matvecs;
      return true;
    }
    carried = false;
    const GapWall& w = walls[best_wall];
    ClosedFormGap& gap = sp.gaps[w.gap];
    double step = best;
    const bool touch = best > 0.0 && gap.RateWithin(best, grazing_rate_tolerance_) &&
                       w.sign * gap.Curvature(best) < 0.0;
    // A grazing touch keeps the state; the search resumes just past it.
    if (touch) step = std::min(remaining, best + 1e-12 * h);
    PropagateDecoupled(sp.decomposition, w_, step, wt_, scratch_);
    MultiplyDense(DenseMatrix(sp, Dense::kS), wt_.data(), z);
    state.z_stale = false;
    if (state.tangent != nullptr) state.tangent->PropagateDecoupled(sp.decomposition, step);
    ++state.matvecs;
    moved = true;
    done += step;
    if (touch) {
      if (!handler.Graze(start + done)) return false;
    } else if (!handler.Switch(segment, sys, w, start + done, /*state_triggered=*/true)) {
      return false;
    }
    if (h - done <= 1e-15 * h) return true;
  }
}

}  // namespace gearnvh
