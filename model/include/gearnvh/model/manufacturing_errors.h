// Manufacturing errors of the two gears as an unloaded transmission error of the mesh
// (docs/design.md §13): runout (eccentricity) a_g sin(theta_g(t) + phi_g) of each gear, and
// cumulative pitch deviations f_g[i] of each tooth.
//
// Pitch errors enter the deformation-compatible sharing pair by pair: the pair that entered the
// path of contact q mesh cycles ago carries pinion tooth (c - q) mod z1 and wheel tooth
// (c - q) mod z2 in mesh cycle c (teeth numbered in the order they enter the mesh), and its
// unloaded separation grows by f_1 + f_2. For the set of loaded pairs of the error-free mesh, the
// mesh approach then moves by the stiffness-weighted mean of those deviations,
//   e_pitch = sum_i k_i (f_1 + f_2)_i / sum_i k_i   (exact while the loaded set is unchanged),
// (for a stiffness override the pair stiffnesses are unknown and the pairs in the path weigh
// equally). The mesh stiffness and the loaded set stay those of the error-free mesh, so the
// segment tables stay one mesh cycle long: the error only enters the affine part of the model,
// as the input e_err(t) = runout + e_pitch held at its mean over each segment. Errors large enough
// to unload a pair (a deviation difference beyond the loaded deflection of a pair) change which
// pairs carry load; that is not modelled, and MeshErrorExcitation::UnloadsPairs() says when it
// may happen. Both flanks see the same error (the error is a kinematic angle error of the gears).
// The error repeats after whole revolutions of the gears that carry it (lcm(z1, z2) mesh cycles,
// the hunting period, when both do).
#pragma once

#include <vector>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/mesh_pair.h"
#include "gearnvh/model/mesh_segmentation.h"

namespace gearnvh {

class MeshErrorExcitation {
 public:
  MeshErrorExcitation() = default;
  // The segments' pair weights come from the segmentation.
  MeshErrorExcitation(const MeshPair& pair, const MeshSegmentation& segmentation);

  // True when the gears carry runout or pitch errors (otherwise the input is identically zero).
  bool active() const { return active_; }
  // The same errors with the first gear turning at `speed_a` rad/s (the second in the mesh's
  // ratio): a runout's frequency follows the speed; pitch errors and the pair weights are per
  // tooth and segment, independent of it.
  MeshErrorExcitation AtSpeed(double speed_a) const;
  // Mean of e_err over segment `segment` of mesh cycle `cycle`, which starts at time t0 and lasts
  // h seconds, m. Allocation-free.
  double SegmentMean(long cycle, int segment, double t0, double h) const;
  // An upper bound of |e_err|, m.
  double bound() const { return bound_; }
  // Mesh cycles after which the error repeats: whole revolutions of the gears that carry errors
  // (z1, z2 or lcm(z1, z2)), 1 without errors.
  long period_cycles() const { return period_; }
  // The largest difference of pitch deviations between two teeth of one gear plus the other's,
  // against the loaded deflection of one pair at the operating load: when it is larger, the
  // errors can unload a pair and the loaded set of the error-free mesh no longer holds.
  double largest_pair_deviation() const { return spread_; }

 private:
  bool active_ = false;
  double speeds_[2] = {0.0, 0.0};  // pinion, wheel angular speeds, rad/s
  Runout runout_[2];
  std::vector<double> pitch_[2];
  int teeth_[2] = {1, 1};
  // Per segment: (pair offset q, weight) of the pairs in contact.
  std::vector<std::vector<std::pair<int, double>>> weights_;
  double bound_ = 0.0, spread_ = 0.0;
  long period_ = 1;
};

}  // namespace gearnvh
