// The report's figures as plot descriptions (gui-less-render draws them): Campbell diagram,
// waterfall, TE spectrum with mesh harmonics and sidebands, dynamic TE trace, mesh stiffness /
// load sharing / LSTE over one mesh cycle, phase portrait with Poincaré section, atlas heat maps.
// Axis labels carry units; speeds are shown in rpm.
#pragma once

#include <string>

#include "display_units.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/render/plots.h"
#include "operating_point.h"
#include "speed_sweep.h"

namespace gearnvh::app {

render::LinePlot CampbellFigure(const SpeedSweepResult& sweep);
render::HeatMap WaterfallFigure(const SpeedSweepResult& sweep);
render::LinePlot SpectrumFigure(const OperatingPointAnalysis& op);
// The last `cycles` recorded mesh cycles.
render::LinePlot TeTraceFigure(const OperatingPointAnalysis& op, long cycles);
// TE against its rate over the last `cycles` cycles, with the Poincaré section at every base
// period (samples at whole multiples of `base_period_cycles` mesh cycles).
render::LinePlot PhaseFigure(const OperatingPointAnalysis& op, long cycles,
                             long base_period_cycles);
render::LinePlot MeshStiffnessFigure(const ComponentModel& model);
render::LinePlot LoadSharingFigure(const ComponentModel& model);
render::LinePlot LsteFigure(const ComponentModel& model);
// lyapunov: lambda per forcing cycle (diverging map); otherwise log10 of the rattle index.
// Axes in the units of `spec` (the gearbox file).
render::HeatMap AtlasFigure(const AtlasResult& atlas, bool lyapunov, const GearboxSpec& spec);

}  // namespace gearnvh::app
