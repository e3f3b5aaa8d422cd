// Piecewise-LTI model of the gear pair and its exact propagators (docs/design.md §4.1–4.2).
//
// Augmented state z = [x; x'; 1; q; u] (dimension m = 2n + 1 + p): x reduced coordinates, q the
// exosystem of the K engine orders s(t) = sum_k a_k sin(w_k t + phi_k), w_k = order_k Omega1 (per
// order q_k = a_k [sin, cos](w_k t + phi_k), q_k' = w_k [[0, 1], [-1, 0]] q_k, s = sum_k q_k,sin:
// carried exactly, DESIGN §14), and, when the gears carry runout or pitch errors, u = e_err, the
// mesh's manufacturing transmission error (m, model/manufacturing_errors.h) held at its mean over
// the current segment; p = 2K (+ 1 with errors) input slots, set at each segment's start. Per
// segment j and contact state sigma in {drive (+), free (0), back (-)}:
//   z' = A_{j,sigma} z,
//   A = [[0, I, 0, 0], [-M^-1 K_s, -M^-1 C_s, M^-1 f_s, M^-1 B_s], [0, 0, 0, W]]
//   drive: K_s = K + k (v + mu w) v^T,  C_s = C + Omega1 G + c (v + mu w) v^T,
//          f_s = f + k (e + b)(v + mu w),  B_s = [d, k (v + mu w)]
//   free:  K_s = K,  C_s = C + Omega1 G,  f_s = f,  B_s = [d, 0]
//   back:  K_s = K + k (v' - mu w') v'^T,  C_s = C + Omega1 G + c (v' - mu w') v'^T,
//          f_s = f + k (e - b)(v' - mu w'),  B_s = [d, k (v' - mu w')]
// (B_s's first column d on each order's sine state, zero on its cosine; W = diag(w_k [[0, 1],
// [-1, 0]]) turns the orders' states, the error slot has a zero row)
// with k the segment's mean mesh stiffness, c the mesh damping, e the
// segment's unloaded error, b = backlash / 2, w/w' the segment's friction vectors, f the static
// load and d = J1 e_pinion the excitation direction (torque J1 s on the pinion). Gaps (affine in
// z): g+ = v^T x - e - e_err - b (drive contact while g+ > 0),
//     g- = v'^T x - e - e_err + b (back contact while g- < 0).
// Tables: for every (j, sigma) the full-segment propagator expm(A h_j), the sub-step propagator
// expm(A h_j / N_j) with N_j a power of two such that rho(A) h_j / N_j <= 1/2 (rho the spectral
// radius of the dynamic block), and A itself (for the
// Taylor polynomial used inside a sub-step when an event is located).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <atomic>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/manufacturing_errors.h"
#include "gearnvh/reduction/reduced_model.h"

namespace gearnvh {

enum class ContactState : int { kBack = 0, kFree = 1, kDrive = 2 };
const char* ContactStateName(ContactState s);

struct SegmentSystem {
  Eigen::MatrixXd A;                                 // generator, m x m
  Eigen::MatrixXd full;                              // expm(A h)
  Eigen::MatrixXd substep;                           // expm(A h / substeps)
  Eigen::RowVectorXd gap_drive, gap_back;            // g+ = gap_drive z, g- = gap_back z
  Eigen::RowVectorXd gap_drive_rate, gap_back_rate;  // rows of c A: d/dt of the gaps
  double mesh_stiffness = 0.0;  // k of this state and segment, 0 when free
  Eigen::RowVectorXd wheel_acceleration_row;  // running angular acceleration of the wheel: row . z
};

struct SegmentTables {
  int n = 0;                       // reduced DOF
  int inputs = 0;  // p: 2 per engine order, plus the manufacturing error when active
  int m = 0;                       // augmented dimension 2n + 1 + p
  double mesh_period = 0.0;        // s
  double pinion_speed = 0.0;       // rad/s
  std::vector<double> boundaries;  // segment start times within a cycle, s (size S + 1)
  std::vector<int> substeps;       // N_j
  // Per segment: the largest ReferenceFrequency of its three generators (>= 1), the balancing of
  // its exponentials and decompositions (BuildSegmentTables; empty in tables assembled by hand).
  std::vector<double> reference_frequency;
  std::vector<std::array<SegmentSystem, 3>> systems;  // [segment][state]
  std::vector<ExcitationOrder> excitation;            // orders, amplitudes (rad/s^2), phases
  double half_backlash = 0.0;
  // Bound on |g+| and |g-| (m): beyond the teeth's whole depth past either wall the gears would
  // have passed through each other or out of mesh, so the model no longer describes them. 0: none.
  double displacement_limit = 0.0;
  double excitation_inertia = 0.0;                     // J1
  double mesh_damping = 0.0;                           // c, N s/m
  Eigen::RowVectorXd te_row;                           // dynamic TE delta = v^T x as a row on z
  Eigen::RowVectorXd te_rate_row;                      // v^T x'
  Eigen::RowVectorXd pinion_rate_row, wheel_rate_row;  // running angular velocities (perturbation)
  // The pair's free rotation r (K r = 0, v^T r = v'^T r = 0) and the M-weighted row that measures
  // it: shifting x by a multiple of r changes no force and no gap, so the solver removes the drift
  // x <- x - r (recenter_row x) once per cycle to keep the gap's rounding floor small.
  Eigen::VectorXd rigid_rotation;
  // Extra pinion drive torque supplying the mean tooth-friction loss at the operating load, N m.
  double friction_loss_torque = 0.0;
  Eigen::RowVectorXd recenter_row;

  MeshErrorExcitation errors;  // runout and pitch errors (inactive: no error input)

  int constant_slot() const { return 2 * n; }
  int input_slot(int input) const { return 2 * n + 1 + input; }
  // The input index of order k's sine state (its cosine follows), and of the error input.
  static int ExcitationInput(int order) { return 2 * order; }
  int error_input() const { return 2 * static_cast<int>(excitation.size()); }
  bool has_error_input() const { return inputs > error_input(); }
  // Sets the input slots of z at the start of segment `segment` of mesh cycle `cycle` (cycles
  // counted from t = 0): the orders' states there (exact) and the error's mean over the segment.
  // Allocation-free.
  void SetInputs(long cycle, int segment, Eigen::Ref<Eigen::VectorXd> z) const;
  // An upper bound of |u_input| over all segments.
  double InputBound(int input) const;
  // The smallest whole number of mesh cycles after which the model repeats: the engine orders
  // (n order / z1 an integer for every order) and the gears' manufacturing errors (whole
  // revolutions of the gears that carry them); 0 when none is found up to max_cycles.
  long CommonPeriodCycles(long max_cycles) const;
  int segments() const { return static_cast<int>(systems.size()); }
  double SegmentLength(int j) const { return boundaries[j + 1] - boundaries[j]; }
  // reference_frequency[j], or computed from the systems when the tables have none.
  double SegmentReferenceFrequency(int j) const;
  // The excitation s(t), rad/s^2, and its highest frequency max_k w_k (0 without orders), rad/s.
  double Excitation(double t) const;
  double HighestExcitationFrequency() const;
  // Per order and segment (order-major: entry k * segments() + j), a_k cos(psi_kj) and
  // a_k sin(psi_kj), psi_kj = w_k t_j the phase of the segment's start within a cycle. With
  // theta_k(c) = w_k c T + phi_k the orders' states at the start of segment j of cycle c are
  //   a_k sin(theta + psi) = sin(theta) start_cos_kj + cos(theta) start_sin_kj,
  //   a_k cos(theta + psi) = cos(theta) start_cos_kj - sin(theta) start_sin_kj,
  // so a stepper that keeps theta's sine and cosine per cycle (CyclePhase) needs no trigonometry
  // per segment. BuildSegmentTables fills them; tables assembled by hand without them evaluate
  // the states directly.
  std::vector<double> excitation_start_cos, excitation_start_sin;
  void PrepareExcitationPhases();
  // sin and cos of every order's phase theta_k(cycle) at the start of `cycle` (cycle -1: none yet)
  // and the excitation input of every segment of that cycle (excitation[j]).
  struct CyclePhase {
    long cycle = -1;
    std::vector<double> sin, cos;
    // The orders' states at every segment's start (segment-major: 2K entries per segment).
    std::vector<double> excitation;
    std::vector<double> error;  // the error input of every segment (has_error_input())
  };
  // SetInputs with the cycle's inputs kept in `phase` (filled by PrepareCycleInputs when the cycle
  // changes): one sincos per order and cycle instead of a sine per order and segment, and per
  // segment one load. Equal to SetInputs to rounding (sin(theta + psi) = sin theta cos psi +
  // cos theta sin psi). Inline: the carried V3 path calls it on every segment.
  void SetInputs(long cycle, int segment, Eigen::Ref<Eigen::VectorXd> z, CyclePhase& phase) const {
    PrepareCycle(cycle, phase);
    SetPreparedInputs(segment, z, phase);
  }
  // SetInputs in two steps for a loop over the segments of one cycle: the cycle's inputs, then
  // per segment the slots (no call in the loop).
  void PrepareCycle(long cycle, CyclePhase& phase) const {
    const size_t states = static_cast<size_t>(error_input());
    if (phase.cycle != cycle || phase.excitation.size() != states * systems.size() ||
        (has_error_input() && phase.error.size() != systems.size())) [[unlikely]]
      PrepareCycleInputs(cycle, phase);
  }
  void SetPreparedInputs(int segment, Eigen::Ref<Eigen::VectorXd> z,
                         const CyclePhase& phase) const {
    const int states = error_input();
    const double* q = phase.excitation.data() + static_cast<size_t>(segment) * states;
    for (int i = 0; i < states; ++i) z[input_slot(i)] = q[i];
    if (has_error_input()) z[input_slot(error_input())] = phase.error[static_cast<size_t>(segment)];
  }
  // Fills `phase` for `cycle`: the phases and, per segment, the orders' states at its start by the
  // angle sums above; tables assembled by hand without the start phases evaluate them directly.
  // Allocates only when the segment count changes (the first cycle).
  void PrepareCycleInputs(long cycle, CyclePhase& phase) const;
  // A CyclePhase sized for these tables (PrepareCycleInputs then allocates nothing).
  CyclePhase MakeCyclePhase() const;
  size_t TableBytes() const;
};

// expm(A t) for an augmented generator with n reduced DOF, by Pade on the balanced generator
// (velocities scaled by 1/w_ref, w_ref = sqrt of the largest |eigenvalue| of the stiffness block,
// at least 1): unbalanced, the generator's O(w^2) and O(1) blocks cost Eigen's expm up to 1e-7.
Eigen::MatrixXd BalancedExpm(const Eigen::MatrixXd& A, double t, int n, double w_ref);
// The w_ref above for one generator.
double ReferenceFrequency(const Eigen::MatrixXd& A, int n);

// The quotient projector L = I - [r;0][r~;0]^T - [0;r][0;r~]^T (m x m) that removes the pair's
// free rotation r (position and velocity) from an augmented state; r~ = recenter_row.
Eigen::MatrixXd FreeRotationProjector(const SegmentTables& tables);
// Applies L to the columns of V (m x p) in place, without allocation.
void RemoveFreeRotation(const SegmentTables& tables, Eigen::Ref<Eigen::MatrixXd> V);

// [x; x'] without the pair's free rotation (position and velocity): the part of the state that
// every gap and force depends on. Used to compare states that may differ only by that rotation.
Eigen::VectorXd ElasticPart(const SegmentTables& tables, const Eigen::VectorXd& z);

// Engine orders of a shaft turning at `speed` (rad/s), for the pair's and the train's tables: the
// excitation sum_k a_k sin(order_k speed t + phi_k) at time t (rad/s^2), its highest frequency
// (rad/s), and the exosystem's states a_k [sin, cos](order_k speed t + phi_k) written from
// z[first_slot] on (two per order).
double OrdersValue(const std::vector<ExcitationOrder>& orders, double speed, double t);
double HighestOrderFrequency(const std::vector<ExcitationOrder>& orders, double speed);
void SetOrderStates(const std::vector<ExcitationOrder>& orders, double speed, double t,
                    int first_slot, Eigen::Ref<Eigen::VectorXd> z);
// Adds the orders' exosystem to a generator with n coordinates: per order k, its sine state (slot
// first_slot + 2k) drives the accelerations through column k of `acceleration` (M^-1 d_k, per unit
// of its amplitude) and W_k = w_k [[0, 1], [-1, 0]] turns its two states.
void AddOrderColumns(const std::vector<ExcitationOrder>& orders, double speed, int n,
                     int first_slot, const Eigen::MatrixXd& acceleration,
                     Eigen::Ref<Eigen::MatrixXd> A);

// The orders with equal `order` (within 1e-9 relative), kind and shaft merged into one (sum_k a_k
// sin(theta + phi_k) = A sin(theta + Phi), A e^{i Phi} = sum_k a_k e^{i phi_k}), in their first
// order of appearance: two exosystems of one frequency would make every decomposition's eigenvalues
// +-i w double (ill-conditioned); a train's validation refuses one frequency on two shafts or
// kinds.
std::vector<ExcitationOrder> DistinctOrders(const std::vector<ExcitationOrder>& orders);

// Builds the tables for one operating point. `spec` gives speed, excitation, damping and friction.
// The inputs p the state carries: two states per engine order, plus the manufacturing error when
// a gear has runout or pitch errors.
int InputCount(const ComponentModel& model, const std::vector<ExcitationOrder>& orders);
// The one definition of a tier's state dimension, as the solver runs it: m = 2n + 1 + p
// (positions, velocities, the constant slot, the inputs). `check`, `simulate`, `tiers` and the
// reports print this number.
int StateDimension(const ComponentModel& model, const ReducedModel& reduced,
                   const std::vector<ExcitationOrder>& orders);

// `cancel` (SolverOptions::cancel) is polled per segment: RunCancelled once set.
SegmentTables BuildSegmentTables(const ComponentModel& model, const ReducedModel& reduced,
                                 const GearboxSpec& spec,
                                 const std::atomic<bool>* cancel = nullptr);

// One operating point's whole model chain, the way every analysis builds it: spec -> component
// model -> reduced model of `tier` -> segment tables.
struct OperatingPointModel {
  ComponentModel model;
  ReducedModel reduced;
  SegmentTables tables;
};
OperatingPointModel BuildOperatingPointModel(const GearboxSpec& spec, Tier tier,
                                             const std::atomic<bool>* cancel = nullptr);

}  // namespace gearnvh
