// Segment-run fusion checked against stepping, run by run (train_segment_runs.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include "gearnvh/solver/train_cycle_map.h"
#include "gearnvh/solver/train_segment_runs.h"

namespace gearnvh {

SegmentRunCheck CheckSegmentRuns(const TrainTables& t, const TrainTables& fused_tables,
                                 const Eigen::VectorXd& z0,
                                 const std::vector<ContactState>& states0, long segments,
                                 EventMethod method, const std::atomic<bool>* cancel) {
  TrainStepperOptions stepped;
  stepped.events = method;
  stepped.jumps = false;
  stepped.fusion_levels = 0;
  stepped.cancel = cancel;
  const TrainStepperOptions defaults;
  const long limit = defaults.max_cycle_map_segments;
  TrainSegmentRuns runs(fused_tables, defaults.fusion_levels, defaults.fusion_limit_bytes, limit,
                        cancel);
  const long period = CountCommonPeriodSegments(t, limit);
  TrainStepper stepper(t, stepped, z0, states0);
  TrainGrid grid(t);
  SegmentRunCheck out;
  for (long k = 0; k < segments && !out.stopped;) {
    Eigen::VectorXd z = stepper.state();
    TrainGrid fused_grid = grid;
    const long r = runs.Advance(k % period, stepper.states(),
                                std::numeric_limits<double>::infinity(), true, fused_grid, z);
    const long before = stepper.summary().events + stepper.summary().grazing;
    for (long i = 0; i < std::max(r, 1L) && !out.stopped; ++i, ++k) {
      out.stopped = !stepper.Run(grid.end());
      grid.Next();
    }
    if (r == 0 || out.stopped) continue;
    ++out.runs;
    out.fused += r;
    if (stepper.summary().events + stepper.summary().grazing != before) ++out.runs_with_event;
    double scale = 0.0, difference = 0.0;
    for (int i = 0; i < t.gear_meshes; ++i) {  // the gear meshes' TE, m (a stage's twist is rad)
      const TrainMeshTable& mt = t.meshes[static_cast<size_t>(i)];
      scale = std::max(scale, std::abs(mt.v.dot(stepper.state().head(t.n))));
      difference =
          std::max(difference, std::abs(mt.v.dot(stepper.state().head(t.n) - z.head(t.n))));
    }
    out.worst_te = std::max(out.worst_te, scale > 0.0 ? difference / scale : difference);
  }
  out.refusals = runs.refusals();
  out.summary = stepper.summary();
  out.events = out.summary.events;
  return out;
}

}  // namespace gearnvh
