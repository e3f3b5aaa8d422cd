#include "gearnvh/nvh/lyapunov.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "gearnvh/model/input_error.h"

namespace gearnvh {

void LyapunovOptions::Validate() const {
  if (transient_cycles < 0) {
    throw InputError("LyapunovOptions.transient_cycles", 0, std::to_string(transient_cycles),
                     "must be >= 0");
  }
  if (alignment_cycles < 0) {
    throw InputError("LyapunovOptions.alignment_cycles", 0, std::to_string(alignment_cycles),
                     "must be >= 0");
  }
  if (blocks < 2) {
    throw InputError("LyapunovOptions.blocks", 0, std::to_string(blocks), "must be >= 2");
  }
  if (renormalise_cycles < 1) {
    throw InputError("LyapunovOptions.renormalise_cycles", 0, std::to_string(renormalise_cycles),
                     "must be >= 1");
  }
  if (cycles < blocks * renormalise_cycles) {
    throw InputError("LyapunovOptions.cycles", 0, std::to_string(cycles),
                     "must be >= blocks * renormalise_cycles (" +
                         std::to_string(blocks * renormalise_cycles) + ")");
  }
  solver.Validate();
}

const char* LyapunovInfoName(LyapunovEstimate::Info info) {
  return info == LyapunovEstimate::Info::kSuccess ? "success" : "solver_failed";
}

double ForcingPeriod(const SegmentTables& tables) {
  if (tables.excitation.empty()) return tables.mesh_period;
  return 2.0 * std::numbers::pi / (tables.excitation.front().order * tables.pinion_speed);
}

namespace {

// A fixed, generic start direction on the quotient (every elastic coordinate excited).
Eigen::MatrixXd StartDirection(const SegmentTables& t) {
  Eigen::MatrixXd u = Eigen::MatrixXd::Zero(t.m, 1);
  for (int i = 0; i < 2 * t.n; ++i) u(i, 0) = 1.0 + 0.1 * std::sin(1.0 + i);
  RemoveFreeRotation(t, u);
  return u;
}

}  // namespace

LyapunovEstimate EstimateLyapunov(const SegmentTables& tables, const Eigen::VectorXd& z0,
                                  ContactState state0, const LyapunovOptions& options) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  LyapunovEstimate out;
  SolverOptions solver = options.solver;
  solver.method = SolverMethod::kStepped;
  solver.cycles = options.cycles;
  solver.transient_cycles = options.transient_cycles;
  solver.record_trajectory = options.record;
  const RecordingReserve reserve = options.record ? PlanRecording(solver) : RecordingReserve{};
  ExactStepper stepper(tables, solver, z0, state0, static_cast<size_t>(reserve.samples),
                       static_cast<size_t>(reserve.events));
  auto fail = [&]() {
    out.info = LyapunovEstimate::Info::kSolverFailed;
    out.message = stepper.summary().message;
    out.run.summary = stepper.summary();
    return out;
  };
  if (options.transient_cycles > 0 && !stepper.Run(options.transient_cycles, false)) return fail();
  Eigen::MatrixXd u = StartDirection(tables);
  u /= u.topRows(2 * tables.n).norm();
  stepper.AttachTangent(&u);
  for (long c = 0; c < options.alignment_cycles; ++c) {
    if (!stepper.Run(1, false)) return fail();
    u /= std::max(u.topRows(2 * tables.n).norm(), std::numeric_limits<double>::min());
  }
  // The summary covers the averaged cycles only (unrecorded runs count no events; these too).
  stepper.summary().matvecs = 0;
  stepper.summary().mesh_cycles = 0;
  stepper.summary().min_event_rate = std::numeric_limits<double>::infinity();
  const long intervals = options.cycles / options.renormalise_cycles;
  const long per_block = intervals / options.blocks;
  double total_log = 0.0, block_log = 0.0;
  long averaged_cycles = 0;
  const double interval_s = static_cast<double>(options.renormalise_cycles) * tables.mesh_period;
  for (long i = 0; i < intervals; ++i) {
    if (!stepper.Run(options.renormalise_cycles, options.record)) return fail();
    const double norm = u.topRows(2 * tables.n).norm();
    // A vanishing tangent (every direction contracted to underflow) would give -inf: the growth
    // rate is then below what double precision can resolve over one interval.
    const double growth = std::log(std::max(norm, std::numeric_limits<double>::min()));
    u /= std::max(norm, std::numeric_limits<double>::min());
    total_log += growth;
    block_log += growth;
    averaged_cycles += options.renormalise_cycles;
    if ((i + 1) % per_block == 0 && static_cast<int>(out.block_exponents.size()) < options.blocks) {
      out.block_exponents.push_back(block_log / (static_cast<double>(per_block) * interval_s));
      block_log = 0.0;
    }
  }
  stepper.AttachTangent(nullptr);
  const double averaged_s = static_cast<double>(averaged_cycles) * tables.mesh_period;
  out.exponent = total_log / averaged_s;
  out.forcing_period = ForcingPeriod(tables);
  out.per_mesh_cycle = out.exponent * tables.mesh_period;
  out.per_forcing_cycle = out.exponent * out.forcing_period;
  double mean = 0.0, var = 0.0;
  for (double b : out.block_exponents) mean += b;
  mean /= static_cast<double>(out.block_exponents.size());
  for (double b : out.block_exponents) var += (b - mean) * (b - mean);
  var /= static_cast<double>(out.block_exponents.size() - 1);
  out.standard_error = std::sqrt(var / static_cast<double>(out.block_exponents.size()));
  const double inf = std::numeric_limits<double>::infinity();
  out.predictability_horizon_s = out.exponent > 0.0 ? 52.0 * std::log(2.0) / out.exponent : inf;
  out.predictability_horizon_cycles =
      out.exponent > 0.0 ? out.predictability_horizon_s / out.forcing_period : inf;

  SolverSummary& s = stepper.summary();
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.simulated_s = stepper.time();
  s.real_time_ratio = s.wall_s > 0.0 ? s.simulated_s / s.wall_s : 0.0;
  s.separated_s = stepper.SeparatedTime();
  s.events_per_cycle = static_cast<double>(s.events) / static_cast<double>(options.cycles);
  s.matvec_per_cycle = static_cast<double>(s.matvecs) / static_cast<double>(options.cycles);
  s.mesh_cycles += options.transient_cycles + options.alignment_cycles;
  out.run.summary = s;
  out.run.trajectory = std::move(stepper.trajectory());
  out.run.final_state = stepper.state();
  out.run.final_contact = stepper.contact();
  return out;
}

}  // namespace gearnvh
