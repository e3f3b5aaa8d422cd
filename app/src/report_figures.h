// The report's figures of the operating point and the mesh cycle, as plot descriptions
// (gui-less-render draws them): TE spectrum with mesh harmonics and sidebands, sideband stems,
// dynamic TE trace, mesh stiffness / load sharing / LSTE over one mesh cycle, phase portrait with
// Poincaré section, a train's coupling twists over time. Axis labels carry units. (Figures over
// speed and parameter ranges: report_sweep_figures.h.)
#pragma once

#include <string>

#include "display_units.h"
#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/render/plots.h"

namespace gearnvh::app {

render::LinePlot SpectrumFigure(const OperatingPointAnalysis& op);
// The sideband table as stems: each mesh harmonic and shaft-order sideband (op.sidebands) within
// 80 dB of the strongest, in dB re 1 µm at its frequency (mesh harmonics apart from shaft orders
// and sidebands); the strongest labelled, mesh harmonics first.
render::LinePlot SidebandStemFigure(const OperatingPointAnalysis& op);
// The last `cycles` recorded mesh cycles.
render::LinePlot TeTraceFigure(const OperatingPointAnalysis& op, long cycles);
// TE against its rate over the last `cycles` cycles, with the Poincaré section at every base
// period (samples at whole multiples of `base_period_cycles` mesh cycles).
render::LinePlot PhaseFigure(const OperatingPointAnalysis& op, long cycles,
                             long base_period_cycles);
render::LinePlot MeshStiffnessFigure(const ComponentModel& model);
render::LinePlot LoadSharingFigure(const ComponentModel& model);
render::LinePlot LsteFigure(const ComponentModel& model);
// The mesh-cycle mean line load across the face of each named mesh whose face is modelled
// (FaceLoad::modelled), against the position from the face start.
render::LinePlot FaceLoadFigure(const std::vector<std::pair<std::string, FaceLoad>>& meshes);
// Each coupling's twist (degrees) over the last `window_s` seconds of a train's kept histories
// (TrainHistories::coupling_twist), with its exact mean over the record dashed in the same colour.
// More than `max_points` samples are drawn as each bucket's minimum and maximum (at most
// max_points points): no peak is lost.
render::LinePlot CouplingTwistFigure(const TrainOperatingPoint& op, double window_s,
                                     size_t max_points = 8000);

}  // namespace gearnvh::app
