#include "gearnvh/nvh/periodic_orbit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "gearnvh/model/count_text.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/lyapunov.h"

namespace gearnvh {

long BasePeriodCycles(const SegmentTables& t) {
  constexpr long kMaxCycles = 100000;
  const long n = t.CommonPeriodCycles(kMaxCycles);
  if (n > 0) return n;
  throw NoCommonPeriod();
}

NoCommonPeriod::NoCommonPeriod()
    : InputError("excitation", 0, "",
                 "orders must repeat with the mesh (and the gears' manufacturing errors, every "
                 "revolution of the gears that carry them) within 100000 mesh cycles for a "
                 "periodic orbit (order * N / teeth integer)") {}

ContactState ContactStateOf(const SegmentTables& t, const Eigen::VectorXd& z) {
  const SegmentSystem& free = t.systems[0][static_cast<int>(ContactState::kFree)];
  if (free.gap_drive.dot(z) > 0.0) return ContactState::kDrive;
  if (free.gap_back.dot(z) < 0.0) return ContactState::kBack;
  return ContactState::kFree;
}

ExactCycleMap::ExactCycleMap(const SegmentTables& tables, long cycles, const SolverOptions& solver)
    : t_(tables),
      cycles_(cycles),
      stepper_(
          tables,
          [&] {
            SolverOptions o = solver;
            o.method = SolverMethod::kStepped;
            o.record_trajectory = false;
            return o;
          }(),
          Eigen::VectorXd::Zero(tables.m), ContactState::kFree, 0, 0) {}

CycleMapEvaluation ExactCycleMap::Evaluate(const Eigen::VectorXd& z0,
                                           const Eigen::MatrixXd& tangent) {
  CycleMapEvaluation out;
  stepper_.Restart(z0, ContactStateOf(t_, z0));
  out.tangent = tangent;
  if (tangent.cols() > 0) stepper_.AttachTangent(&out.tangent);
  out.ok = stepper_.Run(cycles_, true);
  stepper_.AttachTangent(nullptr);
  const SolverSummary& s = stepper_.summary();
  out.message = s.message;
  out.z = stepper_.state();
  Eigen::Map<Eigen::MatrixXd> as_matrix(out.z.data(), out.z.size(), 1);
  RemoveFreeRotation(t_, as_matrix);
  out.state = stepper_.contact();
  out.drive_impacts = s.drive_impacts;
  out.back_impacts = s.back_impacts;
  out.separations = s.separations;
  out.grazing = s.grazing;
  out.min_event_rate = s.min_event_rate;
  out.separated_s = stepper_.SeparatedTime();
  return out;
}

void PeriodicOrbitOptions::Validate() const {
  if (period < 1) {
    throw InputError("PeriodicOrbitOptions.period", 0, std::to_string(period), "must be >= 1");
  }
  if (max_iterations < 1) {
    throw InputError("PeriodicOrbitOptions.max_iterations", 0, std::to_string(max_iterations),
                     "must be >= 1");
  }
  if (!(tolerance > 0.0)) {
    throw InputError("PeriodicOrbitOptions.tolerance", 0, std::to_string(tolerance), "must be > 0");
  }
  solver.Validate();
}

const char* StabilityBoundaryName(StabilityBoundary b) {
  switch (b) {
    case StabilityBoundary::kFold:
      return "fold";
    case StabilityBoundary::kFlip:
      return "flip";
    case StabilityBoundary::kNeimarkSacker:
      return "neimark-sacker";
    case StabilityBoundary::kGrazing:
      return "grazing";
  }
  return "unknown";
}

const char* PeriodicOrbitInfoName(PeriodicOrbit::Info info) {
  switch (info) {
    case PeriodicOrbit::Info::kConverged:
      return "converged";
    case PeriodicOrbit::Info::kNoConvergence:
      return "no_convergence";
    case PeriodicOrbit::Info::kSolverFailed:
      return "solver_failed";
    case PeriodicOrbit::Info::kSingularJacobian:
      return "singular_jacobian";
  }
  return "unknown";
}

namespace {

// Orthonormal basis of the quotient range(L) in the elastic block [x; x'], block diagonal:
// diag(Qp, Qp) with Qp spanning the complement of r~ in R^n (Q = I without a free rotation).
Eigen::MatrixXd QuotientBasis(const SegmentTables& t) {
  const int n = t.n;
  if (t.recenter_row.norm() == 0.0) return Eigen::MatrixXd::Identity(2 * n, 2 * n);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(t.recenter_row.transpose());
  const Eigen::MatrixXd full = qr.householderQ() * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd Qp = full.rightCols(n - 1);
  Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(2 * n, 2 * (n - 1));
  Q.topLeftCorner(n, n - 1) = Qp;
  Q.bottomRightCorner(n, n - 1) = Qp;
  return Q;
}

struct Shot {
  CycleMapEvaluation map;
  Eigen::VectorXd F;   // Q^T (L Pi(y) - y)
  Eigen::MatrixXd Jq;  // Q^T L J Q
  double residual = 0.0;
};

}  // namespace

PeriodicOrbit FindPeriodicOrbit(const SegmentTables& t, const Eigen::VectorXd& guess,
                                const PeriodicOrbitOptions& options) {
  options.Validate();
  PeriodicOrbit out;
  const int n = t.n, e = 2 * n;
  out.period_cycles = options.period * BasePeriodCycles(t);
  out.period_s = static_cast<double>(out.period_cycles) * t.mesh_period;
  const double omega_f = 2.0 * std::numbers::pi / ForcingPeriod(t);
  const Eigen::MatrixXd Q = QuotientBasis(t);
  const Eigen::Index q = Q.cols();
  Eigen::MatrixXd tangent0 = Eigen::MatrixXd::Zero(t.m, q);
  tangent0.topRows(e) = Q;
  Eigen::VectorXd weight = Eigen::VectorXd::Ones(e);
  weight.tail(n).setConstant(1.0 / omega_f);
  ExactCycleMap map(t, out.period_cycles, options.solver);

  Eigen::VectorXd z = Eigen::VectorXd::Zero(t.m);
  z[2 * n] = 1.0;
  auto shoot = [&](const Eigen::VectorXd& a) {
    Shot s;
    z.head(e) = Q * a;
    s.map = map.Evaluate(z, tangent0);
    s.F = Q.transpose() * (s.map.z.head(e) - z.head(e));
    s.Jq = Q.transpose() * s.map.tangent.topRows(e);
    const double size = weight.cwiseProduct(z.head(e)).norm();
    s.residual = weight.cwiseProduct(Q * s.F).norm() / std::max(size, 1e-300);
    return s;
  };

  Eigen::VectorXd a = Q.transpose() * ElasticPart(t, guess);
  Shot shot = shoot(a);
  for (out.iterations = 0;; ++out.iterations) {
    if (!shot.map.ok) {
      out.info = PeriodicOrbit::Info::kSolverFailed;
      out.message = shot.map.message;
      return out;
    }
    if (shot.residual <= options.tolerance) {
      out.info = PeriodicOrbit::Info::kConverged;
      break;
    }
    if (out.iterations >= options.max_iterations) break;
    const Eigen::MatrixXd B = shot.Jq - Eigen::MatrixXd::Identity(q, q);
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(B);
    if (!lu.isInvertible()) {
      out.info = PeriodicOrbit::Info::kSingularJacobian;
      break;
    }
    const Eigen::VectorXd step = lu.solve(-shot.F);
    // Damped Newton: the map is only piecewise smooth (the event sequence can change between
    // iterates), so a full step is taken only when it lowers the residual.
    bool accepted = false;
    for (double theta = 1.0; theta >= 1.0 / 4096.0; theta *= 0.5) {
      Shot trial = shoot(a + theta * step);
      if (trial.map.ok && trial.residual < shot.residual) {
        a += theta * step;
        shot = std::move(trial);
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
  }
  out.residual = shot.residual;
  out.z = Eigen::VectorXd::Zero(t.m);
  out.z.head(e) = Q * a;
  out.z[2 * n] = 1.0;
  out.state = ContactStateOf(t, out.z);
  out.drive_impacts = shot.map.drive_impacts;
  out.back_impacts = shot.map.back_impacts;
  out.separation_fraction = shot.map.separated_s / out.period_s;
  // Multipliers (also reported for a non-converged last iterate, for diagnosis).
  out.monodromy = shot.Jq;
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(shot.Jq, false);
  for (Eigen::Index i = 0; i < q; ++i) out.multipliers.push_back(eig.eigenvalues()[i]);
  std::sort(out.multipliers.begin(), out.multipliers.end(),
            [](const auto& x, const auto& y) { return std::abs(x) > std::abs(y); });
  out.spectral_radius = out.multipliers.empty() ? 0.0 : std::abs(out.multipliers.front());
  out.stable = out.spectral_radius < 1.0;
  out.boundary_distance = std::numeric_limits<double>::infinity();
  for (const std::complex<double>& mu : out.multipliers) {
    const double distance = std::abs(1.0 - std::abs(mu));
    if (distance >= out.boundary_distance) continue;
    out.boundary_distance = distance;
    if (std::abs(mu.imag()) > 1e-9 * std::max(1.0, std::abs(mu))) {
      out.nearest_boundary = StabilityBoundary::kNeimarkSacker;
    } else {
      out.nearest_boundary = mu.real() > 0.0 ? StabilityBoundary::kFold : StabilityBoundary::kFlip;
    }
  }
  out.grazing_margin = shot.map.min_event_rate / (t.half_backlash * omega_f);
  if (out.grazing_margin < out.boundary_distance) {
    out.nearest_boundary = StabilityBoundary::kGrazing;
    out.boundary_distance = out.grazing_margin;
  }
  const std::string period = "period-" + std::to_string(options.period) + " orbit";
  if (out.info == PeriodicOrbit::Info::kConverged) {
    out.message = period + " converged in " + std::to_string(out.iterations) +
                  " Newton iterations; " + (out.stable ? "stable" : "unstable") +
                  ", nearest boundary " + StabilityBoundaryName(out.nearest_boundary);
  } else if (out.info == PeriodicOrbit::Info::kSingularJacobian) {
    out.message = "no " + period +
                  " found: the shooting Jacobian J - I is singular (a multiplier "
                  "at +1: a fold or the neutral direction)";
  } else {
    out.message = "no " + period + " found from this guess: Newton stopped after " +
                  Count(out.iterations, "iteration", "iterations") + " at scaled residual " +
                  std::to_string(out.residual);
  }
  return out;
}

}  // namespace gearnvh
