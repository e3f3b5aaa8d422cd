// Universal File Format (UFF / UNV) dataset 58, ASCII: the function records NVH tools (LMS
// Test.Lab, Simcenter, ME'scope, pyuff, MATLAB readuff) read. gearnvh writes real, double
// precision, evenly spaced functions (record 7 ordinate type 4, spacing 1; data as 4E20.12 per
// line, 13 significant digits). The abscissa start and step are E13.5 fields (6 significant
// digits), as the format defines them.
//
// What a report or `--uff` file holds (docs/reports.md):
//   operating point: TE time history (m over s), mesh force time history (N over s), TE amplitude
//     spectrum (m over Hz); a gear train's for every mesh (response node = the mesh's number);
//   speed sweep: order tracks of the TE amplitude at mesh orders 1..3 (m over rpm; z axis = the
//     pinion order).
#pragma once

#include <string>
#include <vector>

#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/analysis/speed_sweep.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/analysis/train_sweep.h"
#include "gearnvh/analysis/whine.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/spectrum.h"

namespace gearnvh::app {

// Record 8-11: data characteristics of one axis.
struct UffAxis {
  int data_type = 0;  // specific data type: 1 general, 8 displacement, 9 reaction force,
                      // 17 time, 18 frequency, 19 rpm, 20 order
  int length_exponent = 0, force_exponent = 0, temperature_exponent = 0;
  std::string label = "NONE", units = "NONE";
};

struct UffFunction {
  std::string id1, id2, id3, id4, id5;  // ID lines (80 characters at most)
  int function_type = 0;                // 1 time response, 12 spectrum
  int function_id = 0;
  std::string response_name = "NONE";
  int response_node = 1, response_direction = 0;
  UffAxis abscissa, ordinate, denominator, z;
  double z_value = 0.0;
  double x_min = 0.0, dx = 0.0;  // even abscissa
  std::vector<double> values;
};

// One dataset 58 block, from its "    -1" line to the closing "    -1".
std::string UffDataset58(const UffFunction& f);

// What one mesh's operating-point functions are made of.
struct MeshUffSource {
  std::string label;              // the mesh's name in the ID lines; "" for a pair's one mesh
  int node = 1;                   // the response node: the mesh's number, from 1
  double start = 0.0, dt = 0.0;   // the first sample's time and the sample interval, s
  std::vector<double> te, force;  // at the samples, m and N
  AmplitudeSpectrum spectrum;     // the TE spectrum (may be empty)
  std::string spectrum_window;    // what its window holds: "64 mesh cycles"
};

// One mesh's functions: its TE and mesh force histories (when it has 2 samples or more) and its TE
// spectrum (when there is one), ids from `next_id` on (advanced past them).
std::vector<UffFunction> MeshUff(const std::string& gearbox, MeshUffSource mesh, int& next_id);

// The operating point's functions (MeshUff of the pair's one mesh), ids from `first_id`.
std::vector<UffFunction> OperatingPointUff(const GearboxSpec& spec,
                                           const OperatingPointAnalysis& op, int first_id = 1);

// A train's operating point: MeshUff of every mesh in file order (response node i + 1, the mesh
// named in the ID lines), from its time histories (TrainRunOptions::histories); then from tier 2
// on each bearing's force on the housing in x, y, z (response "BRG", node: the bearing's number
// from 1, direction 1..3): its time history and its window spectrum; then each coupling's twist
// (rad) and torque (N m) histories (response "CPL", node: its number from 1, direction 6).
std::vector<UffFunction> TrainOperatingPointUff(const TrainSpec& spec,
                                                const TrainOperatingPoint& op, int first_id = 1);

// Order tracks of the sweep's waterfall at mesh orders 1..3 (order_tracks.h) over the speeds that
// succeeded: a failed speed splits a track into one dataset per run of consecutive speeds that
// succeeded, each saying so in ID line 5; none when no speed succeeded, the sweep has one speed or
// is log-spaced (the dataset's abscissa is even).
std::vector<UffFunction> SweepOrderTracksUff(const GearboxSpec& spec, const SpeedSweepResult& sweep,
                                             int first_id = 1);

// A train's sweep: for every mesh in file order its order tracks at mesh orders 1..3 (input-shaft
// orders and speed; the mesh named in the first ID line), under the same conditions.
std::vector<UffFunction> TrainSweepOrderTracksUff(const TrainSpec& spec,
                                                  const TrainSweepResult& sweep, int first_id = 1);

// Whine's tracks (analysis/whine.h): for every mesh in file order and every line, the TE and mesh
// force amplitude over the input shaft's speed (rpm; z axis = the line's input-shaft order; response
// node = the mesh's number); none when the speeds are log-spaced (the abscissa must be even).
std::vector<UffFunction> WhineOrderTracksUff(const TrainSpec& spec, const WhineResult& r,
                                             int first_id = 1);

// Writes the datasets one after the other into `path` (WriteFileAtomically), one dataset's text
// in memory at a time. Without datasets nothing is written (an earlier file stays): false.
bool WriteUffFile(const std::string& path, const std::vector<UffFunction>& functions);

// What writing OperatingPointUff of `recorded_samples` samples holds, for the memory estimate of
// a run that exports it (simulate --uff, report): the TE and mesh force values it copies and one
// dataset's text of data values (4E20.12: 20 characters each, a line end per 4).
MemoryPart OperatingPointUffMemory(long recorded_samples);

}  // namespace gearnvh::app
