// The report's figures drawn from known data: the order tracks read the waterfall's bins, and
// every new figure (order tracks, sideband stems, Campbell with mode types, tier comparison) draws
// ink inside its plot area with its title, legend and labels apart and inside the image, at the
// default size and at 600x400 (support/figure_checks.h).
#include "report_figures.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "config/gearbox_loader.h"
#include "gearnvh/analysis/order_tracks.h"
#include "gearnvh/render/plots.h"
#include "report_sweep_figures.h"
#include "support/figure_checks.h"
#include "support/run_command.h"

namespace gearnvh::app {
namespace {

const std::pair<int, int> kSizes[] = {{1200, 800}, {600, 400}};

GearboxSpec Pair20x40() {
  GearboxSpec spec;
  spec.pinion.teeth = 20;
  spec.wheel.teeth = 40;
  return spec;
}

// A sweep 600..4200 rpm whose waterfall (0.5 pinion orders per bin, bins 0..140) holds the mesh
// orders (bins 40, 80, 120) as resonance peaks, two sidebands (1x mesh + 1x pinion at pinion order
// 21 = bin 42; 2x mesh - 1x wheel at order 39.5 = bin 79) and a noise floor 200 dB down.
SpeedSweepResult KnownSweep() {
  SpeedSweepResult sweep;
  sweep.order_step = 0.5;
  sweep.order_bins = 141;
  for (int i = 0; i <= 36; ++i) {
    SpeedPoint p;
    p.speed_rpm = 600.0 + 100.0 * i;
    p.speed_rad_s = p.speed_rpm * M_PI / 30.0;
    p.ok = i != 7;  // one failed speed
    p.amplitude_m.assign(141, 1e-16);
    const double peak = 1.0 / (1.0 + std::pow((p.speed_rpm - 2400.0) / 300.0, 2));
    p.amplitude_m[40] = 1e-6 * (0.5 + peak);
    p.amplitude_m[80] = 0.3e-6 * (0.5 + peak);
    p.amplitude_m[120] = 0.1e-6;
    p.amplitude_m[42] = 0.05e-6 * (1.0 + peak);
    p.amplitude_m[79] = 0.02e-6;
    sweep.points.push_back(p);
  }
  return sweep;
}

TEST_CASE("order tracks read the mesh orders on their bins and pick the largest real sidebands",
          "[app][figures]") {
  const SpeedSweepResult sweep = KnownSweep();
  const GearboxSpec spec = Pair20x40();
  const std::vector<OrderTrack> mesh = MeshOrderTracks(PairWaterfall(sweep), spec.pinion.teeth, 3);
  REQUIRE(mesh.size() == 3);
  CHECK(mesh[1].label == "2x mesh");
  CHECK(mesh[1].order == 40.0);
  for (size_t i = 0; i < sweep.points.size(); ++i) {
    INFO("speed " << i);
    if (!sweep.points[i].ok) {
      CHECK(std::isnan(mesh[0].amplitude_m[i]));  // a failed speed is a gap
      continue;
    }
    // Exact copies of the planted bins (no arithmetic between).
    CHECK(mesh[0].amplitude_m[i] == sweep.points[i].amplitude_m[40]);
    CHECK(mesh[2].amplitude_m[i] == sweep.points[i].amplitude_m[120]);
  }
  // 1x mesh + 1x pinion (order 21, on bin 42), then 2x mesh - 1x wheel (order 39.5, bin 79);
  // the other 22 candidates hold the -200 dB floor, below the 60 dB limit.
  const std::vector<OrderTrack> sidebands = LargestSidebandTracks(spec, sweep, 4);
  REQUIRE(sidebands.size() == 2);
  CHECK(sidebands[0].label == "1x mesh + 1x pinion");
  CHECK(sidebands[0].order == 21.0);
  CHECK(sidebands[1].label == "2x mesh - 1x wheel");
  CHECK(sidebands[1].amplitude_m[0] == 0.02e-6);
  // An order between bins takes the larger neighbour: 20.25 lies between bins 40 and 41.
  CHECK(TrackOrder(PairWaterfall(sweep), 20.25, "x").amplitude_m[0] ==
        sweep.points[0].amplitude_m[40]);
}

TEST_CASE("order-track figure: dB re 1 µm against rpm, drawn apart at both sizes",
          "[app][figures][render]") {
  const SpeedSweepResult sweep = KnownSweep();
  const GearboxSpec spec = Pair20x40();
  const render::LinePlot plot =
      OrderTrackFigure(MeshOrderTracks(PairWaterfall(sweep), spec.pinion.teeth, 3),
                       LargestSidebandTracks(spec, sweep, 2), AxisScale::kLinear);
  CHECK(plot.y_label == "TE amplitude (dB re 1 µm)");
  REQUIRE(plot.series.size() == 5);
  // 1 µm x 1.5 at resonance: 20 log10(1.5) = 3.52 dB.
  double top = -1e9;
  for (double v : plot.series[0].y) top = std::isfinite(v) ? std::max(top, v) : top;
  CHECK(top == Approx(20.0 * std::log10(1.5)).margin(1e-9));
  const testing::TempDir dir;
  for (const auto& [w, h] : kSizes) {
    const std::string png = (dir.path() / ("order_tracks" + std::to_string(w) + ".png")).string();
    testing::CheckDrawnFigure(render::RenderLinePlot(plot, {w, h, 100.0}, png), png, w, h);
  }
}

TEST_CASE("sideband stems: harmonics and sidebands in dB, the strongest labelled, apart",
          "[app][figures][render]") {
  OperatingPointAnalysis op;
  const double fm = 600.0, f1 = 30.0, f2 = 15.0;
  for (int k = 1; k <= 3; ++k) {
    const double a = 1e-6 / k;
    op.sidebands.push_back({std::to_string(k) + " fm", k * fm, a, 20.0 * std::log10(a / 1e-6)});
    for (int m = 1; m <= 4; ++m) {
      for (int sign : {1, -1}) {
        const double b = 0.1 * a / (m * m);
        const double f = k * fm + sign * m * (m % 2 == 0 ? f2 : f1);
        op.sidebands.push_back({std::to_string(k) + " fm " + (sign > 0 ? "+ " : "- ") +
                                    std::to_string(m) + (m % 2 == 0 ? " f2" : " f1"),
                                f, b, 20.0 * std::log10(b / 1e-6)});
      }
    }
  }
  const render::LinePlot plot = SidebandStemFigure(op);
  REQUIRE(plot.series.size() == 4);  // stems and heads of harmonics and sidebands
  CHECK(plot.series[2].label == "mesh harmonics");
  CHECK(plot.series[2].x.size() == 3);
  CHECK(plot.series[3].x.size() == 24);
  CHECK(plot.labels.front().text == "1 fm");  // harmonics are labelled first
  const testing::TempDir dir;
  for (const auto& [w, h] : kSizes) {
    const std::string png = (dir.path() / ("sidebands" + std::to_string(w) + ".png")).string();
    const render::RenderStatus s = render::RenderLinePlot(plot, {w, h, 100.0}, png);
    testing::CheckDrawnFigure(s, png, w, h);
    CHECK(s.layout.labels.size() >= 3);
  }
}

TEST_CASE("Campbell figure: every mode by type, critical speeds labelled, apart at both sizes",
          "[app][figures][render]") {
  SpeedSweepResult sweep;
  for (int i = 0; i <= 40; ++i) {
    SpeedPoint p;
    p.speed_rpm = 200.0 + 100.0 * i;
    sweep.points.push_back(p);
  }
  CampbellData& c = sweep.campbell;
  c.orders = GearOrderLines(20, 40);
  const ModeType types[] = {ModeType::kTorsional, ModeType::kLateral, ModeType::kLateral,
                            ModeType::kAxial, ModeType::kCoupled};
  for (int k = 0; k < 5; ++k) {
    std::vector<double> f;
    for (const SpeedPoint& p : sweep.points) f.push_back(400.0 * (k + 1) + 0.02 * k * p.speed_rpm);
    c.frequency_hz.push_back(f);
    ModeInfo info;
    info.type = types[k];
    info.whirl = k == 1 ? Whirl::kForward : k == 2 ? Whirl::kBackward : Whirl::kNone;
    c.modes.push_back(info);
  }
  // Mode 1 (400 Hz) crosses 1x mesh (20 rpm / 60 Hz) at 1200 rpm.
  c.critical_speeds.push_back({"1x mesh", 0, 1200.0 * M_PI / 30.0, 1200.0, 400.0});
  const render::LinePlot plot = CampbellFigure(sweep);
  CHECK(plot.log_y);
  int legend_types = 0;
  for (const render::Series& s : plot.series) {
    if (s.label.find(" modes") != std::string::npos) ++legend_types;
  }
  CHECK(legend_types == 4);  // torsional, lateral, axial, coupled: one legend entry each
  bool tagged = false;
  for (const render::TextLabel& l : plot.labels) tagged = tagged || l.text == "2 lateral fw";
  CHECK(tagged);
  CHECK(plot.labels.front().text == "1200 rpm, mode 1");
  const testing::TempDir dir;
  for (const auto& [w, h] : kSizes) {
    const std::string png = (dir.path() / ("campbell" + std::to_string(w) + ".png")).string();
    const render::RenderStatus s = render::RenderLinePlot(plot, {w, h, 100.0}, png);
    testing::CheckDrawnFigure(s, png, w, h);
    CHECK(s.layout.labels.size() >= 2);
  }
}

TEST_CASE("tier comparison: log cost and error, every tier named, apart at both sizes",
          "[app][figures][render]") {
  const double kNan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<TierPoint> tiers = {{"tier 1", 6, 0.4, std::nullopt},
                                        {"tier 2", 14, 0.05, 0.2},
                                        {"N20 MTA", 42, 1e-4, -1e-3},
                                        {"N20 simple", 30, 2e-3, -0.04},
                                        {"N40 full", 82, 0.0, kNan}};
  const render::LinePlot plot =
      TierComparisonFigure("cost (µs per mesh cycle)", tiers, "TE RMS difference");
  CHECK(plot.log_x);
  CHECK(plot.log_y);
  REQUIRE(plot.series.size() == 3);
  CHECK(plot.series[0].y.back() == 1e-6);  // an exact frequency is drawn at the 1e-6 % floor
  CHECK(plot.series[1].x == std::vector<double>{14});  // not applicable and NaN left out
  // Negative errors at their magnitude in %, as diamonds under their own legend entry.
  CHECK(plot.series[2].y == std::vector<double>{100.0 * 1e-3, 100.0 * 0.04});
  CHECK(plot.series[2].marker == render::Series::Marker::kDiamond);
  CHECK(plot.series[2].label == "TE RMS difference < 0");
  const testing::TempDir dir;
  for (const auto& [w, h] : kSizes) {
    const std::string png = (dir.path() / ("tiers" + std::to_string(w) + ".png")).string();
    const render::RenderStatus s = render::RenderLinePlot(plot, {w, h, 100.0}, png);
    testing::CheckDrawnFigure(s, png, w, h, 100);
    CHECK(s.layout.labels.size() == 5);
    // Every drawn point is a data mark the labels avoided: 5 + 1 + 2.
    CHECK(s.layout.data_marks.size() == 8);
  }
}

TEST_CASE("atlas figure: a log torque axis has geometric cell edges and draws at both sizes",
          "[app][figures][render]") {
  const GearboxSpec spec =
      config::LoadGearboxFile(std::string(GEARNVH_EXAMPLES_DIR) + "/idle_rattle.yaml");
  REQUIRE(spec.analysis.atlas_y->range.scale == AxisScale::kLog);
  AtlasResult atlas;
  atlas.x = *spec.analysis.atlas_x;
  atlas.y = *spec.analysis.atlas_y;
  atlas.x.range.points = 5;
  atlas.y.range.points = 6;
  for (int iy = 0; iy < 6; ++iy) {
    for (int ix = 0; ix < 5; ++ix) {
      AtlasCell c;
      c.ix = ix;
      c.iy = iy;
      c.ok = !(ix == 2 && iy == 3);  // one failed cell: grey
      c.lyapunov_per_forcing_cycle = iy < 2 ? 0.5 + 0.1 * ix : -3.0;
      c.rattle_index = std::pow(10.0, -6.0 + iy);
      atlas.cells.push_back(c);
    }
  }
  const render::HeatMap map = AtlasFigure(atlas, false, spec);
  CHECK(map.log_y);
  CHECK_FALSE(map.log_x);
  // 0.05..5 N m in 6 points: ratio q = 100^(1/5); the edges lie half a step (sqrt q) beyond the
  // ends (1e-12 relative: a few roundings).
  const double q = std::pow(100.0, 0.2);
  CHECK(map.y_min == Approx(0.05 / std::sqrt(q)).epsilon(1e-12));
  CHECK(map.y_max == Approx(5.0 * std::sqrt(q)).epsilon(1e-12));
  CHECK(map.values[1 * 5 + 0] == Approx(-5.0).epsilon(1e-12));  // log10 of the rattle index
  CHECK(std::isnan(map.values[3 * 5 + 2]));
  const testing::TempDir dir;
  for (const auto& [w, h] : kSizes) {
    const std::string png = (dir.path() / ("atlas" + std::to_string(w) + ".png")).string();
    const render::RenderStatus s = render::RenderHeatMap(map, {w, h, 100.0}, png);
    const double area = (s.layout.plot_area.x1 - s.layout.plot_area.x0) *
                        (s.layout.plot_area.y1 - s.layout.plot_area.y0);
    testing::CheckDrawnFigure(s, png, w, h, static_cast<long>(0.5 * area));
  }
}

}  // namespace
}  // namespace gearnvh::app

namespace gearnvh::app {
namespace {

TEST_CASE("the coupling figure shows the last window of each twist, its peaks kept, and its mean",
          "[report][train]") {
  // Two couplings sampled every 1 ms over 20 s (20,001 samples): a sine of 1 deg at 7 Hz about
  // 2 deg with one spike to 5 deg at 19.3 s, and a constant 0.5 deg. The last 2 s hold 2,001
  // samples, more than the 800 points allowed, so each bucket gives its minimum and maximum.
  constexpr double kDeg = std::numbers::pi / 180.0, kDt = 1e-3;
  TrainOperatingPoint op;
  op.histories.start = 1.0;
  op.histories.dt = kDt;
  op.histories.coupling_twist.resize(2);
  for (int k = 0; k <= 20000; ++k) {
    const double t = 1.0 + k * kDt;
    op.histories.coupling_twist[0].push_back((2.0 + std::sin(2.0 * std::numbers::pi * 7.0 * t)) *
                                             kDeg);
    op.histories.coupling_twist[1].push_back(0.5 * kDeg);
  }
  op.histories.coupling_twist[0][18300] = 5.0 * kDeg;  // t = 19.3 s
  op.couplings = {{"damper", {}, {}}, {"halfshaft", {}, {}}};
  op.couplings[0].twist.mean = 2.0 * kDeg;
  op.couplings[1].twist.mean = 0.5 * kDeg;
  const render::LinePlot plot = CouplingTwistFigure(op, 2.0, 800);
  REQUIRE(plot.series.size() == 4);  // each coupling and its mean
  const render::Series& damper = plot.series[0];
  CHECK(damper.label == "damper");
  CHECK(damper.x.size() <= 800);
  // The last 2 s of 1..21 s, to a bucket of 6 samples.
  CHECK(damper.x.front() == Approx(19.0).margin(6 * kDt));
  CHECK(damper.x.back() == Approx(21.0).margin(6 * kDt));
  CHECK(std::is_sorted(damper.x.begin(), damper.x.end()));
  // The spike kept (rad -> deg and back: rounding only) and the trough sampled within half a
  // sample of its time: 1 - cos(2 pi 7 Hz 0.5 ms) = 2.4e-4 deg, so 1e-3.
  CHECK(*std::max_element(damper.y.begin(), damper.y.end()) == Approx(5.0).epsilon(1e-12));
  CHECK(*std::min_element(damper.y.begin(), damper.y.end()) == Approx(1.0).margin(1e-3));
  CHECK(plot.series[1].y == std::vector<double>{2.0, 2.0});
  CHECK(plot.series[1].style == render::Series::Style::kDashed);
  CHECK(plot.series[1].label.empty());
  CHECK(plot.series[3].y == std::vector<double>{0.5, 0.5});
  const testing::TempDir dir;
  for (const auto& [w, h] : kSizes) {
    const std::string png = (dir.path() / ("couplings" + std::to_string(w) + ".png")).string();
    testing::CheckDrawnFigure(render::RenderLinePlot(plot, {w, h, 100.0}, png), png, w, h);
  }
}

}  // namespace
}  // namespace gearnvh::app
