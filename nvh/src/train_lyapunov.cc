#include "gearnvh/nvh/train_lyapunov.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/train_tangents.h"

namespace gearnvh {

void TrainLyapunovOptions::Validate() const {
  if (exponents < 1) {
    throw InputError("TrainLyapunovOptions.exponents", 0, std::to_string(exponents),
                     "must be >= 1");
  }
  if (transient_cycles < 0) {
    throw InputError("TrainLyapunovOptions.transient_cycles", 0, std::to_string(transient_cycles),
                     "must be >= 0");
  }
  if (alignment_cycles < 0) {
    throw InputError("TrainLyapunovOptions.alignment_cycles", 0, std::to_string(alignment_cycles),
                     "must be >= 0");
  }
  if (blocks < 2) {
    throw InputError("TrainLyapunovOptions.blocks", 0, std::to_string(blocks), "must be >= 2");
  }
  if (renormalise_cycles < 1) {
    throw InputError("TrainLyapunovOptions.renormalise_cycles", 0,
                     std::to_string(renormalise_cycles), "must be >= 1");
  }
  if (cycles < blocks * renormalise_cycles) {
    throw InputError("TrainLyapunovOptions.cycles", 0, std::to_string(cycles),
                     "must be >= blocks * renormalise_cycles (" +
                         std::to_string(blocks * renormalise_cycles) + ")");
  }
  stepper.Validate();
}

const char* TrainLyapunovInfoName(TrainLyapunovSummary::Info info) {
  return info == TrainLyapunovSummary::Info::kSuccess ? "success" : "solver_failed";
}

double TrainForcingPeriod(const TrainTables& tables) {
  if (tables.excitation.empty()) return tables.meshes.front().period;
  return 2.0 * std::numbers::pi / (tables.excitation.front().order * tables.input_speed);
}

namespace {

// The exponents largest first, each with its standard error. Column j of the QR converges to the
// j-th exponent, but over a short run two close ones may not have separated yet (the partial sums
// are the volume growth rates either way).
void SortDescending(TrainLyapunovSummary& out) {
  std::vector<size_t> order(out.exponents.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return out.exponents[a] > out.exponents[b]; });
  for (std::vector<double>* v :
       {&out.exponents, &out.per_mesh_cycle, &out.per_forcing_cycle, &out.standard_errors}) {
    std::vector<double> sorted;
    for (size_t j : order) sorted.push_back((*v)[j]);
    *v = std::move(sorted);
  }
}

// Fixed generic start directions on the quotient (every elastic coordinate excited, columns
// independent).
Eigen::MatrixXd StartDirections(const TrainTables& t, int k) {
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(t.m, k);
  for (int c = 0; c < k; ++c) {
    for (int i = 0; i < 2 * t.n; ++i) V(i, c) = 1.0 + 0.5 * std::sin(1.0 + i + 7.3 * c * (i + 1));
  }
  return V;
}

// Modified Gram-Schmidt (twice, for orthogonality to rounding) on the elastic rows after the
// free rotation is projected out; adds ln |R_jj| to `logs`.
void Reorthonormalise(const TrainTables& t, Eigen::MatrixXd& V, double* logs) {
  RemoveTrainFreeRotation(t, V);
  const int e = 2 * t.n;
  for (Eigen::Index c = 0; c < V.cols(); ++c) {
    double diagonal = 1.0;
    for (int pass = 0; pass < 2; ++pass) {
      for (Eigen::Index p = 0; p < c; ++p) {
        V.col(c).head(e) -= V.col(p).head(e).dot(V.col(c).head(e)) * V.col(p).head(e);
      }
      const double norm = std::max(V.col(c).head(e).norm(), std::numeric_limits<double>::min());
      V.col(c).head(e) /= norm;
      diagonal *= norm;  // the second pass's norm is 1 to rounding
    }
    if (logs != nullptr) logs[c] += std::log(diagonal);
  }
}

}  // namespace

TrainLyapunovSummary EstimateTrainLyapunov(const TrainTables& tables, const Eigen::VectorXd& z0,
                                           const std::vector<ContactState>& states0,
                                           const TrainLyapunovOptions& options) {
  options.Validate();
  const int k = options.exponents;
  // The free rotation's position and velocity and each standing rotation's are removed.
  const int most = 2 * tables.n - 2 - 2 * static_cast<int>(tables.standing_rotations.cols());
  if (k > most) {
    throw InputError("TrainLyapunovOptions.exponents", 0, std::to_string(k),
                     "must be <= " + std::to_string(most) +
                         " (the elastic state without the free rotation and standing shafts)");
  }
  TrainLyapunovSummary out;
  out.mesh_period = tables.meshes.front().period;
  out.forcing_period = TrainForcingPeriod(tables);
  TrainStepper stepper(tables, options.stepper, z0, states0);
  const auto fail = [&]() {
    out.info = TrainLyapunovSummary::Info::kSolverFailed;
    out.message = "the train stepper stopped: " + TrainStepperMessage(stepper.summary());
    out.run = stepper.summary();
    return out;
  };
  const double period = out.mesh_period;
  if (!stepper.Run(static_cast<double>(options.transient_cycles) * period)) return fail();
  Eigen::MatrixXd V = StartDirections(tables, k);
  Reorthonormalise(tables, V, nullptr);
  TrainTangentPropagator tangent(tables);
  tangent.Attach(&V);
  stepper.AttachTangent(&tangent);
  const double interval = static_cast<double>(options.renormalise_cycles) * period;
  double time = static_cast<double>(options.transient_cycles) * period;
  const long alignment_intervals =
      (options.alignment_cycles + options.renormalise_cycles - 1) / options.renormalise_cycles;
  const long intervals = options.cycles / options.renormalise_cycles;
  const double end_time = time + static_cast<double>(alignment_intervals + intervals) * interval;
  const auto report = [&]() {
    if (options.progress) options.progress(time / end_time);
  };
  for (long i = 0; i < alignment_intervals; ++i) {
    time += interval;
    if (!stepper.Run(time, options.recorder)) return fail();
    Reorthonormalise(tables, V, nullptr);
    report();
  }
  const long per_block = intervals / options.blocks;
  std::vector<double> total(static_cast<size_t>(k), 0.0), block(static_cast<size_t>(k), 0.0);
  std::vector<std::vector<double>> block_exponents(static_cast<size_t>(k));
  for (long i = 0; i < intervals; ++i) {
    time += interval;
    if (!stepper.Run(time, options.recorder)) return fail();
    Reorthonormalise(tables, V, block.data());
    report();
    if ((i + 1) % per_block == 0 && static_cast<int>(block_exponents[0].size()) < options.blocks) {
      for (size_t j = 0; j < block.size(); ++j) {
        block_exponents[j].push_back(block[j] / (static_cast<double>(per_block) * interval));
        total[j] += block[j];
        block[j] = 0.0;
      }
    }
  }
  stepper.AttachTangent(nullptr);
  // Averaged over the whole blocks (a remainder of intervals % blocks is left out of both).
  out.averaged_s = static_cast<double>(per_block * options.blocks) * interval;
  for (size_t j = 0; j < total.size(); ++j) {
    const double lambda = total[j] / out.averaged_s;
    out.exponents.push_back(lambda);
    out.per_mesh_cycle.push_back(lambda * out.mesh_period);
    out.per_forcing_cycle.push_back(lambda * out.forcing_period);
    double var = 0.0;
    for (double b : block_exponents[j]) var += (b - lambda) * (b - lambda);
    var /= static_cast<double>(options.blocks - 1);
    out.standard_errors.push_back(std::sqrt(var / static_cast<double>(options.blocks)));
  }
  SortDescending(out);
  const double inf = std::numeric_limits<double>::infinity();
  out.predictability_horizon_s =
      out.exponents.front() > 0.0 ? 52.0 * std::log(2.0) / out.exponents.front() : inf;
  out.predictability_horizon_cycles =
      out.exponents.front() > 0.0 ? out.predictability_horizon_s / out.forcing_period : inf;
  out.saltations = tangent.saltations();
  out.run = stepper.summary();
  return out;
}

}  // namespace gearnvh
