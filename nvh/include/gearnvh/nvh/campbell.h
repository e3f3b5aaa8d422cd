// Campbell data of a linearised rotor/gear model (DESIGN.md §6).
//
// At pinion speed Omega the free vibration of M q'' + Omega G q' + K q = 0 (gyroscopic, undamped)
// has eigenvalues lambda = i omega of the first-order form [[0, I], [-M^-1 K, -Omega M^-1 G]].
// Natural frequencies f = omega / 2 pi (lambda with Im > 0, |lambda| >= min_frequency_hz; rigid
// rotations excluded) are computed at every speed; modes are followed from speed to speed by the
// modal assurance criterion of the displacement part of the eigenvectors,
//   MAC(a, b) = |a^H b|^2 / ((a^H a)(b^H b)),
// with a greedy global assignment (the best remaining pair first), so two modes whose
// frequencies cross keep their identities (frequency sorting would swap them). Order lines are
// f = order * Omega / 2 pi; a critical speed is where a tracked mode and an order line cross
// (linear interpolation between neighbouring speeds).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace gearnvh {

struct LinearRotorModel {
  Eigen::MatrixXd M, K, G;  // G per unit pinion speed (gyroscopic force Omega G q')
};

struct OrderLine {
  std::string label;   // e.g. "1x mesh", "2x pinion", "1x wheel"
  double order = 0.0;  // multiples of the pinion speed
};

struct CampbellOptions {
  int modes = 8;                  // tracked modes (the lowest at the first speed); >= 1
  double min_frequency_hz = 1.0;  // below this an eigenvalue is a rigid rotation; >= 0
  void Validate() const;
};

struct CriticalSpeed {
  std::string order;
  int mode = 0;
  double speed_rad_s = 0.0, speed_rpm = 0.0, frequency_hz = 0.0;
};

struct CampbellData {
  std::vector<double> speeds_rad_s;
  // frequency_hz[mode][speed] and the MAC of each match with the previous speed (1 at the first).
  std::vector<std::vector<double>> frequency_hz, mac;
  std::vector<OrderLine> orders;
  std::vector<CriticalSpeed> critical_speeds;
};

// Mesh orders 1..3 (z1 per pinion revolution) and shaft orders 1..2 of both shafts.
std::vector<OrderLine> GearOrderLines(int pinion_teeth, int wheel_teeth);

// Speeds in rad/s (ascending, > 0 recommended: at rest forward and backward whirl coincide).
CampbellData ComputeCampbell(const LinearRotorModel& model, const std::vector<double>& speeds,
                             const std::vector<OrderLine>& orders, const CampbellOptions& options);

}  // namespace gearnvh
