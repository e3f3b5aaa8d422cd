#include "gearnvh/solver/segment_fusion.h"

#include <algorithm>

#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

SegmentFusion::SegmentFusion(const SegmentTables& tables, const SolverOptions& options)
    : t_(tables), ignore_walls_(options.ignore_walls), start_(tables.m), end_(tables.m) {
  if (options.method != SolverMethod::kFused || tables.segments() < 2 ||
      options.fusion_levels <= 0) {
    return;
  }
  int levels = 0;
  while ((2 << levels) <= tables.segments() && levels < options.fusion_levels) ++levels;
  for (int st = 0; st < 3; ++st)
    runs_[static_cast<size_t>(st)] =
        SegmentRunTable(tables, static_cast<ContactState>(st), levels, options.cancel);
  skip_.assign(3 * static_cast<size_t>(tables.segments()), 0);
  backoff_.assign(skip_.size(), 0);
  built_ = true;
  certify_scratch_.resize(tables.m);
  inputs_.resize(tables.m);
  phase_ = tables.MakeCyclePhase();
}

size_t SegmentFusion::bytes() const {
  size_t total = 0;
  for (const SegmentRunTable& table : runs_) total += table.bytes();
  return total;
}

int SegmentFusion::TryRun(long cycle, int segment, LocatorState& state, EventLocator& locator) {
  const size_t key =
      static_cast<size_t>(state.contact) * static_cast<size_t>(t_.segments()) + segment;
  if (skip_[key] > 0) {
    --skip_[key];
    return 0;
  }
  if (state.z_stale) locator.Materialise(state);
  const int length = Advance(cycle, segment, state);
  if (length > 0) {
    backoff_[key] = 0;
  } else {
    backoff_[key] = std::min(2 * backoff_[key] + 1, kMaxBackoff);
    skip_[key] = backoff_[key];
  }
  return length;
}

int SegmentFusion::Advance(long cycle, int segment, LocatorState& state) {
  const SegmentRun* run =
      runs_[static_cast<size_t>(state.contact)].Certify(segment, state.z, certify_scratch_);
  if (run == nullptr) return 0;
  start_ = state.z;
  start_.tail(t_.inputs).setZero();
  end_.noalias() = run->product * start_;
  for (int i = 0; i < run->length; ++i) {
    t_.SetInputs(cycle, segment + i, inputs_, phase_);
    for (int q = 0; q < t_.inputs; ++q) {
      const double u = inputs_[t_.input_slot(q)];
      if (u != 0.0) end_ += u * run->inputs.col(i * t_.inputs + q);
    }
  }
  // The end state must be inside every wall of the state (no event at the run's end).
  const SegmentSystem& last =
      t_.systems[segment + run->length - 1][static_cast<int>(state.contact)];
  GapWall walls[kMaxWalls];
  const int count = ActiveWalls(last, state.contact, walls);
  for (int i = 0; i < count; ++i) {
    if (walls[i].sign * walls[i].row->dot(end_) > 0.0) return 0;
  }
  state.z.swap(end_);
  ++state.matvecs;
  return run->length;
}

}  // namespace gearnvh
