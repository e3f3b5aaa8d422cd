#include "gearnvh/solver/segment_tables.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <unsupported/Eigen/MatrixFunctions>

#include "gearnvh/solver/solver_options.h"

namespace gearnvh {

const char* ContactStateName(ContactState s) {
  switch (s) {
    case ContactState::kBack:
      return "back";
    case ContactState::kFree:
      return "free";
    case ContactState::kDrive:
      return "drive";
  }
  return "?";
}

double OrdersValue(const std::vector<ExcitationOrder>& orders, double speed, double t) {
  double sum = 0.0;
  for (const ExcitationOrder& e : orders)
    sum += e.amplitude * std::sin(e.order * speed * t + e.phase);
  return sum;
}

double HighestOrderFrequency(const std::vector<ExcitationOrder>& orders, double speed) {
  double highest = 0.0;
  for (const ExcitationOrder& e : orders) highest = std::max(highest, std::abs(e.order * speed));
  return highest;
}

void SetOrderStates(const std::vector<ExcitationOrder>& orders, double speed, double t,
                    int first_slot, Eigen::Ref<Eigen::VectorXd> z) {
  for (size_t k = 0; k < orders.size(); ++k) {
    const ExcitationOrder& e = orders[k];
    const double angle = e.order * speed * t + e.phase;
    const int slot = first_slot + 2 * static_cast<int>(k);
    z[slot] = e.amplitude * std::sin(angle);
    z[slot + 1] = e.amplitude * std::cos(angle);
  }
}

void AddOrderColumns(const std::vector<ExcitationOrder>& orders, double speed, int n,
                     int first_slot, const Eigen::MatrixXd& acceleration,
                     Eigen::Ref<Eigen::MatrixXd> A) {
  for (size_t k = 0; k < orders.size(); ++k) {
    const int slot = first_slot + 2 * static_cast<int>(k);
    const double w = orders[k].order * speed;
    A.block(n, slot, n, 1) = acceleration.col(static_cast<Eigen::Index>(k));
    A(slot, slot + 1) = w;
    A(slot + 1, slot) = -w;
  }
}

double SegmentTables::Excitation(double t) const {
  return OrdersValue(excitation, pinion_speed, t);
}

double SegmentTables::HighestExcitationFrequency() const {
  return HighestOrderFrequency(excitation, pinion_speed);
}

void SegmentTables::PrepareExcitationPhases() {
  const size_t count = static_cast<size_t>(segments()), orders = excitation.size();
  excitation_start_cos.assign(count * orders, 0.0);
  excitation_start_sin.assign(count * orders, 0.0);
  for (size_t k = 0; k < orders; ++k) {
    const ExcitationOrder& e = excitation[k];
    for (size_t j = 0; j < count; ++j) {
      const double psi = e.order * pinion_speed * boundaries[j];
      excitation_start_cos[k * count + j] = e.amplitude * std::cos(psi);
      excitation_start_sin[k * count + j] = e.amplitude * std::sin(psi);
    }
  }
}

SegmentTables::CyclePhase SegmentTables::MakeCyclePhase() const {
  CyclePhase phase;
  phase.sin.resize(excitation.size());
  phase.cos.resize(excitation.size());
  phase.excitation.resize(static_cast<size_t>(segments()) * 2 * excitation.size());
  if (has_error_input()) phase.error.resize(static_cast<size_t>(segments()));
  return phase;
}

// A phase from MakeCyclePhase is sized: the resizes below allocate nothing in a stepping loop.
void SegmentTables::PrepareCycleInputs(long cycle, CyclePhase& phase) const {
  const size_t orders = excitation.size(), states = 2 * orders;
  const size_t count = static_cast<size_t>(segments());
  phase.cycle = cycle;
  phase.excitation.resize(count * states);
  if (has_error_input()) {
    phase.error.resize(count);
    for (size_t j = 0; j < count; ++j) {
      const int segment = static_cast<int>(j);
      const double start = static_cast<double>(cycle) * mesh_period + boundaries[segment];
      phase.error[j] = errors.SegmentMean(cycle, segment, start, SegmentLength(segment));
    }
  }
  const size_t entries = orders * count;
  if (excitation_start_cos.size() != entries || excitation_start_sin.size() != entries) {
    // Tables assembled by hand: no start phases, a sine and a cosine per order and segment.
    for (size_t j = 0; j < count; ++j) {
      const double start = static_cast<double>(cycle) * mesh_period + boundaries[j];
      SetOrderStates(excitation, pinion_speed, start, 0,
                     Eigen::Map<Eigen::VectorXd>(phase.excitation.data() + j * states,
                                                 static_cast<Eigen::Index>(states)));
    }
    return;
  }
  phase.sin.resize(orders);
  phase.cos.resize(orders);
  const double cycle_start = static_cast<double>(cycle) * mesh_period;
  for (size_t k = 0; k < orders; ++k) {
    const ExcitationOrder& e = excitation[k];
    sincos(e.order * pinion_speed * cycle_start + e.phase, &phase.sin[k], &phase.cos[k]);
  }
  for (size_t k = 0; k < orders; ++k) {
    const double s = phase.sin[k], c = phase.cos[k];
    const double* start_cos = excitation_start_cos.data() + k * count;
    const double* start_sin = excitation_start_sin.data() + k * count;
    double* q = phase.excitation.data() + 2 * k;
    for (size_t j = 0; j < count; ++j) {
      q[j * states] = s * start_cos[j] + c * start_sin[j];
      q[j * states + 1] = c * start_cos[j] - s * start_sin[j];
    }
  }
}

void SegmentTables::SetInputs(long cycle, int segment, Eigen::Ref<Eigen::VectorXd> z) const {
  const double start = static_cast<double>(cycle) * mesh_period + boundaries[segment];
  SetOrderStates(excitation, pinion_speed, start, input_slot(0), z);
  if (has_error_input())
    z[input_slot(error_input())] =
        errors.SegmentMean(cycle, segment, start, SegmentLength(segment));
}

double SegmentTables::InputBound(int input) const {
  if (input == error_input()) return errors.bound();
  return std::abs(excitation[static_cast<size_t>(input / 2)].amplitude);
}

long SegmentTables::CommonPeriodCycles(long max_cycles) const {
  const double z1 = std::round(2.0 * std::numbers::pi / (pinion_speed * mesh_period));
  const long step = errors.period_cycles();
  for (long n = step; n <= max_cycles; n += step) {
    bool whole = true;
    for (const ExcitationOrder& o : excitation) {
      const double periods = static_cast<double>(n) * o.order / z1;
      if (std::abs(periods - std::round(periods)) > 1e-9 * std::max(1.0, periods)) {
        whole = false;
        break;
      }
    }
    if (whole) return n;
  }
  return 0;
}

double ReferenceFrequency(const Eigen::MatrixXd& A, int n) {
  const Eigen::MatrixXd stiffness = -A.block(n, 0, n, n);
  return std::max(1.0, std::sqrt(stiffness.eigenvalues().cwiseAbs().maxCoeff()));
}

double SegmentTables::SegmentReferenceFrequency(int j) const {
  if (reference_frequency.size() == systems.size()) return reference_frequency[j];
  double w_ref = 1.0;
  for (const auto& sys : systems[j]) w_ref = std::max(w_ref, ReferenceFrequency(sys.A, n));
  return w_ref;
}

Eigen::MatrixXd BalancedExpm(const Eigen::MatrixXd& A, double t, int n, double w_ref) {
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(A.rows());
  scale.segment(n, n).setConstant(1.0 / w_ref);
  const Eigen::MatrixXd balanced = scale.asDiagonal() * A * scale.cwiseInverse().asDiagonal();
  Eigen::MatrixXd expm =
      scale.cwiseInverse().asDiagonal() * (balanced * t).exp() * scale.asDiagonal();
  // A zero row of A (the constant slot, an error input) is a unit row of exp(A t) exactly; Pade and
  // squaring return it to rounding only (1 - 3e-14 on a tier-3 segment), and the constant slot
  // is neutral: a product of segments, a cycle map (1 - 8e-13 per cycle), would scale the load
  // by a drift that grows with every cycle.
  for (int i = 0; i < A.rows(); ++i) {
    if ((A.row(i).array() == 0.0).all()) {
      expm.row(i).setZero();
      expm(i, i) = 1.0;
    }
  }
  return expm;
}

Eigen::VectorXd ElasticPart(const SegmentTables& t, const Eigen::VectorXd& z) {
  Eigen::VectorXd e = z.head(2 * t.n);
  e.head(t.n) -= t.rigid_rotation * t.recenter_row.dot(z.head(t.n));
  e.tail(t.n) -= t.rigid_rotation * t.recenter_row.dot(z.segment(t.n, t.n));
  return e;
}

Eigen::MatrixXd FreeRotationProjector(const SegmentTables& t) {
  Eigen::MatrixXd L = Eigen::MatrixXd::Identity(t.m, t.m);
  RemoveFreeRotation(t, L);
  return L;
}

void RemoveFreeRotation(const SegmentTables& t, Eigen::Ref<Eigen::MatrixXd> V) {
  // V.x <- V.x - r (r^T M V.x), and the same for V.x'.
  const int n = t.n;
  for (Eigen::Index c = 0; c < V.cols(); ++c) {
    const double position = t.recenter_row.dot(V.col(c).head(n));
    const double velocity = t.recenter_row.dot(V.col(c).segment(n, n));
    V.col(c).head(n) -= position * t.rigid_rotation;
    V.col(c).segment(n, n) -= velocity * t.rigid_rotation;
  }
}

size_t SegmentTables::TableBytes() const {
  size_t per_system = 3 * static_cast<size_t>(m) * m + 4 * static_cast<size_t>(m);
  return systems.size() * 3 * per_system * sizeof(double);
}

std::vector<ExcitationOrder> DistinctOrders(const std::vector<ExcitationOrder>& orders) {
  std::vector<ExcitationOrder> out;
  std::vector<std::complex<double>> phasors;
  for (const ExcitationOrder& e : orders) {
    const std::complex<double> phasor = std::polar(e.amplitude, e.phase);
    const auto same = std::find_if(out.begin(), out.end(), [&](const ExcitationOrder& o) {
      return std::abs(o.order - e.order) <= 1e-9 * o.order && o.kind == e.kind && o.on == e.on;
    });
    if (same == out.end()) {
      out.push_back(e);
      phasors.push_back(phasor);
      continue;
    }
    std::complex<double>& sum = phasors[static_cast<size_t>(same - out.begin())];
    sum += phasor;
    same->amplitude = std::abs(sum);
    same->phase = std::arg(sum);
  }
  return out;
}

int InputCount(const ComponentModel& model, const std::vector<ExcitationOrder>& orders) {
  return 2 * static_cast<int>(DistinctOrders(orders).size()) + (model.errors.active() ? 1 : 0);
}

int StateDimension(const ComponentModel& model, const ReducedModel& reduced,
                   const std::vector<ExcitationOrder>& orders) {
  return 2 * reduced.dof + 1 + InputCount(model, orders);
}

SegmentTables BuildSegmentTables(const ComponentModel& model, const ReducedModel& r,
                                 const GearboxSpec& spec, const std::atomic<bool>* cancel) {
  SegmentTables t;
  t.n = r.dof;
  // The model's errors at the speed run here (a sweep runs one model at every speed).
  t.errors = model.errors.AtSpeed(spec.operating.speed);
  t.inputs = InputCount(model, spec.operating.excitation);
  t.m = StateDimension(model, r, spec.operating.excitation);
  t.pinion_speed = spec.operating.speed;
  t.mesh_period = 2.0 * std::numbers::pi / (spec.pinion.teeth * spec.operating.speed);
  t.excitation = DistinctOrders(spec.operating.excitation);
  t.half_backlash = model.half_backlash;
  t.displacement_limit = 2.0 * model.half_backlash + WholeDepth(model.geometry);
  t.excitation_inertia = model.pinion_side_inertia;
  const int n = t.n, m = t.m;
  t.mesh_damping = model.mesh_damping;
  t.te_row = Eigen::RowVectorXd::Zero(m);
  t.te_row.head(n) = r.v_drive.transpose();
  t.te_rate_row = Eigen::RowVectorXd::Zero(m);
  t.te_rate_row.segment(n, n) = r.v_drive.transpose();
  t.pinion_rate_row = Eigen::RowVectorXd::Zero(m);
  t.pinion_rate_row.segment(n, n) = r.pinion_torsion.transpose();
  t.wheel_rate_row = Eigen::RowVectorXd::Zero(m);
  t.wheel_rate_row.segment(n, n) = -r.wheel_torsion.transpose();  // the wheel runs about -z
  const double b = model.half_backlash, mu = model.friction_coefficient, c = model.mesh_damping;
  const Eigen::LLT<Eigen::MatrixXd> mass(r.M);
  const Eigen::MatrixXd C0 = r.C + spec.operating.speed * r.G;
  const Eigen::VectorXd d = t.excitation_inertia * r.pinion_torsion;

  {
    // Free rotations of the structure: the generalized eigenvectors of (K, M) with zero eigenvalue;
    // the pair's rotation is their combination that opens no gap.
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(r.K, r.M);
    const Eigen::MatrixXd free = eig.eigenvectors().leftCols(2);
    const Eigen::RowVector2d g = r.v_drive.transpose() * free;
    Eigen::VectorXd rot = free * Eigen::Vector2d(g[1], -g[0]);
    const double norm = std::sqrt(rot.dot(r.M * rot));
    t.rigid_rotation = rot / norm;
    t.recenter_row = (r.M * t.rigid_rotation).transpose();
  }
  // Tooth friction exerts a mean torque on the pair's free rotation (r^T w != 0): the pinion's
  // drive torque must also supply the mean friction loss at the operating load, or the whole
  // drivetrain would slowly decelerate. Generalized rigid force in drive contact: r^T f - mu N r^T
  // w_j with N ~ F = T / r_b2, so the pinion gets Delta T1 = mu F <r^T w>_t / (r^T e_pinion) extra.
  Eigen::VectorXd static_force = r.static_force;
  {
    double mean_rw = 0.0;
    for (const auto& seg : model.segmentation.segments) {
      const Eigen::VectorXd w =
          r.FrictionVector(Flank::kDrive, seg.drive.friction_sigma, seg.drive.friction_arm_pinion,
                           seg.drive.friction_arm_wheel);
      mean_rw += (seg.tau_end - seg.tau_begin) * t.rigid_rotation.dot(w);
    }
    const double load = spec.WheelTorque() / model.geometry.wheel.base;
    const double lever = t.rigid_rotation.dot(r.pinion_torsion);
    t.friction_loss_torque = lever != 0.0 ? mu * load * mean_rw / lever : 0.0;
    static_force += t.friction_loss_torque * r.pinion_torsion;
  }
  const auto& segs = model.segmentation.segments;
  t.boundaries.reserve(segs.size() + 1);
  for (const auto& s : segs) t.boundaries.push_back(s.tau_begin * t.mesh_period);
  t.boundaries.push_back(t.mesh_period);
  t.systems.resize(segs.size());
  t.substeps.resize(segs.size());
  for (size_t j = 0; j < segs.size(); ++j) {
    ThrowIfCancelled(cancel);
    const MeshSegment& s = segs[j];
    const double h = t.SegmentLength(static_cast<int>(j));
    const double e = s.unloaded_error;
    for (ContactState state : {ContactState::kBack, ContactState::kFree, ContactState::kDrive}) {
      Eigen::MatrixXd K = r.K, C = C0;
      Eigen::VectorXd f = static_force;
      Eigen::VectorXd error_force = Eigen::VectorXd::Zero(n);  // force per metre of e_err
      if (state == ContactState::kDrive) {
        const double k = s.drive.stiffness;
        const Eigen::VectorXd u =
            r.v_drive + mu * r.FrictionVector(Flank::kDrive, s.drive.friction_sigma,
                                              s.drive.friction_arm_pinion,
                                              s.drive.friction_arm_wheel);
        t.systems[j][static_cast<int>(state)].mesh_stiffness = k;
        K += k * u * r.v_drive.transpose();
        C += c * u * r.v_drive.transpose();
        f += k * (e + b) * u;
        error_force = k * u;
      } else if (state == ContactState::kBack) {
        const double k = s.back.stiffness;
        const Eigen::VectorXd u =
            r.v_back - mu * r.FrictionVector(Flank::kBack, s.back.friction_sigma,
                                             s.back.friction_arm_pinion, s.back.friction_arm_wheel);
        t.systems[j][static_cast<int>(state)].mesh_stiffness = k;
        K += k * u * r.v_back.transpose();
        C += c * u * r.v_back.transpose();
        f += k * (e - b) * u;
        error_force = k * u;
      }
      SegmentSystem& sys = t.systems[j][static_cast<int>(state)];
      sys.A = Eigen::MatrixXd::Zero(m, m);
      sys.A.block(0, n, n, n).setIdentity();
      sys.A.block(n, 0, n, n) = -mass.solve(K);
      sys.A.block(n, n, n, n) = -mass.solve(C);
      sys.A.block(n, 2 * n, n, 1) = mass.solve(f);
      AddOrderColumns(t.excitation, t.pinion_speed, n, t.input_slot(0),
                      mass.solve(d).replicate(1, static_cast<Eigen::Index>(t.excitation.size())),
                      sys.A);
      sys.gap_drive = Eigen::RowVectorXd::Zero(m);
      sys.gap_drive.head(n) = r.v_drive.transpose();
      sys.gap_drive[2 * n] = -(e + b);
      sys.gap_back = Eigen::RowVectorXd::Zero(m);
      sys.gap_back.head(n) = r.v_back.transpose();
      sys.gap_back[2 * n] = -e + b;
      if (t.has_error_input()) {
        const int slot = t.input_slot(t.error_input());
        sys.A.block(n, slot, n, 1) = mass.solve(error_force);
        sys.gap_drive[slot] = -1.0;
        sys.gap_back[slot] = -1.0;
      }
      sys.gap_drive_rate = sys.gap_drive * sys.A;
      sys.gap_back_rate = sys.gap_back * sys.A;
      sys.wheel_acceleration_row = t.wheel_rate_row * sys.A;
    }
    // One sub-step count per segment (the stiffest state decides), a power of two.
    // The Taylor series of exp(A tau) z converges like (rho tau)^k / k! with rho the spectral
    // radius of the dynamic block (the constant columns only enter the first power) or the
    // orders' frequencies (A is block triangular: its eigenvalues are both).
    double rho = t.HighestExcitationFrequency();
    for (const auto& sys : t.systems[j]) {
      const Eigen::MatrixXd dyn = sys.A.topLeftCorner(2 * n, 2 * n);
      rho = std::max(rho, dyn.eigenvalues().cwiseAbs().maxCoeff());
    }
    int substeps = 1;
    while (rho * h / substeps > 0.5) substeps *= 2;
    t.substeps[j] = substeps;
    // Balance before the Pade exponential: with velocities scaled by 1/w_ref the generator's blocks
    // are all O(w_ref) instead of O(w_ref^2) next to O(1); unbalanced, Eigen's expm loses up to
    // 1e-7 relative accuracy here, balanced it is at rounding (see the solver tests).
    const double w_ref = t.SegmentReferenceFrequency(static_cast<int>(j));
    t.reference_frequency.push_back(w_ref);
    for (auto& sys : t.systems[j]) {
      sys.full = BalancedExpm(sys.A, h, n, w_ref);
      sys.substep = BalancedExpm(sys.A, h / substeps, n, w_ref);
    }
  }
  t.PrepareExcitationPhases();
  return t;
}

OperatingPointModel BuildOperatingPointModel(const GearboxSpec& spec, Tier tier,
                                             const std::atomic<bool>* cancel) {
  OperatingPointModel op{BuildComponentModel(spec), {}, {}};
  op.reduced = ReduceModel(op.model, tier);
  op.tables = BuildSegmentTables(op.model, op.reduced, spec, cancel);
  return op;
}

}  // namespace gearnvh
