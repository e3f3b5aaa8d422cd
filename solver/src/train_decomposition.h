// The spectral decomposition of a train tuple's generator with its free bodies split off
// (train_tables.h, docs/design.md §11).
//
// A coordinate j whose generator rows and columns are zero but for the slots (no contact and no
// structure couples it: at tier 1 a loose gear whose every mesh is free) moves as a free body
// under its constant forcing (the constant and error slots; a coordinate an excitation order drives
// stays coupled, since the order's state is not constant): x_j'' = a_j^T z_slots. Only the coupled
// coordinates' generator A_c (2p + 2, the slots included) is decomposed, A_c = S_c diag(B0_c,
// B_1..) S_c^-1; the free coordinates join the nilpotent cluster in their own (x_j, v_j)
// coordinates:
//   S = [[S_c, 0], [0, I]] (reordered), B0 = [[B0_c, 0, 0], [0, 0, I], [G, 0, 0]],
//   G = a_Q^T S_c[slots, cluster] (the slots are constant, so their rows of S_c lie on the
//   cluster: the other entries are zero to rounding and are dropped).
// Cost: a Schur form of 2p + (m - 2n) instead of m (the manual transmission at idle: 8 instead of
// 16 while the loose gears fly). Without free coordinates it is DecomposeGenerator itself.
#pragma once

#include <Eigen/Dense>

#include "gearnvh/solver/spectral_gap.h"

namespace gearnvh {

// As DecomposeGenerator(A, n, w_ref, horizon, max_condition).
SpectralDecomposition DecomposeWithFreeBodies(const Eigen::MatrixXd& A, int n, double w_ref,
                                              double horizon, double max_condition);

}  // namespace gearnvh
