// V1: dyadic bisection on dense propagators (event_locator.h).
#include <string>

#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/event_locator.h"
#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

DyadicLocator::DyadicLocator(const SegmentTables& tables, const SolverOptions& options)
    : SubstepLocator(tables, options), zb_(tables.m) {
  const double bytes = static_cast<double>(tables.segments()) * 3 * kDyadicLevels *
                       static_cast<double>(tables.m) * tables.m * sizeof(double);
  if (bytes > 256.0 * 1024 * 1024) {
    throw InputError("event method", 0, "v1",
                     "needs " + std::to_string(static_cast<long>(bytes / 1048576)) +
                         " MiB of dyadic tables for this tier (limit 256 MiB); use v2 or v3");
  }
  levels_.resize(tables.segments());
  for (int j = 0; j < tables.segments(); ++j) {
    ThrowIfCancelled(cancel_);
    for (int st = 0; st < 3; ++st) {
      // Every level straight from the balanced Pade (squaring up from the finest level would
      // amplify rounding by 2^34).
      const SegmentSystem& sys = tables.systems[j][st];
      const double d = tables.SegmentLength(j) / tables.substeps[j];
      const double w_ref = ReferenceFrequency(sys.A, tables.n);
      std::vector<Eigen::MatrixXd>& levels = levels_[j][st];
      levels.resize(kDyadicLevels);
      for (int l = 0; l < kDyadicLevels; ++l) {
        levels[l] = BalancedExpm(sys.A, d / static_cast<double>(1LL << (l + 1)), tables.n, w_ref);
      }
    }
  }
  statistics_.table_bytes = static_cast<size_t>(bytes);
}

bool DyadicLocator::Examine(int segment, double start, LocatorState& state, EventHandler& handler) {
  const long long cells = 1LL << kDyadicLevels;
  const double cell = t_.SegmentLength(segment) / t_.substeps[segment] / static_cast<double>(cells);
  long long pos = 0;
  if (!SwitchIfOutsideAtStart(segment, start, state, handler)) return false;
  Eigen::VectorXd& z = state.z;
  while (pos < cells) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state.contact)];
    const auto& levels = levels_[segment][static_cast<int>(state.contact)];
    // Steps of 2^k cells, k = the trailing zeros of pos (L - 1 at pos = 0): aligned, and level
    // index L - 1 - k.
    int k = pos == 0 ? kDyadicLevels - 1 : __builtin_ctzll(static_cast<unsigned long long>(pos));
    while (pos + (1LL << k) > cells) --k;
    bool crossed = false;
    while (true) {
      const Eigen::MatrixXd& step = levels[kDyadicLevels - 1 - k];
      zb_.noalias() = step * z;
      ++state.matvecs;
      GapWall walls[kMaxWalls];
      const int count = ActiveWalls(sys, state.contact, walls);
      bool suspect = false;
      for (int i = 0; i < count; ++i) {
        const GapWall& w = walls[i];
        // Outside at the end, unless only by the gap's rounding floor while moving inward: right
        // after a slow separation the state sits on the wall within rounding, and that noise is
        // not a new contact (V2 and V3 discount it the same way).
        const double outside = w.sign * w.row->dot(zb_);
        if (outside > 0.0 &&
            (w.sign * w.rate->dot(zb_) > 0.0 || outside > WallTolerance(*w.row, zb_))) {
          suspect = true;
        }
        if (k > 0 && w.sign * w.rate->dot(z) > 0.0 && w.sign * w.rate->dot(zb_) < 0.0 &&
            w.sign * w.row->dot(zb_) > -1e-3 * t_.half_backlash) {
          suspect = true;  // turned back near the wall: look inside
        }
      }
      if (!suspect) break;
      if (k == 0) {
        crossed = true;
        break;
      }
      --k;  // bisect: try the first half
    }
    z.swap(zb_);
    if (state.tangent != nullptr) state.tangent->Propagate(levels[kDyadicLevels - 1 - k]);
    pos += 1LL << k;
    if (crossed) {
      const SegmentSystem& now = t_.systems[segment][static_cast<int>(state.contact)];
      const int outside = Outside(now, state.contact, z, false);
      if (outside >= 0) {
        GapWall walls[kMaxWalls];
        ActiveWalls(now, state.contact, walls);
        if (!handler.Switch(segment, now, walls[outside], start + static_cast<double>(pos) * cell,
                            /*state_triggered=*/true)) {
          return false;
        }
      }
    }
  }
  return true;
}

}  // namespace gearnvh
