// Craig–Bampton basis (Craig & Bampton 1968) for a sparse structure with a chosen boundary.
//
//   q = T [x_b; eta],   T = [[I, 0], [Psi, Phi]]   (rows: boundary, interior; stored in full DOF
//                                                   order)
//   Psi = -K_ii^{-1} K_ib          constraint modes (sparse LDL^T of K_ii)
//   K_ii phi = w^2 M_ii phi        lowest fixed-interface modes, M_ii-normalised
// The modes come from Spectra's SymGEigsShiftSolver in shift-invert mode at sigma = 0 on the
// sparse pencil; interiors with fewer than ReductionOptions::dense_eigen_threshold DOF use a dense
// solver, because the Lanczos subspace must be smaller than the problem.
// Preconditions: K, M symmetric, K_ii positive definite (the boundary must remove every free
// direction of the interior — the gear-node rotations do, for shafts on bearings).
// modes = 0 gives Guyan (static) condensation; otherwise at least `modes` fixed-interface modes,
// more where the cut would split a cluster (FixedInterfaceModes).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "gearnvh/reduction/reduced_model.h"

namespace gearnvh {

enum class CraigBamptonStatus { kSuccess, kInteriorSingular, kEigenNotConverged };

struct CraigBamptonBasis {
  CraigBamptonStatus status = CraigBamptonStatus::kSuccess;
  Eigen::MatrixXd T;                       // full DOF x (boundary + kept modes)
  Eigen::VectorXd fixed_interface_omega2;  // ascending, rad^2/s^2
  bool sparse_eigensolver = false;
  std::string message;
};

// The lowest `modes` fixed-interface modes of the DOF `interior` (every other DOF held):
// K_ii phi = w^2 M_ii phi, M_ii-normalised, ascending, as columns over the full DOF (zero outside
// the interior). The eigensolver choice is CraigBampton's. The count grows past `modes` to the
// end of a cluster of equal eigenvalues (reduction/src/mode_cut.h): a cut never splits a
// degenerate pair, whose members the solver returns in an arbitrary rotation.
struct FixedInterfaceModeSet {
  CraigBamptonStatus status = CraigBamptonStatus::kSuccess;
  Eigen::MatrixXd shapes;  // full DOF x kept modes
  Eigen::VectorXd omega2;  // rad^2/s^2
  bool sparse_eigensolver = false;
  std::string message;
};
FixedInterfaceModeSet FixedInterfaceModes(const Eigen::SparseMatrix<double>& K,
                                          const Eigen::SparseMatrix<double>& M,
                                          const std::vector<int>& interior, int modes,
                                          const ReductionOptions& options = {});

// The lowest `modes` fixed-interface modes over several uncoupled interiors (the shafts'
// interiors, uncoupled once the gear nodes are held): the same set as one solve of their union,
// found part by part. Each part's pencil is solved on its own (FixedInterfaceModes), the values are
// merged and cut (never inside a cluster), and a part is asked for more modes while its largest
// computed one lies below the first value cut off. Solving the parts apart keeps the shapes exactly
// zero on the other parts and finds the repeated values of identical shafts, which one Lanczos run
// over the union sees only through rounding (one direction per distinct value). Ascending; ties in
// part order.
FixedInterfaceModeSet LowestFixedInterfaceModes(const Eigen::SparseMatrix<double>& K,
                                                const Eigen::SparseMatrix<double>& M,
                                                const std::vector<std::vector<int>>& interiors,
                                                int modes, const ReductionOptions& options = {});

CraigBamptonBasis CraigBampton(const Eigen::SparseMatrix<double>& K,
                               const Eigen::SparseMatrix<double>& M,
                               const std::vector<int>& boundary, int modes,
                               const ReductionOptions& options = {});

}  // namespace gearnvh
