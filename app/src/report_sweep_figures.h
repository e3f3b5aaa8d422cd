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
render::HeatMap WaterfallFigure(const SpeedSweepResult& sweep);
// Amplitude in dB re 1 µm against speed: `mesh` solid, `sidebands` dashed. Values more than
// 100 dB under the strongest are left out (an exact solution's rounding noise lies far below).
// The speed axis has the sweep's scale.
render::LinePlot OrderTrackFigure(const std::vector<OrderTrack>& mesh,
                                  const std::vector<OrderTrack>& sidebands, AxisScale speed_scale);
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
