// Periodic orbits of the exact gear dynamics by Newton shooting, with Floquet multipliers
// (docs/design.md §5).
//
// Base period T_0 = N_0 T_m: the smallest whole number of mesh cycles after which the mesh
// stiffness and every engine order repeat (N_0 k_i / z1 integer for every order k_i; N_0 = 1
// without excitation). A period-p orbit repeats after p T_0. The cycle map Pi: z(0) -> z(p T_0)
// is evaluated by the exact stepper; its Jacobian J (the monodromy) by the tangent dynamics
// (segment propagators, saltation matrices at state-triggered events, see ExactStepper::
// AttachTangent).
// The pair's free rotation r is neutral (multiplier 1, changes no gap or force): shooting runs on
// the quotient range(L) = {y : r~^T y_pos = 0, r~^T y_vel = 0}, with an orthonormal basis Q
// (2n x (2n - 2); Q = I when the model has no free rotation). With y = Q a:
//   F(a) = Q^T (L Pi(Q a) - Q a),   J_q = Q^T L J Q,   a <- a - theta (J_q - I)^-1 F(a)
// (theta halved until the scaled residual decreases). Converged when the scaled residual
// |D F| / |D y| <= tolerance, D = diag(1 on positions, 1 / omega_f on velocities), omega_f =
// 2 pi / T_f. The Floquet multipliers are the eigenvalues of J_q at the orbit.
// Stability and the nearest boundary: stable when every |mu| < 1. The multiplier closest to the
// unit circle names the boundary: fold (real, > 0), flip (real, < 0) or Neimark-Sacker (complex
// pair), at distance | 1 - |mu| |. Grazing: the smallest gap rate at a contact change on the orbit,
// scaled by b omega_f, is the grazing margin; when it is smaller than the multiplier distance the
// nearest boundary is grazing (there saltation matrices blow up and Newton is not trusted).
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <string>
#include <vector>

#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/exact_solver.h"

namespace gearnvh {

// Forcing with no common period of at most 100000 mesh cycles: an InputError at the library's
// name "excitation" with the rule; the app names where the user wrote the orders
// (operating.excitation).
class NoCommonPeriod : public InputError {
 public:
  NoCommonPeriod();
};

// N_0 above; throws NoCommonPeriod when the orders are not commensurate with the mesh within 1e-9
// (or N_0 would exceed 100000 mesh cycles).
long BasePeriodCycles(const SegmentTables& tables);

// The contact state the gap of z implies at segment 0 (drive if g+ > 0, back if g- < 0, else free).
ContactState ContactStateOf(const SegmentTables& tables, const Eigen::VectorXd& z);

// The exact map over `cycles` mesh cycles from a cycle start, with its monodromy on the columns
// of `tangent` (m x p; may be empty: no Jacobian).
struct CycleMapEvaluation {
  bool ok = false;
  std::string message;
  Eigen::VectorXd z;  // end state (free rotation removed: L z)
  ContactState state = ContactState::kFree;
  Eigen::MatrixXd tangent;  // L J times the given columns
  long drive_impacts = 0, back_impacts = 0, separations = 0, grazing = 0;
  double min_event_rate = 0.0;  // m/s; infinity without state-triggered events
  double separated_s = 0.0;
};
class ExactCycleMap {
 public:
  // Builds the stepper (and its V3 tables) once; every evaluation restarts it at time 0.
  ExactCycleMap(const SegmentTables& tables, long cycles, const SolverOptions& solver);
  CycleMapEvaluation Evaluate(const Eigen::VectorXd& z0, const Eigen::MatrixXd& tangent);
  long cycles() const { return cycles_; }

 private:
  const SegmentTables& t_;
  long cycles_;
  ExactStepper stepper_;
};

struct PeriodicOrbitOptions {
  int period = 1;            // multiples of the base period; >= 1
  int max_iterations = 40;   // Newton iterations; >= 1
  double tolerance = 1e-10;  // scaled residual; > 0
  SolverOptions solver;      // event method (method/cycles fields are ignored)
  void Validate() const;     // throws InputError naming the field
};

enum class StabilityBoundary { kFold, kFlip, kNeimarkSacker, kGrazing };
const char* StabilityBoundaryName(StabilityBoundary b);

struct PeriodicOrbit {
  enum class Info { kConverged, kNoConvergence, kSolverFailed, kSingularJacobian };
  Info info = Info::kNoConvergence;
  std::string message;
  Eigen::VectorXd z;  // state at the start of the period (time 0 mod p T_0)
  ContactState state = ContactState::kFree;
  int iterations = 0;
  double residual = 0.0;   // scaled, at the returned state
  long period_cycles = 0;  // mesh cycles per period (p N_0)
  double period_s = 0.0;
  Eigen::MatrixXd monodromy;  // J_q on the quotient basis (positions first, then velocities)
  std::vector<std::complex<double>> multipliers;  // its eigenvalues, by decreasing modulus
  double spectral_radius = 0.0;
  bool stable = false;
  StabilityBoundary nearest_boundary = StabilityBoundary::kFold;
  double boundary_distance = 0.0;  // | 1 - |mu| | of the multiplier closest to the unit circle
  double grazing_margin = 0.0;     // min |g'| / (b omega_f) at contact changes; inf without
  long drive_impacts = 0, back_impacts = 0;  // per period
  double separation_fraction = 0.0;
};
const char* PeriodicOrbitInfoName(PeriodicOrbit::Info info);

PeriodicOrbit FindPeriodicOrbit(const SegmentTables& tables, const Eigen::VectorXd& guess,
                                const PeriodicOrbitOptions& options);

}  // namespace gearnvh
