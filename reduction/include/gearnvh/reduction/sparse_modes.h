// The lowest natural modes of a large sparse pencil (K, M) with a few rigid-body modes, by
// Spectra's shift-invert Lanczos at a small negative shift s = -1e-10 max_i K_ii / M_ii (K itself
// is singular at 0). Rigid-body modes by the criterion of model/modal_analysis.h (`magnitude`
// defaults to |x|^T |K| |x| of this K).
#pragma once

#include <Eigen/Sparse>

#include "gearnvh/model/modal_analysis.h"

namespace gearnvh {

// The `count` lowest elastic modes (frequencies and M-normalised shapes); `rigid_body_modes` is how
// many rigid-body modes to expect below them (the Lanczos run asks for count + that many). Empty
// when Lanczos does not converge.
NaturalModes LowestSparseNaturalModes(const Eigen::SparseMatrix<double>& K,
                                      const Eigen::SparseMatrix<double>& M, int count,
                                      int rigid_body_modes,
                                      const StrainMagnitude& magnitude = {});

}  // namespace gearnvh
