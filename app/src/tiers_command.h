// `gearnvh tiers FILE [--cycles N] [--transient N] [--json] [--out DIR] [--width PX]
// [--height PX] [--dpi DPI]`: the modal truncation
// levels side by side (tiers 1-5 / N40 full, N20 simple, N20 MTA, N20 MTA + fusion): DOF, state
// dimension, lowest natural frequencies and their error against the full FE model, static mesh
// compliance error, TE RMS and rattle index at the operating point and their difference to the
// finest tier, and cost (matvec per cycle, us per cycle, real-time ratio, table bytes). A table on
// the terminal, JSON, and with --out tiers.json, tiers.csv and tiers.png (accuracy against cost).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/solver/exact_solver.h"

namespace gearnvh::app {

struct TiersCommandOptions {
  std::string file;
  std::optional<long> cycles;     // recorded cycles per tier (default min(analysis.cycles, 400))
  std::optional<long> transient;  // default min(analysis.transient_cycles, 200)
  std::optional<std::string> out;
  bool json = false;
  int width = 1200, height = 800;  // tiers.png, px
  double dpi = 100.0;              // tiers.png; scales the fonts
  bool allow_slow = false;         // gear trains: run even when the cost estimate exceeds an hour
};

int RunTiers(const TiersCommandOptions& options);

// One row of the comparison: a tier (and N20 MTA once more with fusion).
struct TierRow {
  std::string name;
  SolverMethod method = SolverMethod::kStepped;  // of the run
  // A run that stopped (kOutOfRange, kTooManyEvents) keeps its model columns; its results (TE,
  // rattle, their differences, regime and cost) are NaN and `message` says why.
  SolverStatus status = SolverStatus::kSuccess;
  std::string message;
  int dof = 0, state_dim = 0;
  int rigid_body_modes = 0;              // left out of the frequencies (modal_analysis.h)
  std::vector<double> frequencies_hz;    // lowest elastic (up to 6)
  std::vector<double> frequency_errors;  // relative, against the closest full-FE frequency
  double max_frequency_error = 0.0;
  std::optional<double> compliance_error;  // none for tier 1 (ComplianceErrorVsFull)
  double te_rms = 0.0, rattle_index = 0.0;
  double te_rms_difference = 0.0, rattle_index_difference = 0.0;  // relative to the finest tier
  RattleRegime regime = RattleRegime::kNoImpact;
  double matvec_per_cycle = 0.0, us_per_cycle = 0.0, real_time_ratio = 0.0;
  size_t table_bytes = 0;
  bool ok() const { return status == SolverStatus::kSuccess; }
};

struct TiersComparison {
  std::vector<TierRow> rows;
  // The row with most DOF among those whose run succeeded, the reference of the differences (the
  // row with most DOF when none did: its differences are then NaN).
  size_t finest = 0;
  int failed = 0;  // rows whose run stopped
  int full_fe_dof = 0;
  int full_fe_rigid_body_modes = 0;
  nlohmann::json doc;  // the `tiers --json` document without name and file
};

// The largest relative error of a tier's lowest (up to 6) natural frequencies, each against the
// closest frequency of the full FE model.
double TierFrequencyError(const ReducedModel& reduced, const ModalSummary& full);

// The exit code of `tiers` (either schema): 1, said on stderr, when `failed` of the `tiers` runs
// stopped (the others are listed), else 0.
int TiersExitCode(int failed, size_t tiers);

// (tier being run, tiers in all, its name)
using TiersProgress = std::function<void(size_t, size_t, const std::string&)>;

// Every available tier at the operating point with `solver`'s cycles (also N20 MTA with fusion),
// one after the other; a tier whose run stops is a failed row, and the others still run.
// `before_run_memory` is AnalyseOperatingPoint's, for every tier's run.
TiersComparison CompareTiers(const GearboxSpec& spec, const SolverOptions& solver,
                             const TiersProgress& progress = {},
                             const std::function<std::string(RunMemory&)>& before_run_memory = {});

}  // namespace gearnvh::app
