#include "gearnvh/analysis/train_transient.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "gearnvh/solver/train_rate_bound.h"
#include "gearnvh/solver/train_stepper.h"

namespace gearnvh {
namespace {

// A damping ratio -Re lambda / |lambda| below this counts as undamped (a lateral mode damped only
// by the bearings' rounding, or a mesh without damping): 1e-3 is far below any driveline's or
// mesh's damping (a few % of critical) and far above rounding.
constexpr double kUndamped = 1e-3;

}  // namespace

std::optional<DecayingMode> SlowestDecayingMode(const TrainTables& t) {
  const int n = t.n;
  const TuplePencil p =
      AssembleTuplePencil(t, std::vector<int>(t.meshes.size(), 0), LoadedContactStates(t));
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -(t.inertia.cwiseInverse().asDiagonal() * p.K);
  a.bottomRightCorner(n, n) = -(t.inertia.cwiseInverse().asDiagonal() * p.C);
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(a, false);
  if (eig.info() != Eigen::Success) return std::nullopt;
  double largest = 0.0;
  for (const std::complex<double>& lambda : eig.eigenvalues())
    largest = std::max(largest, std::abs(lambda));
  std::optional<DecayingMode> slowest;
  for (const std::complex<double>& lambda : eig.eigenvalues()) {
    // Not a mode: the free and fixed rotations' zeros (their rounding, ~eps of the largest,
    // can be complex). Not oscillatory: a real eigenvalue (a damped rotation). Undamped: a
    // damping ratio below kUndamped, which no transient removes.
    if (std::abs(lambda) <= 1e-6 * largest || !(lambda.imag() > 1e-8 * std::abs(lambda)) ||
        !(-lambda.real() > kUndamped * std::abs(lambda)))
      continue;
    if (!slowest || -lambda.real() < slowest->decay_rate) {
      slowest = DecayingMode{lambda.imag() / (2.0 * std::numbers::pi), -lambda.real()};
    }
  }
  return slowest;
}

std::string TransientDecayWarning(const TrainTables& tables, double transient_s,
                                  long transient_cycles, const std::string& option) {
  const std::optional<DecayingMode> mode = SlowestDecayingMode(tables);
  if (!mode || mode->decay_rate * transient_s >= 3.0) return "";
  const double needed_s = 3.0 / mode->decay_rate;
  // Cycles of the first mesh, which the transient counts.
  const auto needed_cycles = static_cast<long>(std::ceil(needed_s / tables.meshes.front().period));
  return fmt::format(
      "the transient ({:.3g} s, {} cycles) is shorter than three decay times of the train's "
      "slowest mode ({:.3g} Hz, 1/e in {:.3g} s, in drive contact): the record may still hold "
      "the start from the static state (more than 5 % of it); {} {} or more lets it die out",
      transient_s, transient_cycles, mode->frequency_hz, 1.0 / mode->decay_rate, option,
      needed_cycles);
}

}  // namespace gearnvh
