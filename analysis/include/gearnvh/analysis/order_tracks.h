// Order tracks of the speed sweep (what an NVH engineer reads off a run-up): the TE amplitude at
// one pinion order across the speeds, read off the sweep's waterfall (speed_sweep.h), whose bins
// lie order_step pinion orders apart. An order on a bin (the mesh orders: k z1 / order_step =
// k * window cycles) takes that bin; an order between two bins (a shaft-order sideband) takes the
// larger of the two, the peak of the window's main lobe within its scalloping loss.
// Used by the UFF export (uff_export.h) and the report's order-track figure.
#pragma once

#include <string>
#include <vector>

#include "gearnvh/analysis/speed_sweep.h"
#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

struct OrderTrack {
  std::string label;                           // "1x mesh", "2x mesh - 1x wheel"
  double pinion_order = 0.0;                   // multiples of the pinion speed
  std::vector<double> speed_rpm, amplitude_m;  // per sweep speed; NaN where the run failed
};

// The track of one pinion order (> 0).
OrderTrack TrackOrder(const SpeedSweepResult& sweep, double pinion_order, const std::string& label);

// Mesh orders 1..`mesh_orders` (k z1 pinion orders).
std::vector<OrderTrack> MeshOrderTracks(const GearboxSpec& spec, const SpeedSweepResult& sweep,
                                        int mesh_orders = 3);

// Of the sidebands of mesh orders 1..3 at +-1 and +-2 orders of either shaft, the `count` with the
// largest amplitude anywhere in the sweep, strongest first; only those within 60 dB of the
// strongest mesh order (weaker ones are the rounding noise of a gearbox without the shaft-order
// errors that make sidebands, or leakage). An order with two names is listed once, under the
// first (pinion before wheel).
std::vector<OrderTrack> LargestSidebandTracks(const GearboxSpec& spec,
                                              const SpeedSweepResult& sweep, int count);

}  // namespace gearnvh
