#include "gearnvh/solver/reference_integrator.h"

#include <algorithm>
#include <chrono>
#include <memory>

#include "cvode_bdf.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/quadrature.h"

namespace gearnvh {

void ReferenceOptions::Validate() const {
  if (cycles < 1)
    throw InputError("ReferenceOptions.cycles", 0, std::to_string(cycles), "must be >= 1");
  if (!(rtol > 0.0 && rtol <= 1e-3)) {
    throw InputError("ReferenceOptions.rtol", 0, std::to_string(rtol), "must be in (0, 1e-3]");
  }
  if (!(atol_position > 0.0) || !(atol_velocity > 0.0)) {
    throw InputError("ReferenceOptions.atol_position", 0, "", "absolute tolerances must be > 0");
  }
  if (max_events < 1)
    throw InputError("ReferenceOptions.max_events", 0, std::to_string(max_events), "must be >= 1");
  if (samples_per_cycle < 1) {
    throw InputError("ReferenceOptions.samples_per_cycle", 0, std::to_string(samples_per_cycle),
                     "must be >= 1");
  }
}

namespace {

// The engine orders enter as the continuous s(t) (SegmentTables::Excitation), not through the
// solver's exosystem: their states in z stay put and act nowhere, so the reference integrates the
// same inputs independently of how the solver carries them.
struct Problem {
  const SegmentTables* t = nullptr;
  const SegmentSystem* sys = nullptr;
  ContactState state = ContactState::kFree;
  int first_order = 0, order_end = 0;  // the orders' slots [first_order, order_end)
  bool OrderSlot(long i) const { return i >= first_order && i < order_end; }
};

int Rhs(sunrealtype time, N_Vector y, N_Vector ydot, void* data) {
  const Problem& p = *static_cast<Problem*>(data);
  const long m = NV_LENGTH_S(y);
  const int n = p.t->n;
  Eigen::Map<const Eigen::VectorXd> z(NV_DATA_S(y), m);
  Eigen::Map<Eigen::VectorXd> dz(NV_DATA_S(ydot), m);
  dz.noalias() = p.sys->A * z;
  if (p.order_end == p.first_order) return 0;
  for (int slot = p.first_order; slot < p.order_end; ++slot) {
    dz.segment(n, n) -= p.sys->A.col(slot).segment(n, n) * z[slot];
    dz[slot] = 0.0;
  }
  // Every order's sine state has the one forcing column M^-1 d.
  dz.segment(n, n) += p.sys->A.col(p.first_order).segment(n, n) * p.t->Excitation(time);
  return 0;
}

int Jac(sunrealtype, N_Vector, N_Vector, SUNMatrix J, void* data, N_Vector, N_Vector, N_Vector) {
  const Problem& p = *static_cast<Problem*>(data);
  const long m = SM_ROWS_D(J);
  for (long c = 0; c < m; ++c) {
    for (long r = 0; r < m; ++r)
      SM_ELEMENT_D(J, r, c) = p.OrderSlot(r) || p.OrderSlot(c) ? 0.0 : p.sys->A(r, c);
  }
  return 0;
}

// Walls of the current state as root functions (the same sign convention as the exact solver).
int Roots(sunrealtype, N_Vector y, sunrealtype* g, void* data) {
  const Problem& p = *static_cast<Problem*>(data);
  Eigen::Map<const Eigen::VectorXd> z(NV_DATA_S(y), NV_LENGTH_S(y));
  const double gd = p.sys->gap_drive.dot(z), gb = p.sys->gap_back.dot(z);
  switch (p.state) {
    case ContactState::kFree:
      g[0] = gd;
      g[1] = gb;
      break;
    case ContactState::kDrive:
      g[0] = gd;
      g[1] = 1.0;
      break;
    case ContactState::kBack:
      g[0] = 1.0;
      g[1] = gb;
      break;
  }
  return 0;
}

// The outputs of the exact recorder at one time, from the state itself.
TrajectorySample Sample(const SegmentTables& t, const SegmentSystem& sys, ContactState state,
                        double time, const Eigen::Ref<const Eigen::VectorXd>& z) {
  TrajectorySample s;
  s.time = time;
  s.te = t.te_row.dot(z);
  s.te_rate = t.te_rate_row.dot(z);
  if (state == ContactState::kDrive) {
    s.mesh_force =
        sys.mesh_stiffness * sys.gap_drive.dot(z) + t.mesh_damping * sys.gap_drive_rate.dot(z);
  } else if (state == ContactState::kBack) {
    s.mesh_force =
        -(sys.mesh_stiffness * sys.gap_back.dot(z) + t.mesh_damping * sys.gap_back_rate.dot(z));
  }
  s.pinion_speed = t.pinion_rate_row.dot(z);
  s.wheel_speed = t.wheel_rate_row.dot(z);
  s.wheel_acceleration = sys.wheel_acceleration_row.dot(z);
  s.state = state;
  return s;
}

// Dense output of CVODE's steps: uniform samples, and statistics by 8-point Gauss-Legendre on
// every step (the interpolant is a polynomial of degree <= 5 there, so y and y^2 integrate
// exactly) with extrema from 16 points per step refined by a parabola.
class DenseOutput {
 public:
  DenseOutput(const SegmentTables& t, int samples_per_cycle, long cycles, N_Vector like,
              std::vector<TrajectorySample>* samples)
      : t_(t),
        step_(t.mesh_period / samples_per_cycle),
        last_sample_(cycles * samples_per_cycle),
        samples_(samples),
        rule_(MakeGaussLegendre(8)) {
    dky_ = N_VClone(like);
  }
  ~DenseOutput() { N_VDestroy(dky_); }
  DenseOutput(const DenseOutput&) = delete;
  DenseOutput& operator=(const DenseOutput&) = delete;

  // [a, b] inside CVODE's last step, in `state` with generator `sys`.
  void Interval(void* cvode, const SegmentSystem& sys, ContactState state, double a, double b) {
    if (!(b > a)) return;
    auto at = [&](double time) {
      CVodeGetDky(cvode, time, 0, dky_);
      return Sample(t_, sys, state, time,
                    Eigen::Map<const Eigen::VectorXd>(NV_DATA_S(dky_), NV_LENGTH_S(dky_)));
    };
    // Uniform samples in [a, b) (b within rounding belongs to the next interval).
    for (double time = static_cast<double>(next_sample_) * step_;
         next_sample_ < last_sample_ && time < b - 1e-9 * step_;
         time = static_cast<double>(++next_sample_) * step_) {
      samples_->push_back(at(std::max(time, a)));
    }
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (size_t q = 0; q < rule_.nodes.size(); ++q) {
      const TrajectorySample s = at(mid + half * rule_.nodes[q]);
      const double w = half * rule_.weights[q];
      Accumulate(stats_.te, s.te, w);
      Accumulate(stats_.mesh_force, s.mesh_force, w);
      Accumulate(stats_.wheel_acceleration, s.wheel_acceleration, w);
    }
    constexpr int kPoints = 16;
    TrajectorySample grid[kPoints + 1];
    for (int i = 0; i <= kPoints; ++i) grid[i] = at(a + (b - a) * i / kPoints);
    Extrema(grid, kPoints, &TrajectorySample::te, stats_.te, true);
    if (state != ContactState::kFree) {
      Extrema(grid, kPoints, &TrajectorySample::mesh_force, stats_.mesh_force, false);
    } else {
      stats_.mesh_force.max = std::max(stats_.mesh_force.max, 0.0);
    }
    stats_.duration += b - a;
  }
  const TrajectoryStatistics& statistics() const { return stats_; }

 private:
  static void Accumulate(OutputStatistics& st, double value, double weight) {
    if (!st.has_offset) st.offset = value, st.has_offset = true;
    st.integral += weight * (value - st.offset);
    st.square_integral += weight * (value - st.offset) * (value - st.offset);
  }
  static void Extrema(const TrajectorySample* grid, int n, double TrajectorySample::*field,
                      OutputStatistics& st, bool with_min) {
    for (int sign : {1, -1}) {
      if (sign < 0 && !with_min) break;
      int best = 0;
      for (int i = 1; i <= n; ++i) {
        if (sign * (grid[i].*field) > sign * (grid[best].*field)) best = i;
      }
      double value = grid[best].*field, when = grid[best].time;
      if (best > 0 && best < n) {
        // The parabola through the best point and its neighbours.
        const double ya = sign * (grid[best - 1].*field), yb = sign * (grid[best].*field),
                     yc = sign * (grid[best + 1].*field);
        const double curvature = ya - 2 * yb + yc;
        if (curvature < 0.0) value = sign * (yb - 0.125 * (ya - yc) * (ya - yc) / curvature);
      }
      if (sign > 0 && value > st.max) st.max = value, st.time_of_max = when;
      if (sign < 0 && value < st.min) st.min = value, st.time_of_min = when;
    }
  }

  const SegmentTables& t_;
  double step_;
  long next_sample_ = 0, last_sample_;
  std::vector<TrajectorySample>* samples_;
  GaussLegendreRule rule_;
  N_Vector dky_;
  TrajectoryStatistics stats_;
};

}  // namespace

ReferenceResult SimulateReference(const SegmentTables& t, const Eigen::VectorXd& z0,
                                  ContactState state0, const ReferenceOptions& options) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  ReferenceResult result;
  const long m = t.m;
  Problem problem;
  problem.t = &t;
  problem.first_order = t.input_slot(0);
  problem.order_end = t.input_slot(t.error_input());
  problem.state = state0;
  problem.sys = &t.systems[0][static_cast<int>(state0)];
  const CvodeBdf cvode(z0, {t.n, options.rtol, options.atol_position, options.atol_velocity, Rhs,
                            Jac, Roots, 2, &problem});
  void* mem = cvode.mem();
  N_Vector y = cvode.y();
  int roots_found[2];

  double time = 0.0;
  long events = 0;
  DenseOutput dense(t, options.samples_per_cycle, options.cycles, y, &result.trajectory.samples);
  for (long c = 0; c < options.cycles && result.status == ReferenceStatus::kSuccess; ++c) {
    for (int j = 0; j < t.segments(); ++j) {
      const double seg_start = c * t.mesh_period + t.boundaries[j];
      const double seg_end = seg_start + t.SegmentLength(j);
      t.SetInputs(c, j, Eigen::Map<Eigen::VectorXd>(NV_DATA_S(y), m));
      problem.sys = &t.systems[j][static_cast<int>(problem.state)];
      {
        // The unloaded error e_j (part of the gap rows) can jump at a segment boundary and leave
        // the state outside its wall: switch at once, as the exact solver does (CVODE only sees
        // sign changes after its initial point).
        Eigen::Map<const Eigen::VectorXd> z(NV_DATA_S(y), m);
        const double gd = problem.sys->gap_drive.dot(z), gb = problem.sys->gap_back.dot(z);
        ContactState to = problem.state;
        if (problem.state == ContactState::kFree && gd > 0.0)
          to = ContactState::kDrive;
        else if (problem.state == ContactState::kFree && gb < 0.0)
          to = ContactState::kBack;
        else if (problem.state == ContactState::kDrive && gd < 0.0)
          to = ContactState::kFree;
        else if (problem.state == ContactState::kBack && gb > 0.0)
          to = ContactState::kFree;
        if (to != problem.state) {
          const double rate = (to == ContactState::kDrive || problem.state == ContactState::kDrive)
                                  ? problem.sys->gap_drive_rate.dot(z)
                                  : problem.sys->gap_back_rate.dot(z);
          result.trajectory.events.push_back({time, problem.state, to, rate});
          problem.state = to;
          problem.sys = &t.systems[j][static_cast<int>(to)];
        }
      }
      result.steps += cvode.StepsSoFar();  // CVodeReInit resets CVODE's counter
      CVodeReInit(mem, time, y);
      CVodeSetStopTime(mem, seg_end);
      while (time < seg_end && result.status == ReferenceStatus::kSuccess) {
        ThrowIfCancelled(options.cancel);
        double reached = time;
        const int flag = CVode(mem, seg_end, y, &reached, CV_ONE_STEP);
        if (flag < 0) {
          result.status = ReferenceStatus::kSolverFailure;
          result.message = std::string("CVODE failed: ") + CVodeGetReturnFlagName(flag) + " (" +
                           cvode.last_message() + ")";
          break;
        }
        // [time, reached] lies inside CVODE's last step: its interpolant gives the dense output.
        dense.Interval(mem, *problem.sys, problem.state, time, reached);
        time = reached;
        if (flag != CV_ROOT_RETURN) continue;
        CVodeGetRootInfo(mem, roots_found);
        const ContactState from = problem.state;
        ContactState to = from;
        // Only crossings in the triggering direction switch the state.
        if (from == ContactState::kFree && roots_found[0] == 1)
          to = ContactState::kDrive;
        else if (from == ContactState::kFree && roots_found[1] == -1)
          to = ContactState::kBack;
        else if (from == ContactState::kDrive && roots_found[0] == -1)
          to = ContactState::kFree;
        else if (from == ContactState::kBack && roots_found[1] == 1)
          to = ContactState::kFree;
        if (to == from) continue;
        Eigen::Map<const Eigen::VectorXd> z(NV_DATA_S(y), m);
        const SegmentSystem& sys = *problem.sys;
        const double rate = (to == ContactState::kDrive || from == ContactState::kDrive)
                                ? sys.gap_drive_rate.dot(z)
                                : sys.gap_back_rate.dot(z);
        result.trajectory.events.push_back({time, from, to, rate});
        problem.state = to;
        problem.sys = &t.systems[j][static_cast<int>(to)];
        result.steps += cvode.StepsSoFar();
        CVodeReInit(mem, time, y);
        if (++events > options.max_events) {
          result.status = ReferenceStatus::kTooManyEvents;
          result.message = "too many contact events";
        }
      }
      if (result.status != ReferenceStatus::kSuccess) break;
    }
  }
  result.trajectory.statistics = dense.statistics();
  result.steps += cvode.StepsSoFar();
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace gearnvh
