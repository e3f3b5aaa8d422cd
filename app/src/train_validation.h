// The validation ladder of a gear train (schema gearnvh/2, docs/design.md §8 and §11): the exact
// train solver at analysis.tier (V3) against the CVODE reference (TE and every event) and against
// its V2 and V1 event methods, over the first cycles of the run from the static state.
//
// A rattling train amplifies any error quickly (a light loose gear: ~10^3 per mesh cycle), so
// CVODE, whose accuracy in double precision ends near rtol 1e-13, is itself accurate to 1e-8 of
// the TE only over the first cycles. The comparison is therefore restricted to the window where
// the reference is trusted: CVODE runs twice (rtol 1e-13 and 1e-12), and the window ends before
// the first sample at which the two differ by more than a tenth of the TE tolerance (the error
// estimate of the coarser run, larger than that of the reference run), clear of any event.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "gearnvh/model/train_spec.h"
#include "gearnvh/solver/train_tables.h"
#include "validation_ladder.h"

namespace gearnvh::app {

std::vector<ValidationRow> RunTrainValidationLadder(const TrainSpec& spec);

// The rows "exact TE vs CVODE" and "events vs CVODE": the exact solver (V3) on `candidate` from
// z_candidate against CVODE on `reference` from z_reference, both in states0, at `times` (uniform,
// times[k] = (k + 1) times[0]). The ladder passes the same tables and state twice; a test passes
// a perturbed state or altered tables to see the rows fail.
struct TrainReferenceComparison {
  std::vector<ValidationRow> rows;
  size_t trusted_samples = 0;   // leading samples where the reference is trusted (0: none)
  double trusted_cycles = 0.0;  // the window they span, in cycles of the first mesh
  bool exact_ran = true;        // false: the exact run stopped (its row says why), nothing compared
};
TrainReferenceComparison CompareTrainWithReference(const TrainTables& reference,
                                                   const TrainTables& candidate,
                                                   const Eigen::VectorXd& z_reference,
                                                   const Eigen::VectorXd& z_candidate,
                                                   const std::vector<ContactState>& states0,
                                                   const std::vector<double>& times);

}  // namespace gearnvh::app
