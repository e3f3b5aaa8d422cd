#include "gearnvh/analysis/order_tracks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace gearnvh {

namespace {

double Peak(const OrderTrack& t) {
  double peak = 0.0;
  for (double a : t.amplitude_m) {
    if (std::isfinite(a)) peak = std::max(peak, a);
  }
  return peak;
}

}  // namespace

OrderTrack TrackOrder(const SpeedSweepResult& sweep, double pinion_order,
                      const std::string& label) {
  OrderTrack t;
  t.label = label;
  t.pinion_order = pinion_order;
  const double at = sweep.order_step > 0.0 ? pinion_order / sweep.order_step : -1.0;
  const long nearest = std::lround(at);
  const bool on_bin = std::abs(at - static_cast<double>(nearest)) < 1e-9;
  const long lo = on_bin ? nearest : static_cast<long>(std::floor(at));
  const long hi = on_bin ? nearest : lo + 1;
  for (const SpeedPoint& p : sweep.points) {
    t.speed_rpm.push_back(p.speed_rpm);
    const long bins = static_cast<long>(p.amplitude_m.size());
    if (!p.ok || lo < 0 || hi >= bins) {
      t.amplitude_m.push_back(std::numeric_limits<double>::quiet_NaN());
    } else {
      t.amplitude_m.push_back(std::max(p.amplitude_m[lo], p.amplitude_m[hi]));
    }
  }
  return t;
}

std::vector<OrderTrack> MeshOrderTracks(const GearboxSpec& spec, const SpeedSweepResult& sweep,
                                        int mesh_orders) {
  std::vector<OrderTrack> out;
  for (int k = 1; k <= mesh_orders; ++k) {
    out.push_back(
        TrackOrder(sweep, static_cast<double>(k) * spec.pinion.teeth, fmt::format("{}x mesh", k)));
  }
  return out;
}

std::vector<OrderTrack> LargestSidebandTracks(const GearboxSpec& spec,
                                              const SpeedSweepResult& sweep, int count) {
  const double z1 = spec.pinion.teeth, wheel = z1 / spec.wheel.teeth;
  std::vector<OrderTrack> all;
  for (int k = 1; k <= 3; ++k) {
    for (int m = 1; m <= 2; ++m) {
      for (int sign : {1, -1}) {
        const char* s = sign > 0 ? "+" : "-";
        all.push_back(
            TrackOrder(sweep, k * z1 + sign * m, fmt::format("{}x mesh {} {}x pinion", k, s, m)));
        all.push_back(TrackOrder(sweep, k * z1 + sign * m * wheel,
                                 fmt::format("{}x mesh {} {}x wheel", k, s, m)));
      }
    }
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const OrderTrack& a, const OrderTrack& b) { return Peak(a) > Peak(b); });
  double mesh_peak = 0.0;
  for (const OrderTrack& t : MeshOrderTracks(spec, sweep, 3))
    mesh_peak = std::max(mesh_peak, Peak(t));
  std::vector<OrderTrack> out;
  for (OrderTrack& t : all) {
    if (static_cast<int>(out.size()) == count || !(Peak(t) > 0.0) || Peak(t) < 1e-3 * mesh_peak) {
      break;
    }
    // Two names of one order (1x mesh + 1x pinion = 1x mesh + 2x wheel at 1:2): listed once.
    if (std::any_of(out.begin(), out.end(), [&t](const OrderTrack& o) {
          return std::abs(o.pinion_order - t.pinion_order) < 1e-9 * t.pinion_order;
        })) {
      continue;
    }
    out.push_back(std::move(t));
  }
  return out;
}

}  // namespace gearnvh
