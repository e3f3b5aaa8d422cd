#include "gearnvh/solver/train_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <type_traits>

#include "cvode_bdf.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/train_stepper.h"

namespace gearnvh {

void TrainReferenceOptions::Validate() const {
  if (!(end_time > 0.0))
    throw InputError("TrainReferenceOptions.end_time", 0, std::to_string(end_time), "must be > 0");
  if (!(rtol > 0.0 && rtol <= 1e-3))
    throw InputError("TrainReferenceOptions.rtol", 0, std::to_string(rtol), "must be in (0, 1e-3]");
  if (!(atol_position > 0.0) || !(atol_velocity > 0.0)) {
    throw InputError("TrainReferenceOptions.atol_position", 0, "",
                     "absolute tolerances must be > 0");
  }
  if (max_events < 1) {
    throw InputError("TrainReferenceOptions.max_events", 0, std::to_string(max_events),
                     "must be >= 1");
  }
  if (!(sample_interval >= 0.0)) {
    throw InputError("TrainReferenceOptions.sample_interval", 0, std::to_string(sample_interval),
                     "must be >= 0");
  }
}

Eigen::MatrixXd AssembleTrainGenerator(const TrainTables& t, const std::vector<int>& segments,
                                       const std::vector<ContactState>& states) {
  const int n = t.n;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(t.m, t.m);
  for (int r = 0; r < n; ++r) {
    A(r, n + r) = 1.0;
    A(n + r, t.constant_slot()) = t.force[r] / t.inertia[r];
  }
  t.AddExcitationColumns(A);
  t.AddErrorColumns(segments, states, A);
  const Eigen::VectorXd inv_j = t.inertia.cwiseInverse();
  if (t.structural_stiffness.size() > 0)
    A.block(n, 0, n, n) -= inv_j.asDiagonal() * t.structural_stiffness;
  if (t.structural_damping.size() > 0)
    A.block(n, n, n, n) -= inv_j.asDiagonal() * t.structural_damping;
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    if (states[i] == ContactState::kFree) continue;
    const TrainMeshTable& mt = t.meshes[i];
    const size_t j = static_cast<size_t>(segments[i]);
    const bool drive = states[i] == ContactState::kDrive;
    const double k = drive ? mt.k_drive[j] : mt.k_back[j];
    const double wall = drive ? mt.error[j] + mt.half_backlash : mt.error[j] - mt.half_backlash;
    // Mesh torque on coordinate r: -u_r (k (v^T x - wall) + c v^T x'), v the flank's vector, u
    // its force direction (v + mu w or v_back - mu w with friction, else v).
    const Eigen::VectorXd& v = mt.Vector(drive);
    const Eigen::VectorXd& u = mt.ForceVector(segments[i], drive);
    for (int r = 0; r < n; ++r) {
      if (u[r] == 0.0) continue;
      for (int s = 0; s < n; ++s) {
        A(n + r, s) -= u[r] * k * v[s] / t.inertia[r];
        A(n + r, n + s) -= u[r] * mt.damping * v[s] / t.inertia[r];
      }
      A(n + r, t.constant_slot()) += u[r] * k * wall / t.inertia[r];
    }
  }
  return A;
}

namespace {

// Pieces shorter than this fraction of their grid segment are stepped over.
constexpr double kNegligiblePiece = 1e-12;

// Whether the piece [time, end] (h its grid segment's length) is stepped over: shorter than
// kNegligiblePiece h, or than CVODE can resolve at this absolute time (it refuses an interval under
// 2 u max(|t0|, |tout|) with CV_TOO_CLOSE, which late in a long run exceeds 1e-12 h).
bool NegligiblePiece(double time, double end, double h) {
  const double resolvable =
      4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(time), std::abs(end));
  return end - time <= std::max(kNegligiblePiece * h, resolvable);
}

struct Problem {
  const TrainTables* t = nullptr;
  // The tuple's generator without the orders' exosystem (their states stay put and act nowhere):
  // the orders enter as the continuous AddExcitationAcceleration(t) instead, independent of the
  // stepper's exosystem.
  Eigen::MatrixXd A;
  std::vector<int> segments;
  std::vector<ContactState> states;
  void Assemble() {
    A = AssembleTrainGenerator(*t, segments, states);
    const int first = t->ExcitationSlot(0), count = t->excitation_states();
    A.middleRows(first, count).setZero();
    A.middleCols(first, count).setZero();
  }
};

int TrainRhs(sunrealtype time, N_Vector y, N_Vector ydot, void* data) {
  const Problem& p = *static_cast<Problem*>(data);
  Eigen::Map<const Eigen::VectorXd> z(NV_DATA_S(y), NV_LENGTH_S(y));
  Eigen::Map<Eigen::VectorXd> dz(NV_DATA_S(ydot), NV_LENGTH_S(y));
  dz.noalias() = p.A * z;
  p.t->AddExcitationAcceleration(time, dz.segment(p.t->n, p.t->n));
  return 0;
}

int TrainJac(sunrealtype, N_Vector, N_Vector, SUNMatrix J, void* data, N_Vector, N_Vector,
             N_Vector) {
  const Problem& p = *static_cast<Problem*>(data);
  for (long c = 0; c < SM_COLUMNS_D(J); ++c)
    for (long r = 0; r < SM_ROWS_D(J); ++r) SM_ELEMENT_D(J, r, c) = p.A(r, c);
  return 0;
}

// Gaps of mesh i: g+ (index 2i) and g- (2i + 1).
double Gap(const Problem& p, size_t i, bool drive, const double* z) {
  const TrainMeshTable& mt = p.t->meshes[i];
  const Eigen::VectorXd& v = mt.Vector(drive);
  double delta = 0.0;
  for (int r = 0; r < p.t->n; ++r) delta += v[r] * z[r];
  const double e =
      mt.error[static_cast<size_t>(p.segments[i])] +
      p.t->ErrorInput(static_cast<int>(i), Eigen::Map<const Eigen::VectorXd>(z, p.t->m));
  return drive ? delta - e - mt.half_backlash : delta - e + mt.half_backlash;
}

int TrainRoots(sunrealtype, N_Vector y, sunrealtype* g, void* data) {
  const Problem& p = *static_cast<Problem*>(data);
  for (size_t i = 0; i < p.t->meshes.size(); ++i) {
    g[2 * i] = Gap(p, i, true, NV_DATA_S(y));
    g[2 * i + 1] = Gap(p, i, false, NV_DATA_S(y));
  }
  return 0;
}

// The state a mesh switches to when gap g+ (drive = true) or g- has value / crossing direction
// `sign` (> 0 rising), or its own state.
ContactState Triggered(ContactState s, bool drive, int sign) {
  if (s == ContactState::kFree && drive && sign > 0) return ContactState::kDrive;
  if (s == ContactState::kFree && !drive && sign < 0) return ContactState::kBack;
  if (s == ContactState::kDrive && drive && sign < 0) return ContactState::kFree;
  if (s == ContactState::kBack && !drive && sign > 0) return ContactState::kFree;
  return s;
}

}  // namespace

TrainReferenceResult SimulateTrainReference(const TrainTables& t, const Eigen::VectorXd& z0,
                                            const std::vector<ContactState>& states0,
                                            const TrainReferenceOptions& options) {
  options.Validate();
  TrainReferenceResult result;
  const long m = t.m;
  const size_t meshes = t.meshes.size();
  Problem p;
  p.t = &t;
  p.states = states0;
  TrainGrid grid(t);
  p.segments = grid.segments();
  p.Assemble();
  const CvodeBdf cvode(z0, {t.n, options.rtol, options.atol_position, options.atol_velocity,
                            TrainRhs, TrainJac, TrainRoots, static_cast<int>(2 * meshes), &p});
  void* mem = cvode.mem();
  N_Vector y = cvode.y();
  // Owned here (freed also when a cancellation unwinds the run).
  const std::unique_ptr<std::remove_pointer_t<N_Vector>, void (*)(N_Vector)> dky_owner(
      N_VNew_Serial(m, cvode.context()), N_VDestroy);
  N_Vector dky = dky_owner.get();
  std::vector<int> found(2 * meshes);
  std::vector<double> te_rows;
  long next_sample = 0;
  const auto emit_samples = [&](double a, double b) {
    if (options.sample_interval <= 0.0) return;
    for (double ts = next_sample * options.sample_interval;
         ts < b - 1e-12 * options.sample_interval && ts <= options.end_time;
         ts = ++next_sample * options.sample_interval) {
      CVodeGetDky(mem, std::max(ts, a), 0, dky);
      result.sample_times.push_back(ts);
      for (size_t i = 0; i < meshes; ++i)
        te_rows.push_back(
            t.meshes[i].v.dot(Eigen::Map<const Eigen::VectorXd>(NV_DATA_S(dky), t.n)));
    }
  };

  double time = 0.0;
  while (time < options.end_time && result.success) {
    const double seg_end = std::min(grid.end(), options.end_time);
    const double h = grid.end() - grid.start();
    t.SetInputs(grid.cycles(), grid.segments(), grid.start(), h,
                Eigen::Map<Eigen::VectorXd>(NV_DATA_S(y), t.m));
    p.segments = grid.segments();
    // Outside a wall at the boundary (e jumps): switch at once.
    for (size_t i = 0; i < meshes; ++i) {
      const double gd = Gap(p, i, true, NV_DATA_S(y)), gb = Gap(p, i, false, NV_DATA_S(y));
      ContactState to = p.states[i];
      if (to == ContactState::kFree && gd > 0.0)
        to = ContactState::kDrive;
      else if (to == ContactState::kFree && gb < 0.0)
        to = ContactState::kBack;
      else if (to == ContactState::kDrive && gd < 0.0)
        to = ContactState::kFree;
      else if (to == ContactState::kBack && gb > 0.0)
        to = ContactState::kFree;
      if (to != p.states[i]) {
        result.events.push_back({static_cast<int>(i), time, p.states[i], to});
        p.states[i] = to;
      }
    }
    p.Assemble();
    // A piece a few ulps long (the end time or another mesh's boundary within rounding of this
    // one): CVODE cannot start on it, and the motion over it is far below the reference's rtol.
    if (NegligiblePiece(time, seg_end, h)) time = seg_end;
    result.steps += cvode.StepsSoFar();  // CVodeReInit resets CVODE's counter
    CVodeReInit(mem, time, y);
    CVodeSetStopTime(mem, seg_end);
    while (time < seg_end && result.success) {
      ThrowIfCancelled(options.cancel);
      double reached = time;
      const int flag = CVode(mem, seg_end, y, &reached, CV_ONE_STEP);
      if (flag < 0) {
        result.success = false;
        result.message = std::string("CVODE failed: ") + CVodeGetReturnFlagName(flag) + " (" +
                         cvode.last_message() + ")";
        break;
      }
      emit_samples(time, reached);
      time = reached;
      if (flag != CV_ROOT_RETURN) continue;
      CVodeGetRootInfo(mem, found.data());
      bool changed = false;
      for (size_t i = 0; i < meshes; ++i) {
        for (bool drive : {true, false}) {
          const int dir = found[2 * i + (drive ? 0 : 1)];
          if (dir == 0) continue;
          const ContactState to = Triggered(p.states[i], drive, dir);
          if (to == p.states[i]) continue;
          result.events.push_back({static_cast<int>(i), time, p.states[i], to});
          p.states[i] = to;
          changed = true;
        }
      }
      if (!changed) continue;
      p.Assemble();
      result.steps += cvode.StepsSoFar();
      CVodeReInit(mem, time, y);
      if (NegligiblePiece(time, seg_end, h)) time = seg_end;
      if (static_cast<long>(result.events.size()) > options.max_events) {
        result.success = false;
        result.message = "too many contact events";
      }
    }
    if (time >= grid.end()) grid.Next();
  }
  result.te = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      te_rows.data(), static_cast<Eigen::Index>(result.sample_times.size()),
      static_cast<Eigen::Index>(meshes));
  result.steps += cvode.StepsSoFar();
  result.final_state = Eigen::Map<const Eigen::VectorXd>(NV_DATA_S(y), m);
  t.SetExcitation(time, result.final_state);  // the orders' states where the run ended
  result.final_states = p.states;
  return result;
}

}  // namespace gearnvh
