#include "gearnvh/nvh/train_periodic_orbit.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/train_lyapunov.h"
#include "gearnvh/solver/train_tangents.h"

namespace gearnvh {

void TrainOrbitOptions::Validate() const {
  if (periods < 1) {
    throw InputError("TrainOrbitOptions.periods", 0, std::to_string(periods), "must be >= 1");
  }
  if (max_iterations < 1) {
    throw InputError("TrainOrbitOptions.max_iterations", 0, std::to_string(max_iterations),
                     "must be >= 1");
  }
  if (!(tolerance > 0.0)) {
    throw InputError("TrainOrbitOptions.tolerance", 0, std::to_string(tolerance), "must be > 0");
  }
  stepper.Validate();
}

const char* TrainOrbitInfoName(TrainOrbit::Info info) {
  switch (info) {
    case TrainOrbit::Info::kConverged:
      return "converged";
    case TrainOrbit::Info::kNotConverged:
      return "not_converged";
    case TrainOrbit::Info::kNoCommonPeriod:
      return "no_common_period";
    case TrainOrbit::Info::kSolverFailed:
      return "solver_failed";
  }
  return "";
}

namespace {

// One exact run over T from (y, states) with the tangent of every elastic coordinate.
struct Shot {
  bool ok = false;
  Eigen::VectorXd end;
  std::vector<ContactState> states;
  Eigen::MatrixXd J;  // 2n x 2n
  long events = 0;
  std::string stop_reason;  // !ok: TrainStepperMessage of the stopped run
};

Shot Shoot(const TrainTables& t, const TrainStepperOptions& options, const Eigen::VectorXd& y,
           const std::vector<ContactState>& states, double period) {
  const int e = 2 * t.n;
  Shot shot;
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(t.m, e);
  V.topRows(e).setIdentity();
  TrainTangentPropagator tangent(t);
  tangent.Attach(&V);
  TrainStepper stepper(t, options, y, states);
  stepper.AttachTangent(&tangent);
  shot.ok = stepper.Run(period);
  shot.end = stepper.state();
  shot.states = stepper.states();
  shot.J = V.topRows(e);
  shot.events = stepper.summary().events;
  if (!shot.ok) shot.stop_reason = TrainStepperMessage(stepper.summary());
  return shot;
}

}  // namespace

TrainOrbit FindTrainPeriodicOrbit(const TrainTables& t, const Eigen::VectorXd& z0,
                                  const std::vector<ContactState>& states0,
                                  const TrainOrbitOptions& options) {
  options.Validate();
  TrainOrbit out;
  if (!(t.common_period > 0.0)) {
    out.info = TrainOrbit::Info::kNoCommonPeriod;
    return out;
  }
  const int n = t.n, e = 2 * n;
  out.period = options.periods * t.common_period;
  // Pi and Q (see the header).
  const int neutral = t.neutral_directions();
  const Eigen::MatrixXd U = t.NeutralBasis();
  Eigen::VectorXd w(e);
  w << t.inertia, t.inertia;
  const Eigen::MatrixXd WU = w.asDiagonal() * U;
  const Eigen::MatrixXd Pi = Eigen::MatrixXd::Identity(e, e) - U * WU.transpose();
  const Eigen::MatrixXd Q =
      Eigen::HouseholderQR<Eigen::MatrixXd>(WU).householderQ() * Eigen::MatrixXd::Identity(e, e);
  const Eigen::MatrixXd Qc = Q.rightCols(e - neutral);
  const double omega_f = 2.0 * std::numbers::pi / TrainForcingPeriod(t);
  Eigen::VectorXd scale(e);
  scale << Eigen::VectorXd::Ones(n), Eigen::VectorXd::Constant(n, 1.0 / omega_f);
  const auto residual_of = [&](const Eigen::VectorXd& y, const Shot& s) {
    const Eigen::VectorXd r = Pi * (s.end.head(e) - y.head(e));
    return r.cwiseProduct(scale).norm() / std::max(y.head(e).cwiseProduct(scale).norm(), 1e-300);
  };

  Eigen::VectorXd y = z0;
  y.head(e) = Pi * z0.head(e);
  std::vector<ContactState> states = states0;
  Shot shot = Shoot(t, options.stepper, y, states, out.period);
  if (!shot.ok) {
    out.info = TrainOrbit::Info::kSolverFailed;
    out.stop_reason = shot.stop_reason;
    return out;
  }
  double residual = residual_of(y, shot);
  for (out.iterations = 0; out.iterations < options.max_iterations; ++out.iterations) {
    if (residual <= options.tolerance) break;
    const Eigen::MatrixXd C = Qc.transpose() * Pi * shot.J * Qc;
    const Eigen::VectorXd F = Qc.transpose() * (Pi * (shot.end.head(e) - y.head(e)));
    const Eigen::VectorXd step =
        -(C - Eigen::MatrixXd::Identity(e - neutral, e - neutral)).fullPivLu().solve(F);
    double theta = 1.0;
    bool improved = false;
    for (int halving = 0; halving <= 10; ++halving, theta *= 0.5) {
      Eigen::VectorXd trial = y;
      trial.head(e) += theta * (Qc * step);
      Shot trial_shot = Shoot(t, options.stepper, trial, shot.states, out.period);
      if (!trial_shot.ok) continue;
      const double trial_residual = residual_of(trial, trial_shot);
      if (trial_residual < residual) {
        y = trial;
        states = shot.states;
        shot = std::move(trial_shot);
        residual = trial_residual;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  out.residual = residual;
  out.info = residual <= options.tolerance ? TrainOrbit::Info::kConverged
                                           : TrainOrbit::Info::kNotConverged;
  out.z = y;
  out.states = states;
  out.events_per_period = shot.events;
  Eigen::VectorXcd mu = (Qc.transpose() * Pi * shot.J * Qc).eigenvalues();
  std::sort(mu.data(), mu.data() + mu.size(),
            [](const std::complex<double>& a, const std::complex<double>& b) {
              return std::abs(a) > std::abs(b);
            });
  out.multipliers = mu;
  out.stable = mu.size() == 0 || std::abs(mu[0]) < 1.0;
  return out;
}

}  // namespace gearnvh
