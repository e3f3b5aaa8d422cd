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

WaterfallView PairWaterfall(const SpeedSweepResult& sweep) {
  WaterfallView w;
  w.order_step = sweep.order_step;
  for (const SpeedPoint& p : sweep.points) {
    w.speed_rpm.push_back(p.speed_rpm);
    w.rows.push_back(p.ok ? &p.amplitude_m : nullptr);
  }
  return w;
}

WaterfallView MeshWaterfall(const TrainSweepResult& sweep, size_t mesh) {
  WaterfallView w;
  w.order_step = sweep.order_step;
  for (const TrainSweepPoint& p : sweep.points) {
    w.speed_rpm.push_back(p.speed_rpm);
    w.rows.push_back(p.ok && mesh < p.waterfall.size() ? &p.waterfall[mesh] : nullptr);
  }
  return w;
}

std::vector<WaterfallView> MeshWaterfalls(const TrainSweepResult& sweep) {
  std::vector<WaterfallView> views;
  for (size_t i = 0; i < sweep.mesh_names.size(); ++i) views.push_back(MeshWaterfall(sweep, i));
  return views;
}

OrderTrack TrackOrder(const WaterfallView& waterfall, double order, const std::string& label) {
  OrderTrack t;
  t.label = label;
  t.order = order;
  const double at = waterfall.order_step > 0.0 ? order / waterfall.order_step : -1.0;
  const long nearest = std::lround(at);
  const bool on_bin = std::abs(at - static_cast<double>(nearest)) < 1e-9;
  const long lo = on_bin ? nearest : static_cast<long>(std::floor(at));
  const long hi = on_bin ? nearest : lo + 1;
  for (size_t s = 0; s < waterfall.rows.size(); ++s) {
    t.speed_rpm.push_back(waterfall.speed_rpm[s]);
    const std::vector<double>* row = waterfall.rows[s];
    if (row == nullptr || lo < 0 || hi >= static_cast<long>(row->size())) {
      t.amplitude_m.push_back(std::numeric_limits<double>::quiet_NaN());
    } else {
      t.amplitude_m.push_back(std::max((*row)[lo], (*row)[hi]));
    }
  }
  return t;
}

std::vector<OrderTrack> MeshOrderTracks(const WaterfallView& waterfall, double mesh_order,
                                        int mesh_orders, const std::string& mesh) {
  std::vector<OrderTrack> out;
  for (int k = 1; k <= mesh_orders; ++k) {
    out.push_back(TrackOrder(waterfall, k * mesh_order,
                             fmt::format("{}x mesh{}", k, mesh.empty() ? "" : " " + mesh)));
  }
  return out;
}

std::vector<OrderTrack> LargestSidebandTracks(const GearboxSpec& spec,
                                              const SpeedSweepResult& sweep, int count) {
  const double z1 = spec.pinion.teeth, wheel = z1 / spec.wheel.teeth;
  const WaterfallView waterfall = PairWaterfall(sweep);
  std::vector<OrderTrack> all;
  for (int k = 1; k <= 3; ++k) {
    for (int m = 1; m <= 2; ++m) {
      for (int sign : {1, -1}) {
        const char* s = sign > 0 ? "+" : "-";
        all.push_back(TrackOrder(waterfall, k * z1 + sign * m,
                                 fmt::format("{}x mesh {} {}x pinion", k, s, m)));
        all.push_back(TrackOrder(waterfall, k * z1 + sign * m * wheel,
                                 fmt::format("{}x mesh {} {}x wheel", k, s, m)));
      }
    }
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const OrderTrack& a, const OrderTrack& b) { return Peak(a) > Peak(b); });
  double mesh_peak = 0.0;
  for (const OrderTrack& t : MeshOrderTracks(waterfall, z1, 3))
    mesh_peak = std::max(mesh_peak, Peak(t));
  std::vector<OrderTrack> out;
  for (OrderTrack& t : all) {
    if (static_cast<int>(out.size()) == count || !(Peak(t) > 0.0) || Peak(t) < 1e-3 * mesh_peak) {
      break;
    }
    // Two names of one order (1x mesh + 1x pinion = 1x mesh + 2x wheel at 1:2): listed once.
    if (std::any_of(out.begin(), out.end(), [&t](const OrderTrack& o) {
          return std::abs(o.order - t.order) < 1e-9 * t.order;
        })) {
      continue;
    }
    out.push_back(std::move(t));
  }
  return out;
}

}  // namespace gearnvh
