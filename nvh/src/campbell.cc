#include "gearnvh/nvh/campbell.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "gearnvh/model/input_error.h"

namespace gearnvh {

void CampbellOptions::Validate() const {
  if (modes < 1)
    throw InputError("CampbellOptions.modes", 0, std::to_string(modes), "must be >= 1");
  if (!(min_frequency_hz >= 0.0)) {
    throw InputError("CampbellOptions.min_frequency_hz", 0, std::to_string(min_frequency_hz),
                     "must be >= 0");
  }
}

std::vector<OrderLine> GearOrderLines(int pinion_teeth, int wheel_teeth) {
  std::vector<OrderLine> lines;
  for (int k = 1; k <= 3; ++k) {
    lines.push_back({std::to_string(k) + "x mesh", static_cast<double>(k * pinion_teeth)});
  }
  for (int k = 1; k <= 2; ++k) {
    lines.push_back({std::to_string(k) + "x pinion", static_cast<double>(k)});
    lines.push_back({std::to_string(k) + "x wheel",
                     static_cast<double>(k) * pinion_teeth / static_cast<double>(wheel_teeth)});
  }
  return lines;
}

namespace {

struct Mode {
  double frequency_hz;
  Eigen::VectorXcd shape;  // displacement part, normalised
};

// M^-1 K and M^-1 G, factorised once for the whole sweep.
struct FirstOrderBlocks {
  Eigen::MatrixXd stiffness, gyroscopic;
};

std::vector<Mode> Modes(const FirstOrderBlocks& blocks, double speed, double min_hz) {
  const Eigen::Index n = blocks.stiffness.rows();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = -blocks.stiffness;
  A.bottomRightCorner(n, n) = -speed * blocks.gyroscopic;
  Eigen::EigenSolver<Eigen::MatrixXd> eig(A, true);
  std::vector<Mode> modes;
  for (Eigen::Index i = 0; i < 2 * n; ++i) {
    const std::complex<double> lambda = eig.eigenvalues()[i];
    const double f = lambda.imag() / (2.0 * std::numbers::pi);
    if (lambda.imag() <= 0.0 || std::abs(lambda) / (2.0 * std::numbers::pi) < min_hz) continue;
    Eigen::VectorXcd shape = eig.eigenvectors().col(i).head(n);
    shape.normalize();
    modes.push_back({f, std::move(shape)});
  }
  std::sort(modes.begin(), modes.end(),
            [](const Mode& a, const Mode& b) { return a.frequency_hz < b.frequency_hz; });
  return modes;
}

double Mac(const Eigen::VectorXcd& a, const Eigen::VectorXcd& b) {
  const double num = std::norm(a.dot(b));  // a^H b
  return num / (a.squaredNorm() * b.squaredNorm());
}

}  // namespace

CampbellData ComputeCampbell(const LinearRotorModel& model, const std::vector<double>& speeds,
                             const std::vector<OrderLine>& orders, const CampbellOptions& options) {
  options.Validate();
  CampbellData data;
  data.speeds_rad_s = speeds;
  data.orders = orders;
  if (speeds.empty()) return data;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::LDLT<Eigen::MatrixXd> mass(model.M);
  const FirstOrderBlocks blocks{mass.solve(model.K), mass.solve(model.G)};
  std::vector<Eigen::VectorXcd> tracked;
  for (size_t s = 0; s < speeds.size(); ++s) {
    const std::vector<Mode> modes = Modes(blocks, speeds[s], options.min_frequency_hz);
    if (s == 0) {
      const int count = std::min<int>(options.modes, static_cast<int>(modes.size()));
      data.frequency_hz.assign(count, std::vector<double>(speeds.size(), nan));
      data.mac.assign(count, std::vector<double>(speeds.size(), nan));
      for (int k = 0; k < count; ++k) {
        tracked.push_back(modes[k].shape);
        data.frequency_hz[k][0] = modes[k].frequency_hz;
        data.mac[k][0] = 1.0;
      }
      continue;
    }
    // Greedy global assignment on the MAC matrix (tracks x candidates).
    const size_t tracks = tracked.size();
    std::vector<std::vector<double>> mac(tracks, std::vector<double>(modes.size()));
    for (size_t k = 0; k < tracks; ++k)
      for (size_t c = 0; c < modes.size(); ++c) mac[k][c] = Mac(tracked[k], modes[c].shape);
    std::vector<bool> track_done(tracks, false), cand_used(modes.size(), false);
    for (size_t round = 0; round < std::min(tracks, modes.size()); ++round) {
      double best = -1.0;
      size_t bk = 0, bc = 0;
      for (size_t k = 0; k < tracks; ++k) {
        if (track_done[k]) continue;
        for (size_t c = 0; c < modes.size(); ++c) {
          if (!cand_used[c] && mac[k][c] > best) best = mac[k][c], bk = k, bc = c;
        }
      }
      if (best < 0.0) break;
      track_done[bk] = cand_used[bc] = true;
      data.frequency_hz[bk][s] = modes[bc].frequency_hz;
      data.mac[bk][s] = best;
      tracked[bk] = modes[bc].shape;
    }
  }
  // Critical speeds: sign changes of f_mode(Omega) - order Omega / 2 pi.
  for (const OrderLine& line : orders) {
    for (size_t k = 0; k < data.frequency_hz.size(); ++k) {
      for (size_t s = 1; s < speeds.size(); ++s) {
        const double f0 = data.frequency_hz[k][s - 1], f1 = data.frequency_hz[k][s];
        if (std::isnan(f0) || std::isnan(f1)) continue;
        const double d0 = f0 - line.order * speeds[s - 1] / (2.0 * std::numbers::pi);
        const double d1 = f1 - line.order * speeds[s] / (2.0 * std::numbers::pi);
        if (d0 == 0.0 || (d0 > 0.0) == (d1 > 0.0)) continue;
        const double u = d0 / (d0 - d1);
        CriticalSpeed c;
        c.order = line.label;
        c.mode = static_cast<int>(k);
        c.speed_rad_s = speeds[s - 1] + u * (speeds[s] - speeds[s - 1]);
        c.speed_rpm = c.speed_rad_s * 60.0 / (2.0 * std::numbers::pi);
        c.frequency_hz = line.order * c.speed_rad_s / (2.0 * std::numbers::pi);
        data.critical_speeds.push_back(c);
      }
    }
  }
  std::sort(
      data.critical_speeds.begin(), data.critical_speeds.end(),
      [](const CriticalSpeed& a, const CriticalSpeed& b) { return a.speed_rad_s < b.speed_rad_s; });
  return data;
}

}  // namespace gearnvh
