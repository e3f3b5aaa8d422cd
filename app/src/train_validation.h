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
#include <atomic>
#include <functional>
#include <vector>

#include "gearnvh/model/train_spec.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_tables.h"
#include "validation_ladder.h"

namespace gearnvh::app {

// progress(done, 4) after each stage (the window run, the CVODE comparison, V2, V1); `cancel` is
// passed to the exact runs (TrainStepperOptions::cancel: RunCancelled), CVODE's runs finish first.
std::vector<ValidationRow> RunTrainValidationLadder(
    const TrainSpec& spec, const std::atomic<bool>* cancel = nullptr,
    const std::function<void(int done, int total)>& progress = {});

// Tolerance of every TE row: 1e-8 of the TE (the issue's).
inline constexpr double kTeTolerance = 1e-8;
// The reference is trusted while it and its estimate differ by at most this relative to the TE.
inline constexpr double kTrustedError = 0.1 * kTeTolerance;
// An event matches a CVODE event within this fraction of the first mesh's period (CVODE's root
// moves with its error by about the TE's relative error times the period: <= 1e-9 of a period in
// the trusted window).
inline constexpr double kEventMatch = 1e-7;

// The trusted window: the count of leading samples over which |reference - estimate| <=
// kTrustedError max |reference| (both maxima over the samples so far; the series sample-major,
// mesh-minor, `meshes` values a sample, at `times`), then shortened while its last sample lies
// within 2 kEventMatch `period` (s) of a reference event (so every event is on one side of the
// window's end for both methods). 0: the two never agree.
size_t TrustedSamples(const std::vector<double>& reference, const std::vector<double>& estimate,
                      size_t meshes, const std::vector<TrainReferenceEvent>& events,
                      const std::vector<double>& times, double period);

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
TrainReferenceComparison CompareTrainWithReference(
    const TrainTables& reference, const TrainTables& candidate, const Eigen::VectorXd& z_reference,
    const Eigen::VectorXd& z_candidate, const std::vector<ContactState>& states0,
    const std::vector<double>& times, const std::atomic<bool>* cancel = nullptr);

}  // namespace gearnvh::app
