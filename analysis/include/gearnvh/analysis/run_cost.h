// The run-cost estimate of a gear-train run (docs/cli.md, "Run cost"), made before the run from the
// solver's own rate bound, and the warning or refusal it leads to.
#pragma once

#include <string>
#include <vector>

#include "gearnvh/analysis/option_names.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

// The run-cost estimate of a train run and what a command does with it (docs/cli.md, "Run
// cost"): the dense path takes about 2 rho sub-steps per simulated second, rho the solver's own
// bound on the spectral radius of the generator (BoundTupleRate, solver/train_rate_bound.h), each
// costing about kSubstepSecondsPerState2 m^2 (m the state dimension). Above kSlowRunWarnSeconds a
// warning, above kSlowRunRefuseSeconds a refusal unless the caller allows slow runs.
//
// The per-sub-step constant is a third of what was measured (65 us per sub-step at m = 86, i.e.
// ~9e-9 m^2 s: the manual-transmission example at tier 3 with a heavy rigid shaft, dense path, on
// the 2-core development machine, 2026-12-02) so that a faster machine is not refused a run that
// is not surely slow. The closed-form path (decomposed tuples), certified jumps and
// segment-run fusion can make the transient cheaper than the dense path; the recorded cycles are
// always stepped on sub-steps (the recorder's Taylor chunks).
constexpr double kSubstepSecondsPerState2 = 3e-9;
constexpr double kSlowRunWarnSeconds = 60.0;
constexpr double kSlowRunRefuseSeconds = 3600.0;

// The term of rho that dominates it (BoundTupleRate): the highest undamped mode sqrt(lambda_max(
// M^-1 K)), the symmetric damping lambda_max(M^-1 C), the gyroscopic (skew) part of a reduced
// tier's damping, or tooth friction.
enum class RateTerm { kStiffness, kDamping, kGyroscopic, kFriction, kExcitation };
const char* RateTermName(RateTerm term);

// What a run costs, estimated before it starts, on the tuple the run starts in with every mesh in
// drive contact (segment 0 of every mesh, t = 0): the solver's own bound rho on that tuple's
// spectral radius (tooth friction and a reduced tier's skew damping included), so the dense
// path's sub-step there is 1 / (2 rho) unless its second bound (the balanced row norm) is
// shorter; the highest frictionless undamped mode omega = sqrt(lambda_max(M^-1 K)) of that tuple
// and the body that moves most in it.
struct RunCostEstimate {
  double mode_hz = 0.0;          // the highest mode, Hz (frictionless)
  double fastest_mesh_hz = 0.0;  // the fastest mesh frequency, Hz
  int body = 0;                  // the body that moves most in the highest mode
  double substep_s = 0.0;        // 1 / (2 rho), s; 0 when rho is 0 or an eigenproblem failed
  double rho = 0.0;              // 1/s
  RateTerm dominant = RateTerm::kStiffness;
  double dominant_rate = 0.0;  // that term's part of rho, 1/s
  // The body the dominant term comes from: for kGyroscopic the body whose node has the largest
  // spin rate |w_b| I_p / I_d (the nutation a disk's gyroscopic moment drives), else `body`.
  int cause_body = 0;
  std::string cause_body_name;
  double cause_body_inertia = 0.0;   // its polar inertia, kg m^2
  double cause_nutation_rate = 0.0;  // kGyroscopic: |w_b| I_p / I_d at that node, rad/s
  Tier tier = Tier::kTier1;
  int state_dim = 0;         // m
  double simulated_s = 0.0;  // the simulated time the estimate is for, s (all runs)
  double substeps = 0.0;     // simulated_s / substep_s (all runs)
  double wall_s = 0.0;       // substeps * kSubstepSecondsPerState2 m^2 (/ parallel runs)
  int runs = 1;              // runs counted (a sweep's speeds, an atlas's cells, tiers)
};
// For `simulated_s` seconds of simulated time on `tables`. The structure is assembled for the
// gyroscopic cause's body when that term dominates (tiers 2+ only).
RunCostEstimate EstimateRunCost(const TrainTables& tables, double simulated_s = 0.0,
                                const TrainSpec* spec = nullptr);
// Several runs: sub-steps summed, wall time summed over `parallel` threads (>= 1), the cause that
// of the costliest run.
RunCostEstimate CombineRunCosts(const std::vector<RunCostEstimate>& runs, int parallel);

// The cost of running `what` ("the run", "the sweep's 12 speeds"): empty below
// kSlowRunWarnSeconds, else a warning naming the estimate and its cause. Above
// kSlowRunRefuseSeconds, unless `allow_slow`, throws InputError at names("allow-slow") (exit 2
// on the command line) stating the estimate, its cause and that the option allows the run.
std::string CheckRunCost(const RunCostEstimate& cost, bool allow_slow,
                         const std::string& what = "the run", const OptionNames& names = {});

// The warning text of a cost (whatever its size): the estimate and its cause.
std::string RunCostText(const RunCostEstimate& cost, const std::string& what);

}  // namespace gearnvh
