// The report's figures over speed and parameter ranges, as plot descriptions (gui-less-render
// draws them): the Campbell diagram, the waterfall, the mesh-order tracks, the chaos atlas maps and
// the modal-tier comparison. Axis labels carry units; speeds are shown in rpm; amplitudes in dB
// re 1 µm.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gearnvh/analysis/order_tracks.h"
#include "gearnvh/analysis/speed_sweep.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/render/plots.h"

namespace gearnvh::app {

// Every tracked mode, coloured by its type (torsional, lateral, axial, coupled) and labelled at
// its end with its number (from 1), type and whirl; order lines dashed and labelled; critical
// speeds marked and labelled in rpm with their mode. Logarithmic frequency axis, so the shaft
// orders are not squeezed under the mesh orders; the speed axis has the sweep's scale.
render::LinePlot CampbellFigure(const SpeedSweepResult& sweep);
// The same from Campbell data (e.g. a gear train's, nvh/train_campbell.h) at its speeds in rpm
// (one per column of campbell.frequency_hz), with its speed axis label ("input speed (rpm)").
render::LinePlot CampbellFigure(const CampbellData& campbell, const std::vector<double>& rpm,
                                AxisScale speed_scale, const std::string& speed_label);
// TE amplitude in dB re 1 µm over order (x) and speed (y), floored 60 dB under the strongest
// line: a pair's (pinion orders and speed) ...
render::HeatMap WaterfallFigure(const SpeedSweepResult& sweep);
// ... or any waterfall of `order_bins` bins on `reference`'s orders and speed ("input" for a
// train's mesh), titled `title`.
render::HeatMap WaterfallFigure(const WaterfallView& waterfall, int order_bins,
                                AxisScale speed_scale, const std::string& reference,
                                const std::string& title);
// How the dashed tracks of an order-track figure are coloured: after the solid ones (a pair's
// sidebands) or each as the solid track of the same index (a train's 2x mesh order of a mesh).
enum class DashedColours { kAfterSolid, kAsSolid };
// Amplitude in dB re 1 µm against speed: `solid` (the mesh orders), `dashed` (a pair's largest
// sidebands, a train's higher mesh orders). Values more than 100 dB under the strongest are left
// out (an exact solution's rounding noise lies far below). The speed axis has the sweep's scale
// and is `reference`'s speed.
render::LinePlot OrderTrackFigure(
    const std::vector<OrderTrack>& solid, const std::vector<OrderTrack>& dashed,
    AxisScale speed_scale,
    const std::string& title = "Order tracks: TE at the mesh orders and the largest sidebands",
    const std::string& reference = "pinion", DashedColours colours = DashedColours::kAfterSolid);
// The figure's data: speed_rpm, then per track its amplitude in m and in dB re 1 µm (empty where
// the run failed); columns named with the track's label and its order of `reference`.
std::string OrderTracksCsv(const std::vector<OrderTrack>& solid,
                           const std::vector<OrderTrack>& dashed,
                           const std::string& reference = "pinion");
// lyapunov: lambda per forcing cycle (diverging map); otherwise log10 of the rattle index.
// Axes in the units of `spec` (the gearbox file), logarithmic where the atlas axis is.
render::HeatMap AtlasFigure(const AtlasResult& atlas, bool lyapunov, const GearboxSpec& spec);

// One modal tier in the comparison: its cost (e.g. µs per mesh cycle or state dimension), the
// largest relative error of its lowest natural frequencies and a second relative error (NaN: none).
struct TierPoint {
  std::string name;
  double cost = 0.0;
  double frequency_error = 0.0;        // >= 0
  std::optional<double> second_error;  // signed; none: not applicable (tier 1's compliance)
};
// Both errors in % against the cost, log-log, each tier labelled with its name. The second error is
// drawn at its magnitude, a negative one as a diamond (its own legend entry) rather than a circle.
// A magnitude below 1e-6 % (exact to rounding) is drawn at 1e-6 %.
render::LinePlot TierComparisonFigure(const std::string& cost_label,
                                      const std::vector<TierPoint>& tiers,
                                      const std::string& second_error_label);

}  // namespace gearnvh::app
