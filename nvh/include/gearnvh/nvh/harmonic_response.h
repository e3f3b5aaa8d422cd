// Steady-state response of a gear train's mean-stiffness model to harmonic inputs, the frequency
// domain of whine (docs/design.md §14). In the tier's coordinates q, with
// every mesh i on its loaded flank at its mean stiffness k_i, its damping c_i and its approach
// delta_i = v_i^T q:
//   M q'' + (C + W G + sum_i c_i v_i v_i^T) q' + (K + sum_i k_i v_i v_i^T) q
//     = sum_i k_i v_i e_i(t) + sum_b a_b tau_b(t),
// W the input shaft's speed (G per unit input speed), e_i the mesh's displacement input (its loaded
// static transmission error and the gears' errors), tau_b a torque on body b (a_b its running
// angle's row). One line e_i = Re(E_i e^{i w t}), tau_b = Re(T_b e^{i w t}) gives q = Re(Q e^{i w
// t}) with
//   Z(w) Q = sum_i k_i v_i E_i + sum_b a_b T_b,   Z(w) = K + sum k_i v_i v_i^T - w^2 M
//                                                + i w (C + W G + sum c_i v_i v_i^T),
// the mesh force F_i = (k_i + i w c_i) v_i^T Q - k_i E_i (the time-domain solver's mesh force: its
// damping acts on the approach, its error input through the stiffness), the mesh's TE t_i^T Q
// (t_i the drive flank's vector, the solver's TE whichever flank is loaded), a bearing's force on
// the housing (K_b + i w C_b) Q and a body's speed i w a_b^T Q (a_b: its running angle). Z is
// nonsingular for w > 0 (the train's free rotation has mass), so every line is solved directly.
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <vector>

namespace gearnvh {

struct HarmonicModel {
  Eigen::MatrixXd M, C, G, K;  // the structure without the meshes; G per unit input speed
  std::vector<Eigen::VectorXd> mesh_vectors;         // v_i of the loaded flank
  std::vector<Eigen::VectorXd> te_vectors;           // t_i, the drive flank's (one per mesh)
  std::vector<double> mesh_stiffness, mesh_damping;  // k_i (N/m), c_i (N s/m)
  // Per bearing: rows x, y, z of its force on the housing per unit q (stiffness and damping).
  std::vector<Eigen::MatrixXd> bearing_stiffness, bearing_damping;
  Eigen::MatrixXd body_angles;  // rows: each body's running angle a_b^T
  int dof() const { return static_cast<int>(M.rows()); }
  // Sizes agree (throws std::invalid_argument naming the member).
  void CheckSizes() const;
};

struct HarmonicInput {
  std::vector<std::complex<double>> mesh;         // E_i, m (empty: none)
  std::vector<std::complex<double>> body_torque;  // T_b, N m, per body (empty: none)
};

struct HarmonicResponse {
  std::vector<std::complex<double>> te, mesh_force;  // per mesh, m and N
  std::vector<Eigen::Vector3cd> bearing_force;       // per bearing, N
  std::vector<std::complex<double>> body_speed;      // per body, rad/s
};

// Solves lines at one input speed. Not thread-safe; one per thread.
class HarmonicSolver {
 public:
  explicit HarmonicSolver(const HarmonicModel& model);  // keeps a reference
  // The input shaft's speed W (rad/s) of the lines that follow.
  void SetSpeed(double input_speed);
  // The response at w > 0 rad/s to `input`.
  void Solve(double w, const HarmonicInput& input, HarmonicResponse& out);

 private:
  const HarmonicModel& model_;
  // With the meshes: the stiffness, the damping at rest (once) and at the speed (SetSpeed).
  Eigen::MatrixXd stiffness_, still_damping_, damping_;
  Eigen::MatrixXcd z_;
  Eigen::VectorXcd rhs_, q_;
  Eigen::PartialPivLU<Eigen::MatrixXcd> lu_;
};

}  // namespace gearnvh
