// Cutting the mesh cycle into S segments for the piecewise-LTI solver (docs/design.md §4.1).
//
// Mandatory boundaries (in cycle fraction tau): 0, every change of the loaded-pair count on either
// flank (located by bisection to 1e-12 of the cycle), every pitch-point crossing on either
// flank (friction reverses there), and every switch of a stiffness override on either flank
// (MeshEvaluator::OverrideBreaks), so no segment averages k or e across a discontinuity. The
// remaining S - (#mandatory) cuts are spread over the intervals in proportion to their length
// (largest remainder; every interval gets at least one segment, and segments inside an interval are
// equal). Within segment j every quantity is replaced by its mean over the segment (8-point
// Gauss–Legendre on the smooth integrand between boundaries):
//   k_j (per flank), LSTE_j, friction sigma/arms (per flank), and the unloaded error
//   e_j = mean(LSTE) - F / k_j + mean(user STE),
// chosen so that the static solution of k_j (delta - e_j) = F reproduces the mean loaded STE.
// User STE: e_user(tau) = sum_n A_n cos(2 pi n tau + phi_n).
#pragma once

#include <vector>

#include "gearnvh/model/mesh_stiffness.h"

namespace gearnvh {

struct FlankSegment {
  double stiffness = 0.0;            // N/m
  double friction_sigma = 0.0;       // sum LSR sgn
  double friction_arm_pinion = 0.0;  // m
  double friction_arm_wheel = 0.0;   // m
};

struct MeshSegment {
  double tau_begin = 0.0, tau_end = 0.0;
  FlankSegment drive, back;
  double lste = 0.0;            // mean loaded static TE (drive flank), m
  double unloaded_error = 0.0;  // e_j, m
  // Sensitivity of the mesh approach to each loaded pair's unloaded separation (segment mean of
  // d delta / d e_i = k_i / sum k over the loaded pairs; equal shares for a stiffness override),
  // keyed by the pair's offset q: the pair entered the path of contact q mesh cycles ago.
  std::vector<std::pair<int, double>> error_weights;
};

struct MeshSegmentation {
  std::vector<MeshSegment> segments;     // S segments covering [0, 1)
  std::vector<double> mandatory_breaks;  // the mandatory boundaries found
};

// Throws InputError (analysis.segments_per_cycle) when S is below the number of mandatory
// boundaries.
MeshSegmentation SegmentMeshCycle(const MeshPair& pair, const MeshEvaluator& evaluator,
                                  int segments_per_cycle, int scan_samples = 2048);

// The cycle mean of the flank's stiffness over the segments the solver integrates,
// sum_j k_j (tau_end - tau_begin), N/m: exact for a stiffness override (its switches are segment
// boundaries). MeshStiffnessSummary::mean is the drive flank's.
double CycleMeanStiffness(const MeshSegmentation& segmentation, Flank flank);

}  // namespace gearnvh
