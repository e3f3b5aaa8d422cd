// Largest Lyapunov exponents of a gear train's exact dynamics (docs/design.md §11, §5).
//
// Benettin's method with QR re-orthonormalisation on the exact tangent dynamics of the train
// (solver/train_tangents.h: the pieces' exact flows, a saltation per gap event, the identity at
// grazing touches and time-triggered switches). k tangent columns start on generic directions;
// every `renormalise_cycles` cycles of the first mesh (period T_1)
//   V <- P V (P: the M-orthogonal projection off the free rotation, position and velocity),
//   V.e = Q R (Gram-Schmidt on the elastic rows [x; x'], Euclidean),  g_j = ln |R_jj|,  V.e <- Q
// after `alignment_cycles` unaveraged cycles; then lambda_j = sum g_j / T (1/s, T the averaged
// time), in descending order. The free rotation is neutral in every tuple (multiplier 1 and its
// Jordan partner, linear growth): its two zero exponents would hide every negative one, so it is
// projected out and the k exponents are those of the quotient (k <= 2n - 2, less 2 per fixed shaft,
// whose standing rotation is projected out too). A viscous drag damps the rotation's speed at
// sigma = r^T C r, often ~1e-3 1/s, which would hide the relative motion's exponents as the
// neutral pair would: it is projected out as well (not invariant then: the exponents are the
// relative motion's to second order in the drag's coupling; sigma is known in closed form).
// Reported per second, per cycle of the first mesh (lambda T_1) and per forcing cycle (lambda T_f,
// T_f = 2 pi / (order_1 Omega_in), the first engine order of the input; T_1 without excitation).
// Standard error per exponent: the run is cut into `blocks` equal blocks, the standard deviation
// of the block exponents over sqrt(blocks). Predictability horizon of the largest exponent:
// t_p = 52 ln 2 / lambda_1 (as the pair).
// In permanent contact the train is linear and T-periodic (T the common period): the exponents
// are the Floquet exponents ln |mu_j| / T of its monodromy matrix (for a constant generator, the
// real parts of its eigenvalues).
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"

namespace gearnvh {

struct TrainLyapunovOptions {
  int exponents = 1;            // k, the largest exponents wanted; 1 <= k <= 2n - neutral (checked)
  long transient_cycles = 200;  // cycles of the first mesh before the tangents start; >= 0
  long alignment_cycles = 50;   // cycles run renormalised before averaging; >= 0
  long cycles = 1000;           // cycles averaged; >= blocks * renormalise_cycles
  long renormalise_cycles = 1;  // cycles between re-orthonormalisations; >= 1
  int blocks = 8;               // blocks for the standard errors; >= 2
  TrainStepperOptions stepper;
  // Sees every piece, sample and event after the transient (alignment and averaged cycles), so
  // one run gives the exponents and the statistics (atlases). Not owned; may be null. Its start
  // time should be the transient's end.
  TrainRecorder* recorder = nullptr;
  // Called after every interval with the fraction of the run done, in (0, 1]; may be empty.
  std::function<void(double)> progress;
  void Validate() const;  // throws InputError naming the field
};

struct TrainLyapunovSummary {
  enum class Info { kSuccess, kSolverFailed };
  Info info = Info::kSuccess;
  std::string message;
  std::vector<double> exponents;          // lambda_j, 1/s, descending
  std::vector<double> per_mesh_cycle;     // lambda_j T_1
  std::vector<double> per_forcing_cycle;  // lambda_j T_f
  std::vector<double> standard_errors;    // 1/s
  double mesh_period = 0.0;               // T_1, s
  double forcing_period = 0.0;            // T_f, s
  double averaged_s = 0.0;                // T, s
  // t_p = 52 ln 2 / lambda_1 (s) and in forcing cycles; infinity when lambda_1 <= 0.
  double predictability_horizon_s = 0.0;
  double predictability_horizon_cycles = 0.0;
  long saltations = 0;      // saltation matrices applied to the tangents
  TrainStepperSummary run;  // the whole run (transient, alignment, averaged)
};
const char* TrainLyapunovInfoName(TrainLyapunovSummary::Info info);

// T_f of the train: 2 pi / (order_1 Omega_in), or the first mesh's period without excitation.
double TrainForcingPeriod(const TrainTables& tables);

TrainLyapunovSummary EstimateTrainLyapunov(const TrainTables& tables, const Eigen::VectorXd& z0,
                                           const std::vector<ContactState>& states0,
                                           const TrainLyapunovOptions& options);

}  // namespace gearnvh
