// Periodic orbits of a gear train by Newton shooting on the exact train flow, with Floquet
// multipliers (docs/gear-trains.md, "Simulating a train").
//
// Period T = p T_c, T_c the train's common period (every mesh and every excitation order back in
// phase; TrainTables::common_period). The map P: z(0) -> z(T) is an exact train run from t = 0;
// its Jacobian J comes from the tangent columns (train_tangents.h: exact pieces, a saltation per
// gap event). The free rotation U = [[r, 0], [0, r]] is neutral (multiplier 1 and its Jordan
// partner) and changes no gap or force, so the shooting runs on the quotient: Pi = I - U U^T W
// (W = diag(M, M)) projects off U (with each fixed shaft's standing rotation, also neutral:
// TrainTables::standing_rotations; a viscous drag damps r's speed, and U then keeps r's angle
// only: TrainTables::NeutralBasis), Q (2n x (2n - neutral), orthonormal) spans
// {y : U^T W y = 0}, a complement (invariant, J Q = Q C, when U holds r's velocity; with r's angle
// only, Pi J Q is the quotient's map). With y = y_0 + Q a:
//   F(a) = Q^T Pi (P(y) - y),   C = Q^T Pi J Q,   a <- a - theta (C - I)^-1 F(a),
// theta halved (at most 10 times) until the scaled residual decreases. Converged when
// |D Pi (P(y) - y)| <= tolerance |D y|, D = diag(1 on angles, 1 / omega_f on speeds), omega_f =
// 2 pi / T_f (the forcing period). The start states of every run are those the previous run ended
// in; a state found outside a wall at t = 0 is switched by the stepper. The Floquet multipliers
// are the eigenvalues of C at the orbit; stable when every |mu| < 1.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "gearnvh/solver/train_stepper.h"

namespace gearnvh {

struct TrainOrbitOptions {
  int periods = 1;           // p, the orbit's period in common periods; >= 1
  int max_iterations = 30;   // Newton iterations; >= 1
  double tolerance = 1e-10;  // scaled residual; > 0
  TrainStepperOptions stepper;
  void Validate() const;  // throws InputError naming the field
};

struct TrainOrbit {
  enum class Info { kConverged, kNotConverged, kNoCommonPeriod, kSolverFailed };
  Info info = Info::kNotConverged;
  Eigen::VectorXd z;                 // the orbit's state at t = 0 (free rotation removed)
  std::vector<ContactState> states;  // its contact states at t = 0
  double period = 0.0;               // T, s
  int iterations = 0;
  double residual = 0.0;         // scaled, as the tolerance
  Eigen::VectorXcd multipliers;  // on the quotient, 2n - neutral, by decreasing modulus
  bool stable = false;           // every |mu| < 1
  long events_per_period = 0;    // contact events of the last run over one orbit period
  std::string stop_reason;       // kSolverFailed: why the shot stopped (TrainStepperMessage)
};
const char* TrainOrbitInfoName(TrainOrbit::Info info);

TrainOrbit FindTrainPeriodicOrbit(const TrainTables& tables, const Eigen::VectorXd& z0,
                                  const std::vector<ContactState>& states0,
                                  const TrainOrbitOptions& options);

}  // namespace gearnvh
