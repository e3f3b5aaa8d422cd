// The validation ladder of a gear train (schema gearnvh/2, docs/design.md §8 and §11): the exact
// train solver at analysis.tier (V3) against the CVODE reference (TE and every event) and against
// its V2 and V1 event methods, over the first cycles of the run from the static state; and V3's
// segment-run fusion against V3 step by step over the first common periods.
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

#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/analysis/validation_ladder.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

struct TrainValidationOptions {
  // Passed to the table build, the exact runs and CVODE's runs (each polls it: RunCancelled once
  // set). Not owned; null: never cancelled.
  const std::atomic<bool>* cancel = nullptr;
  // progress(done, 5) after each stage (the window run, the CVODE comparison, V2, V1, fusion).
  std::function<void(int done, int total)> progress;
  // The ladder's worst case (TrainValidationCost) above kSlowRunRefuseSeconds is refused unless
  // this is set (CheckRunCost: InputError naming names("allow-slow")).
  bool allow_slow = false;
  OptionNames names;
  // Called with the cost warning (above kSlowRunWarnSeconds) before the first run; empty: not
  // called.
  std::function<void(const std::string&)> before_run_warning;
};

std::vector<ValidationRow> RunTrainValidationLadder(const TrainSpec& spec,
                                                    const TrainValidationOptions& options = {});

// The ladder's worst case on `tables`: its five exact runs, the window run, V3, V2 and V1 each
// the longest window (200 cycles of the first mesh) and the fused check the longer of that and
// its kFusionPeriods common periods. CVODE's two runs are not counted (their cost is not the
// dense sub-step's).
RunCostEstimate TrainValidationCost(const TrainTables& tables, const TrainSpec& spec);

// Tolerance of every TE row: 1e-8 of the TE (the issue's).
inline constexpr double kTeTolerance = 1e-8;
// Tolerance of the fusion row, relative to the TE at a run's end: a fused run and the same grid
// segments stepped from the same state apply the same propagators, the fused one as a product of
// up to 32 balanced-Pade expm against one closed-form piece per grid segment, each within about
// cond(S) eps of the exact map (cond(S) <= 1e6); the unit tests measure 1.1e-12 (a rattling
// train) and 1.3e-11 (a strong engine order) and allow 3e-11
// (tests/solver/train_segment_runs_test.cc); a wrong input column or length moves the TE by > 1e-6.
inline constexpr double kFusionTolerance = 3e-11;
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

// The events of either list up to `end` (s) left unpaired when each reference event is paired
// with the nearest unpaired exact event of the same mesh, from and to state within `tolerance` (s).
// By value, not by order: simultaneous events of different meshes (a kinematic loop) come in
// either order.
long UnpairedEvents(const std::vector<TrainReferenceEvent>& reference,
                    const std::vector<TrainEventRecord>& exact, double end, double tolerance);

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

// The row "segment-run fusion vs step by step": V3 steps `tables` grid segment by grid segment
// (no jumps, no fusion) from z0 in states0 over the first kFusionPeriods common periods; at every
// grid segment start its state is offered to segment-run fusion on `fused_tables` (its tables
// built as it goes, so the second period uses held runs), and every certified run is compared
// with the same grid segments stepped: no contact event or grazing in them, and the TE of every
// mesh at the run's end within kFusionTolerance of the largest. Each run is compared from the
// stepped state, not end to end: a rattle amplifies any rounding difference about tenfold per
// millisecond, so two whole runs would part however exact each is. Skipped without a common
// period, with more than max_cycle_map_segments grid segments in it, or when no run was
// certified. The ladder passes the same tables twice; a test passes altered tables to see the row
// fail.
inline constexpr int kFusionPeriods = 2;
ValidationRow CompareFusionWithStepping(const TrainTables& tables, const TrainTables& fused_tables,
                                        const Eigen::VectorXd& z0,
                                        const std::vector<ContactState>& states0,
                                        const std::atomic<bool>* cancel = nullptr);

}  // namespace gearnvh
