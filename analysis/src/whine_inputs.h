// The harmonic inputs of whine (whine.h): each mesh's displacement input and the torque orders as
// exact Fourier coefficients, and the lines they are solved at. Internal to the analysis library.
//
// A periodic input e(t) of period P is sum_n Re(X_n e^{i 2 pi n t / P}) + mean with
//   X_n = (2 / P) integral_0^P e(t) e^{-i 2 pi n t / P} dt,
// in closed form for the piecewise-constant inputs (the static input per segment, the pitch error
// per segment and mesh cycle) and X = -i a e^{i phi} for a sinusoid a sin(w t + phi). Time 0 is
// the start of every mesh's cycle 0, as in the time-domain solver.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "gearnvh/analysis/whine.h"
#include "gearnvh/model/gear_train.h"

namespace gearnvh::whine {

struct GearInput {
  std::string name;
  int teeth = 1;
  double order = 0.0;  // its shaft's speed over the input shaft's
  Runout runout;
  std::vector<double> pitch;  // cumulative pitch deviations per tooth, m (empty: none)
  // The pitch error's signal over one revolution of the gear (z mesh cycles): per cycle and
  // segment its start and end (mesh cycles) and value (m); built once by MeshInputOf.
  std::vector<double> pitch_begin, pitch_end, pitch_value;
};

// One mesh's displacement input e_i(t).
struct MeshInput {
  double mesh_order = 0.0;  // mesh frequency over the input shaft's rotation frequency
  std::vector<double> tau_begin, tau_end;  // the segments, cycle fractions
  std::vector<double> static_input;        // per segment: the static solution delta_j, m
  std::vector<std::vector<std::pair<int, double>>> pitch_weights;  // per segment (MeshSegment)
  GearInput gears[2];

  // X at `order` (input-shaft orders): the static input's harmonic where the order is a whole
  // multiple of the mesh order, each gear's runout at 1x and pitch harmonic at whole multiples of
  // its shaft order; 0 where none.
  std::complex<double> Coefficient(double order) const;
};

// Mesh i's input from its model: the static solution of each segment on the loaded flank
// (e_j + F / k_j on the drive flank, e_j - F / k_j on the back flank) and the gears' errors.
MeshInput MeshInputOf(const TrainSpec& spec, const GearTrain& train, size_t mesh);

// The engine orders' torque on each body at `order` of the input shaft's speed, N m: the phasor X
// of T sin(order W_in t + phi) summed over the excitation orders there (T = J_s a for an
// acceleration order on shaft s, its amplitude for a torque order); empty without one.
std::vector<std::complex<double>> BodyTorques(const TrainSpec& spec, const GearTrain& train,
                                              double order);

// The lines (whine.h), ascending, one per distinct order.
std::vector<WhineLine> Lines(const TrainSpec& spec, const GearTrain& train,
                             const std::vector<MeshInput>& inputs, const WhineOptions& options);

// Whether x is a whole number >= 1 to the rounding of a ratio of orders.
bool WholeMultiple(double x);

}  // namespace gearnvh::whine
