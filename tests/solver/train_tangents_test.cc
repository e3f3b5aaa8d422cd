// Tangents of the exact train flow (solver/train_tangents.h): finite differences of the flow over
// a window with events, the saltation of one impact against its closed form, the free rotation.
#include "gearnvh/solver/train_tangents.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;

// The state at `time` from z0 (states0), and the run's event count.
Eigen::VectorXd FlowTo(const TrainTables& t, const TrainStepperOptions& options,
                       const Eigen::VectorXd& z0, const std::vector<ContactState>& states0,
                       double time, long* events = nullptr) {
  TrainStepper stepper(t, options, z0, states0);
  REQUIRE(stepper.Run(time));
  if (events != nullptr) *events = stepper.summary().events;
  return stepper.state();
}

// Tangent columns of every elastic coordinate at `time` against central differences of the flow
// with steps h and h/2 (Richardson: their difference estimates the h/2 truncation error).
void CheckAgainstFiniteDifferences(const TrainTables& t, const TrainStepperOptions& options,
                                   double time) {
  const int n = t.n, k = 2 * n;
  auto [z0, states0] = TrainStaticState(t);
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(t.m, k);
  V.topRows(k).setIdentity();
  TrainTangentPropagator tangent(t);
  tangent.Attach(&V);
  TrainStepper stepper(t, options, z0, states0);
  stepper.AttachTangent(&tangent);
  REQUIRE(stepper.Run(time));
  const long events = stepper.summary().events;
  INFO("events in the window " << events << ", saltations " << tangent.saltations());
  REQUIRE(events >= 4);
  CHECK(tangent.saltations() == events - stepper.summary().start_switches);
  // Steps: 1e-9 rad in the angles (a gap moves by ~3e-11 m, 3e-7 of the backlash: the event
  // sequence stays the same) and 1e-5 rad/s in the speeds (the same gap change over ~3e-6 s).
  for (int c = 0; c < k; ++c) {
    const double h = c < n ? 1e-9 : 1e-5;
    Eigen::VectorXd d[2];
    for (int level = 0; level < 2; ++level) {
      const double step = h / (1 << level);
      Eigen::VectorXd plus = z0, minus = z0;
      plus[c] += step;
      minus[c] -= step;
      long events_plus = 0, events_minus = 0;
      const Eigen::VectorXd zp = FlowTo(t, options, plus, states0, time, &events_plus);
      const Eigen::VectorXd zm = FlowTo(t, options, minus, states0, time, &events_minus);
      REQUIRE(events_plus == events);  // the same event sequence, so the flow is smooth here
      REQUIRE(events_minus == events);
      d[level] = (zp - zm).head(k) / (2.0 * step);
    }
    const double scale = d[1].norm();
    const double richardson = (d[0] - d[1]).norm();
    const double error = (V.col(c).head(k) - d[1]).norm();
    INFO("column " << c << ": |V - D(h/2)| = " << error << ", |D(h) - D(h/2)| = " << richardson
                   << ", |D| = " << scale);
    // Tolerance: the truncation error of D(h/2) is about |D(h) - D(h/2)| / 3, its rounding about
    // eps |z| / h (|z| ~ 1e-3 rad, h >= 5e-10: ~5e-10 of |D| here); 1e-5 |D| bounds both with
    // margin, and a missing saltation (a jump of c / m_e ~ 1e3 1/s in a velocity row per impact)
    // or a wrong piece length changes a column by far more.
    CHECK(error <= 4.0 * richardson + 1e-5 * scale);
  }
}

TEST_CASE("train tangents equal finite differences of the flow over a window with events",
          "[solver][train][tangent]") {
  const Model s(testing::RattlerTrain(1500.0));
  // 4 ms of the rattling train: impacts and separations on both meshes, within the first input
  // revolution (no recentring).
  CheckAgainstFiniteDifferences(s.tables, {}, 4e-3);
}

TEST_CASE("train tangents on the dense (Taylor) path equal finite differences",
          "[solver][train][tangent]") {
  TrainStepperOptions options;
  options.tables.max_condition = 1.0;  // every tuple on the dense path
  const Model s(testing::RattlerTrain(1500.0), options.tables);
  CheckAgainstFiniteDifferences(s.tables, options, 4e-3);
}

TEST_CASE("train saltation of one impact equals its closed form", "[solver][train][tangent]") {
  // One mesh, both bodies free, no excitation: the gap closes on a parabola, the mesh impacts
  // drive at t*, then stays in contact. The tangent over [0, T] is, in closed form,
  //   Phi = expm(A_drive (T - t*)) S [[I, t* I], [0, I]],
  //   S = I + (f+ - f-) n^T / (n^T f-) = I - c [0; M^-1 v] [v^T, 0]
  // (at the wall the spring force k g is zero, so the fields differ by the damping force c g'
  // only, and g' = n^T f- cancels). An independent check of S from two assembled generators:
  // (A_drive z* - A_free z*) n^T / (n^T A_free z*).
  TrainSpec spec = testing::TwoStageTrain(150.0, 0.0, 600.0);
  spec.operating.excitation.clear();
  spec.shafts = {spec.shafts[0], spec.shafts[1]};
  spec.gears = {spec.gears[0], spec.gears[1]};
  spec.meshes = {spec.meshes[0]};
  spec.operating.loads = {{"layshaft", 75.0}};
  const Model s(spec);
  const TrainTables& t = s.tables;
  const int n = t.n, k = 2 * n;
  const TrainMeshTable& mt = t.meshes[0];
  REQUIRE(mt.damping > 0.0);
  // Start 1e-7 m inside the drive wall of segment 0, closing at 0.02 m/s.
  Eigen::VectorXd z0 = Eigen::VectorXd::Zero(t.m);
  z0[t.constant_slot()] = 1.0;
  const double wall = t.Wall(0, 0, true);
  const double vv = mt.v.squaredNorm();
  z0.head(n) = (wall - 1e-7) / vv * mt.v;
  z0.segment(n, n) = 0.02 / vv * mt.v;
  const std::vector<ContactState> free = {ContactState::kFree};
  const std::vector<ContactState> drive = {ContactState::kDrive};
  const double end = 1e-5;  // about 2 t*, inside the first grid segment
  TrainGrid grid(t);
  REQUIRE(grid.end() > end);

  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(t.m, k);
  V.topRows(k).setIdentity();
  TrainTangentPropagator tangent(t);
  tangent.Attach(&V);
  TrainStepper stepper(t, {}, z0, free);
  stepper.AttachTangent(&tangent);
  // The impact time: the first root of the free parabola's gap.
  const Eigen::VectorXd accel = t.force.cwiseQuotient(t.inertia);
  const double a = 0.5 * mt.v.dot(accel), b = 0.02, c0 = -1e-7;
  const double t_star = a == 0.0 ? -c0 / b : (-b + std::sqrt(b * b - 4.0 * a * c0)) / (2.0 * a);
  REQUIRE(t_star > 0.0);
  REQUIRE(t_star < end);
  REQUIRE(stepper.Run(t_star * (1.0 - 1e-9)));
  REQUIRE(stepper.states()[0] == ContactState::kFree);
  REQUIRE(stepper.Run(end));
  REQUIRE(stepper.states()[0] == ContactState::kDrive);
  REQUIRE(stepper.summary().events == 1);
  REQUIRE(tangent.saltations() == 1);

  const Eigen::VectorXd inv_j = t.inertia.cwiseInverse();
  Eigen::MatrixXd S = Eigen::MatrixXd::Identity(k, k);
  S.block(n, 0, n, n) -= mt.damping * inv_j.cwiseProduct(mt.v) * mt.v.transpose();
  // The generic saltation from two independently assembled generators at the impact state.
  Eigen::VectorXd z_star = Eigen::VectorXd::Zero(t.m);
  z_star.head(n) = z0.head(n) + t_star * z0.segment(n, n) + 0.5 * t_star * t_star * accel;
  z_star.segment(n, n) = z0.segment(n, n) + t_star * accel;
  z_star[t.constant_slot()] = 1.0;
  const Eigen::MatrixXd A_free = AssembleTrainGenerator(t, {0}, free);
  const Eigen::MatrixXd A_drive = AssembleTrainGenerator(t, {0}, drive);
  Eigen::RowVectorXd normal = Eigen::RowVectorXd::Zero(t.m);
  normal.head(n) = mt.v.transpose();
  const Eigen::VectorXd f_minus = A_free * z_star;
  const Eigen::MatrixXd S_generic = Eigen::MatrixXd::Identity(t.m, t.m) +
                                    (A_drive * z_star - f_minus) * normal / normal.dot(f_minus);
  // The gap at z* is ~1e-7 m * (rounding of t*), k g ~ 1e-9 N against c g' ~ 1 N: the two forms
  // agree to 1e-8 of the jump.
  CHECK((S_generic.topLeftCorner(k, k) - S).cwiseAbs().maxCoeff() <=
        1e-8 * (S - Eigen::MatrixXd::Identity(k, k)).cwiseAbs().maxCoeff());

  Eigen::MatrixXd flight = Eigen::MatrixXd::Identity(k, k);
  flight.topRightCorner(n, n) = t_star * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd contact =
      BalancedExpm(A_drive, end - t_star, n, ReferenceFrequency(A_drive, n)).topLeftCorner(k, k);
  const Eigen::MatrixXd expected = contact * S * flight;
  // Tolerance: the event time is located to rounding (~1e-16 s relative), and the two exponentials
  // (closed form vs Pade) agree to ~1e-13 of |Phi|; 1e-9 leaves margin. Without the saltation
  // the velocity rows differ by c / m_e t ~ O(1) of |Phi|.
  const double scale = expected.cwiseAbs().maxCoeff();
  INFO("max |V - Phi| / |Phi| = " << (V.topRows(k) - expected).cwiseAbs().maxCoeff() / scale);
  CHECK((V.topRows(k) - expected).cwiseAbs().maxCoeff() <= 1e-9 * scale);
}

TEST_CASE("the train's free rotation is neutral: multiplier 1 through impacts",
          "[solver][train][tangent]") {
  // [r; 0] is an eigenvector of eigenvalue 0 of every tuple's generator and annihilated by every
  // gap row, so it maps to itself through pieces and saltations (exponent 0); [0; r] maps to
  // [t r; r] (its Jordan partner: linear growth, exponent 0 as well). Their coordinates
  // r~ x = r^T M x and r~ x' evolve on their own (r^T K_s = r^T C_s = 0, r^T v_i = 0), so they are
  // exact through any run; the rest of the column is rounding, which the rattling train's
  // positive exponent amplifies (~e^{t / 1.3 ms} measured), so the whole column is checked over a
  // short window and the coordinates over a long one.
  const Model s(testing::RattlerTrain(1500.0));
  const TrainTables& t = s.tables;
  const int n = t.n;
  auto [z0, states0] = TrainStaticState(t);
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(t.m, 2);
  V.col(0).head(n) = t.rigid_rotation;
  V.col(1).segment(n, n) = t.rigid_rotation;
  TrainTangentPropagator tangent(t);
  tangent.Attach(&V);
  TrainStepper stepper(t, {}, z0, states0);
  stepper.AttachTangent(&tangent);
  const double scale = t.rigid_rotation.norm();

  const double short_time = 5e-3;
  REQUIRE(stepper.Run(short_time));
  REQUIRE(tangent.saltations() >= 5);
  Eigen::VectorXd position = Eigen::VectorXd::Zero(t.m), velocity = position;
  position.head(n) = t.rigid_rotation;
  velocity.head(n) = short_time * t.rigid_rotation;
  velocity.segment(n, n) = t.rigid_rotation;
  // Tolerance: each piece reproduces [r; 0] to ~cond(S) eps |A| |r| t (measured 4e-11 of |r| in
  // 5 ms); 1e-7 of |r| allows the amplification of that rounding over the window.
  CHECK((V.col(0) - position).norm() <= 1e-7 * scale);
  CHECK((V.col(1) - velocity).norm() <= 1e-7 * scale);

  const double long_time = 20e-3;  // within the first input revolution (75 ms): no recentring
  REQUIRE(stepper.Run(long_time));
  REQUIRE(stepper.summary().recenterings == 0);
  REQUIRE(tangent.saltations() > 20);
  // r~ r = 1 (M-normalised). Tolerance: rounding of the pieces, 1e-9 (measured < 1e-10).
  CHECK(std::abs(t.recenter_row.dot(V.col(0).head(n)) - 1.0) <= 1e-9);
  CHECK(std::abs(t.recenter_row.dot(V.col(0).segment(n, n))) <= 1e-9);
  CHECK(std::abs(t.recenter_row.dot(V.col(1).head(n)) - long_time) <= 1e-9);
  CHECK(std::abs(t.recenter_row.dot(V.col(1).segment(n, n)) - 1.0) <= 1e-9);
  // The exponent along the free rotation: ln(r~ V r) / T = 0.
  CHECK(std::abs(std::log(t.recenter_row.dot(V.col(0).head(n)))) / long_time <= 1e-7);
  // Projected out, the free rotation leaves only the amplified rounding: its r-coordinates vanish.
  RemoveTrainFreeRotation(t, V);
  CHECK(std::abs(t.recenter_row.dot(V.col(0).head(n))) <= 1e-12);
  CHECK(std::abs(t.recenter_row.dot(V.col(1).segment(n, n))) <= 1e-12);
}

}  // namespace
}  // namespace gearnvh
