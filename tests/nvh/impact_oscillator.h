// A one-degree-of-freedom backlash (impact) oscillator written straight into solver tables:
//   m x'' = F_j                          |x| <= b (free)
//   m x'' = F_j - k (x - b) - c x'        x > b  (drive wall)
//   m x'' = F_j - k (x + b) - c x'        x < -b (back wall)
// with a piecewise-constant force F_j per segment of one cycle (period T). No free rotation, so the
// quotient is the whole state. Test helper.
#pragma once

#include <numbers>
#include <vector>

#include "gearnvh/solver/segment_tables.h"

namespace gearnvh::testing {

struct ImpactOscillator {
  double mass = 1.0, stiffness = 1.0, damping = 0.0, half_backlash = 1.0;
  std::vector<double> boundaries;  // segment boundaries from 0 to T
  std::vector<double> forces;      // F_j, one per segment
};

inline SegmentTables BuildOscillatorTables(const ImpactOscillator& o) {
  SegmentTables t;
  t.n = 1;
  t.m = 4;
  t.mesh_period = o.boundaries.back();
  t.pinion_speed = 2.0 * std::numbers::pi / t.mesh_period;  // one "tooth": the period is one cycle
  t.boundaries = o.boundaries;
  t.half_backlash = o.half_backlash;
  t.excitation_inertia = o.mass;
  t.mesh_damping = o.damping;
  const double b = o.half_backlash;
  auto row = [](double a, double bb, double c, double d) {
    Eigen::RowVectorXd r(4);
    r << a, bb, c, d;
    return r;
  };
  t.te_row = row(1, 0, 0, 0);
  t.te_rate_row = row(0, 1, 0, 0);
  t.pinion_rate_row = row(0, 1, 0, 0);
  t.wheel_rate_row = row(0, 0, 0, 0);
  t.rigid_rotation = Eigen::VectorXd::Zero(1);
  t.recenter_row = Eigen::RowVectorXd::Zero(1);
  const double omega = std::sqrt(o.stiffness / o.mass);
  for (size_t j = 0; j + 1 < o.boundaries.size(); ++j) {
    const double h = o.boundaries[j + 1] - o.boundaries[j];
    int substeps = 1;
    while (omega * h / substeps > 0.5) substeps *= 2;
    t.substeps.push_back(substeps);
    std::array<SegmentSystem, 3> systems;
    const double f = o.forces[j] / o.mass;
    const double k = o.stiffness / o.mass, c = o.damping / o.mass;
    for (int st = 0; st < 3; ++st) {
      SegmentSystem& s = systems[st];
      s.A = Eigen::MatrixXd::Zero(4, 4);
      s.A(0, 1) = 1.0;
      if (st == static_cast<int>(ContactState::kFree)) {
        s.A.row(1) = row(0, 0, f, 0);
      } else {
        const double wall = st == static_cast<int>(ContactState::kDrive) ? b : -b;
        s.A.row(1) = row(-k, -c, f + k * wall, 0);
        s.mesh_stiffness = o.stiffness;
      }
      s.full = BalancedExpm(s.A, h, 1, ReferenceFrequency(s.A, 1));
      s.substep = BalancedExpm(s.A, h / substeps, 1, ReferenceFrequency(s.A, 1));
      s.gap_drive = row(1, 0, -b, 0);
      s.gap_back = row(1, 0, b, 0);
      s.gap_drive_rate = s.gap_drive * s.A;
      s.gap_back_rate = s.gap_back * s.A;
      s.wheel_acceleration_row = s.A.row(1);
    }
    t.systems.push_back(systems);
  }
  return t;
}

}  // namespace gearnvh::testing
