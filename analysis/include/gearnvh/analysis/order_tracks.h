// Order tracks of a speed sweep (what an NVH engineer reads off a run-up): the TE amplitude at one
// order across the speeds, read off a waterfall whose bins lie order_step orders apart. An order
// on a bin (the mesh orders: k z1 / order_step = k * window cycles on a pair) takes that bin; an
// order between two bins (a shaft-order sideband, another mesh of a train) takes the larger of the
// two, the peak of the window's main lobe within its scalloping loss. Orders are multiples of a
// reference shaft's speed: the pinion's on a pair, the input shaft's on a gear train.
// Used by the UFF export (uff_export.h) and the report's order-track figure.
#pragma once

#include <string>
#include <vector>

#include "gearnvh/analysis/speed_sweep.h"
#include "gearnvh/analysis/train_sweep.h"
#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

struct OrderTrack {
  std::string label;                           // "1x mesh", "2x mesh - 1x wheel"
  double order = 0.0;                          // multiples of the reference shaft's speed
  std::vector<double> speed_rpm, amplitude_m;  // per sweep speed; NaN where the run failed
};

// One waterfall of a sweep: per speed an amplitude row (null where the run failed), bin b at
// order b * order_step.
struct WaterfallView {
  double order_step = 0.0;
  std::vector<double> speed_rpm;
  std::vector<const std::vector<double>*> rows;
};
// A pair's waterfall (pinion orders).
WaterfallView PairWaterfall(const SpeedSweepResult& sweep);
// The waterfall of a train's mesh `mesh` (input-shaft orders), and of every mesh in file order.
WaterfallView MeshWaterfall(const TrainSweepResult& sweep, size_t mesh);
std::vector<WaterfallView> MeshWaterfalls(const TrainSweepResult& sweep);

// The track of one order (> 0).
OrderTrack TrackOrder(const WaterfallView& waterfall, double order, const std::string& label);

// Mesh orders 1..`mesh_orders` of a mesh whose fundamental is `mesh_order` orders ("1x mesh", or
// "1x mesh NAME" when `mesh` names it).
std::vector<OrderTrack> MeshOrderTracks(const WaterfallView& waterfall, double mesh_order,
                                        int mesh_orders = 3, const std::string& mesh = "");

// Of a pair's sidebands of mesh orders 1..3 at +-1 and +-2 orders of either shaft, the `count`
// with the largest amplitude anywhere in the sweep, strongest first; only those within 60 dB of
// the strongest mesh order (weaker ones are the rounding noise of a gearbox without the
// shaft-order errors that make sidebands, or leakage). An order with two names is listed once,
// under the first (pinion before wheel).
std::vector<OrderTrack> LargestSidebandTracks(const GearboxSpec& spec,
                                              const SpeedSweepResult& sweep, int count);

}  // namespace gearnvh
