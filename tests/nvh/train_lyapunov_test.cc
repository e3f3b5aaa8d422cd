// Lyapunov exponents (nvh/train_lyapunov.h) and periodic orbits (nvh/train_periodic_orbit.h) of
// gear trains: Floquet exponents of a train in permanent contact, a train decoupled by a massive
// layshaft against its one-mesh trains, a one-mesh train against the pair's solver, the periodic
// orbit of a train in permanent contact against the linear periodic solution.
#include "gearnvh/nvh/train_lyapunov.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <functional>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/lyapunov.h"
#include "gearnvh/nvh/train_periodic_orbit.h"
#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/train_reference.h"
#include "model/test_specs.h"
#include "model/test_trains.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;

// Floquet exponents ln |mu| / T (descending) of a train held in drive contact on every mesh, from
// the monodromy over the common period T assembled from dense propagators of an independent
// assembly; the two unit multipliers of the free rotation are left out.
std::vector<double> FloquetExponents(const TrainTables& t) {
  const int n = t.n, e = 2 * n;
  REQUIRE(t.common_period > 0.0);
  const std::vector<ContactState> drive(t.meshes.size(), ContactState::kDrive);
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(e, e);
  for (TrainGrid grid(t); grid.start() < t.common_period * (1.0 - 1e-12); grid.Next()) {
    const Eigen::MatrixXd A = AssembleTrainGenerator(t, grid.segments(), drive);
    const double h = grid.end() - grid.start();
    P = BalancedExpm(A, h, n, ReferenceFrequency(A, n)).topLeftCorner(e, e) * P;
  }
  // On the quotient: Pi = I - U U^T W projects off the free rotation U = [[r, 0], [0, r]]
  // (W = diag(M, M), U^T W U = I); the complement is invariant, so Pi P = P Pi has the elastic
  // multipliers and two zeros, and its entries are those of the decaying part only (the free
  // rotation's 1 and T would otherwise set the rounding floor of the eigenvalues).
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(e, 2);
  U.col(0).head(n) = t.rigid_rotation;
  U.col(1).tail(n) = t.rigid_rotation;
  Eigen::VectorXd w(e);
  w << t.inertia, t.inertia;
  const Eigen::MatrixXd Pi = Eigen::MatrixXd::Identity(e, e) - U * (U.transpose() * w.asDiagonal());
  const Eigen::VectorXcd mu = (Pi * P).eigenvalues();
  std::vector<double> moduli;
  for (Eigen::Index i = 0; i < mu.size(); ++i) moduli.push_back(std::abs(mu[i]));
  std::sort(moduli.begin(), moduli.end());
  // The two zeros come out at the rounding floor of Pi P; the elastic multipliers carry an
  // absolute error of the same size, so moduli[1] / moduli[2] bounds their relative error (and
  // that over T the exponents' error: < 2e-2 1/s with the 1e-3 bound below, measured 1e-3).
  INFO("multipliers " << Eigen::Map<Eigen::VectorXd>(moduli.data(), e).transpose());
  REQUIRE(moduli[1] < 1e-3 * moduli[2]);
  moduli.erase(moduli.begin(), moduli.begin() + 2);
  // The product of the pieces carries an absolute rounding error ~1e-16 |P| (|P| includes the
  // free rotation's block, O(1)): multipliers below 1e-10 would be rounding, not dynamics.
  REQUIRE(moduli.front() > 1e-10);
  std::vector<double> out;
  for (double m : moduli) out.push_back(std::log(m) / t.common_period);
  std::sort(out.begin(), out.end(), std::greater<>());
  return out;
}

TrainLyapunovSummary Estimate(const TrainTables& t, int exponents, long cycles) {
  const auto [z0, states0] = TrainStaticState(t);
  TrainLyapunovOptions options;
  options.exponents = exponents;
  options.transient_cycles = 20;
  options.cycles = cycles;
  const TrainLyapunovSummary s = EstimateTrainLyapunov(t, z0, states0, options);
  REQUIRE(s.info == TrainLyapunovSummary::Info::kSuccess);
  REQUIRE(s.run.events == 0);  // permanent contact
  return s;
}

// Each exponent against its reference (both descending). For a complex pair of multipliers the
// QR splits the pair's area growth between two columns only to O(1 / T) (the plane rotates); the
// sum of all exponents is the volume growth of the whole quotient, exact up to a boundary term
// O(ln cond / T).
void CheckAgainst(const TrainLyapunovSummary& est, std::vector<double> expected) {
  REQUIRE(est.exponents.size() == expected.size());
  std::sort(expected.begin(), expected.end(), std::greater<>());
  double sum = 0.0, expected_sum = 0.0;
  for (size_t j = 0; j < expected.size(); ++j) {
    INFO("exponent " << j << ": " << est.exponents[j] << " 1/s (standard error "
                     << est.standard_errors[j] << "), expected " << expected[j] << " 1/s over "
                     << est.averaged_s << " s");
    // Tolerance: 3 / T (measured up to 0.35 / T for the split of a pair).
    CHECK(std::abs(est.exponents[j] - expected[j]) <= 3.0 / est.averaged_s);
    sum += est.exponents[j];
    expected_sum += expected[j];
  }
  // Tolerance: 1e-4 of the sum (measured < 1e-8).
  CHECK(std::abs(sum - expected_sum) <= 1e-4 * std::abs(expected_sum));
}

TEST_CASE("train Lyapunov exponents in permanent contact are the Floquet exponents",
          "[nvh][train][lyapunov]") {
  // Loaded, no excitation, light damping (so the monodromy's multipliers e^{-zeta w T} stay far
  // above rounding): every mesh stays in drive contact and the train is linear and periodic in its
  // common period (one input revolution, 20 ms).
  TrainSpec spec = testing::TwoStageTrain(1000.0, 0.0, 1000.0);
  spec.operating.excitation.clear();
  for (TrainMesh& m : spec.meshes) m.mesh.damping_ratio = 0.01;
  const Model s(spec);
  const std::vector<double> floquet = FloquetExponents(s.tables);
  REQUIRE(floquet.size() == 4);
  const TrainLyapunovSummary est = Estimate(s.tables, 4, 2000);
  CheckAgainst(est, floquet);
  // In contact the sum of all the quotient's exponents is tr(A) on it, constant in time:
  // -sum_i c_i v_i^T M^-1 v_i (the free rotation's two zeros add nothing). Tolerance as above.
  double trace = 0.0;
  for (const TrainMeshTable& mt : s.tables.meshes)
    trace -= mt.damping * mt.v.cwiseQuotient(s.tables.inertia).dot(mt.v);
  double sum = 0.0;
  for (double l : est.exponents) sum += l;
  CHECK(std::abs(sum - trace) <= 1e-4 * std::abs(trace));
  CHECK(est.per_forcing_cycle[0] == Approx(est.exponents[0] * est.forcing_period));
  CHECK(std::isinf(est.predictability_horizon_s));
}

TEST_CASE("train Lyapunov exponents come largest first, even from a short run",
          "[nvh][train][lyapunov]") {
  // A lightly loaded two-stage train over 10 cycles: two close exponents have not separated in
  // the QR's columns yet (unsorted without the sort, as a user saw lambda_1 < lambda_2). The list
  // is sorted, each exponent keeping its standard error and cycle scalings; the horizon uses the
  // largest.
  const Model s(testing::TwoStageTrain(5.0, 300.0, 600.0));
  const auto [z0, states0] = TrainStaticState(s.tables);
  TrainLyapunovOptions options;
  options.exponents = 2 * s.tables.n - 2;
  options.transient_cycles = 5;
  options.alignment_cycles = 2;
  options.cycles = 10;
  const TrainLyapunovSummary est = EstimateTrainLyapunov(s.tables, z0, states0, options);
  REQUIRE(est.info == TrainLyapunovSummary::Info::kSuccess);
  REQUIRE(est.exponents.size() == static_cast<size_t>(options.exponents));
  CHECK(std::is_sorted(est.exponents.rbegin(), est.exponents.rend()));
  for (size_t j = 0; j < est.exponents.size(); ++j) {
    // The scalings are products of the same doubles: equal to one rounding.
    CHECK(est.per_mesh_cycle[j] == Approx(est.exponents[j] * est.mesh_period).epsilon(1e-15));
    CHECK(est.per_forcing_cycle[j] == Approx(est.exponents[j] * est.forcing_period).epsilon(1e-15));
  }
  if (est.exponents.front() > 0.0) {
    CHECK(est.predictability_horizon_s ==
          Approx(52.0 * std::log(2.0) / est.exponents.front()).epsilon(1e-15));
  } else {
    CHECK(std::isinf(est.predictability_horizon_s));
  }
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

// Input (g1, 20) -> layshaft (g2, 40; g3, 20) -> output (g4, 40) with a massive layshaft, or one
// of its stages alone as a one-mesh train with the same transmitted torque (as the train solver's
// decoupling test).
TrainSpec Stage(int which) {
  TrainSpec t = testing::TwoStageAlone(which, 1e8);
  // Light damping keeps the multipliers over the common period (0.1 s, 0.2 s for the second
  // stage alone) far above rounding (see FloquetExponents).
  for (TrainMesh& m : t.meshes) m.mesh.damping_ratio = 0.01;
  return t;
}

TEST_CASE("a train decoupled by a massive layshaft has the exponents of its one-mesh trains",
          "[nvh][train][lyapunov]") {
  // The layshaft (1e8 kg m^2) decouples the stages: the train's four exponents are the union of
  // the two one-mesh trains' two each (each one mesh's pair), to the coupling through the
  // layshaft (relative ~J_gear / J_lay ~ 1e-11) and the estimator's O(1 / T) split.
  const Model full(Stage(0)), first(Stage(1)), second(Stage(2));
  const TrainLyapunovSummary a = Estimate(full.tables, 4, 1000);
  const TrainLyapunovSummary b = Estimate(first.tables, 2, 1000);
  const TrainLyapunovSummary c = Estimate(second.tables, 2, 500);
  // Each one-mesh train against its own Floquet exponents (the independent reference), then the
  // train against the union of the one-mesh trains' exponents.
  CheckAgainst(b, FloquetExponents(first.tables));
  CheckAgainst(c, FloquetExponents(second.tables));
  CheckAgainst(a, {b.exponents[0], b.exponents[1], c.exponents[0], c.exponents[1]});
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("a one-mesh train has the single pair's exponent at the same operating point",
          "[nvh][train][lyapunov]") {
  // The schema-1 pair and its train TrainOf(pair) at tier 1 are the same two torsional bodies and
  // the same mesh model; the pair's solver (ExactStepper, one tangent) and the train's (tangent
  // columns with saltation per gap) are independent implementations. Loaded, no excitation:
  // permanent contact, one complex pair of multipliers, so the train's two exponents and the
  // pair's one are the same sigma.
  GearboxSpec pair = testing::StandardPair(27, 43);
  pair.operating.torque = 40.0;
  pair.operating.excitation.clear();
  // Light damping: the multipliers over one revolution stay far above rounding (FloquetExponents).
  pair.mesh.damping_ratio = 0.005;
  const OperatingPointModel op = BuildOperatingPointModel(pair, Tier::kTier1);
  const auto [z_pair, state_pair] = StaticInitialState(op.tables);
  LyapunovOptions pair_options;
  pair_options.transient_cycles = 20;
  pair_options.cycles = 1000;
  const LyapunovEstimate pair_est = EstimateLyapunov(op.tables, z_pair, state_pair, pair_options);
  REQUIRE(pair_est.info == LyapunovEstimate::Info::kSuccess);
  REQUIRE(pair_est.run.summary.events == 0);

  const Model train(TrainOf(pair));
  REQUIRE(train.tables.n == 2);
  const TrainLyapunovSummary est = Estimate(train.tables, 2, 1000);
  const std::vector<double> floquet = FloquetExponents(train.tables);
  CheckAgainst(est, floquet);
  INFO("pair " << pair_est.exponent << " 1/s, train " << est.exponents[0] << ", "
               << est.exponents[1] << " 1/s, Floquet " << floquet[0] << ", " << floquet[1]);
  // Tolerance: 3 / T as for the train (the pair's one tangent splits the same rotating plane;
  // measured 0.16 1/s = 0.45 / T), far below the 245 1/s exponent a wrong damping would move.
  CHECK(std::abs(pair_est.exponent - floquet[0]) <= 3.0 / est.averaged_s);
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("a train's periodic orbit in permanent contact is the linear periodic solution",
          "[nvh][train][orbit]") {
  // The train of the Floquet test: linear and T-periodic in permanent contact, so its periodic
  // orbit is the fixed point of the affine period map, here from dense Pade propagators of an
  // independent assembly ((I - P) y = p, least squares: the free rotation is null), and its
  // multipliers are those of FloquetExponents.
  TrainSpec spec = testing::TwoStageTrain(1000.0, 0.0, 1000.0);
  spec.operating.excitation.clear();
  for (TrainMesh& m : spec.meshes) m.mesh.damping_ratio = 0.01;
  const Model s(spec);
  const TrainTables& t = s.tables;
  const int n = t.n, e = 2 * n;
  const std::vector<ContactState> drive(t.meshes.size(), ContactState::kDrive);
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(t.m, t.m);
  for (TrainGrid grid(t); grid.start() < t.common_period * (1.0 - 1e-12); grid.Next()) {
    const Eigen::MatrixXd A = AssembleTrainGenerator(t, grid.segments(), drive);
    P = BalancedExpm(A, grid.end() - grid.start(), n, ReferenceFrequency(A, n)) * P;
  }
  const Eigen::VectorXd reference = (Eigen::MatrixXd::Identity(e, e) - P.topLeftCorner(e, e))
                                        .completeOrthogonalDecomposition()
                                        .solve(P.block(0, t.constant_slot(), e, 1));

  const auto [z0, states0] = TrainStaticState(t);
  const TrainOrbit orbit = FindTrainPeriodicOrbit(t, z0, states0, {});
  INFO("residual " << orbit.residual << " after " << orbit.iterations << " iterations");
  REQUIRE(orbit.info == TrainOrbit::Info::kConverged);
  CHECK(orbit.events_per_period == 0);
  CHECK(orbit.stable);
  // TE (free of the free rotation). Tolerance: both are the same fixed point to the Newton
  // tolerance (1e-10) and the rounding of ~400 pieces (~1e-13 of the TE in the stepper's test);
  // 1e-8 of the TE.
  for (const TrainMeshTable& mt : t.meshes) {
    const double expected = mt.v.dot(reference.head(n));
    CHECK(std::abs(mt.v.dot(orbit.z.head(n)) - expected) <= 1e-8 * std::abs(expected));
  }
  // Multipliers: |mu| = e^{lambda T} with the Floquet exponents of the Pade monodromy.
  // Tolerance: 1e-6 relative in |mu| (the two products agree to rounding times cond, the
  // smallest multiplier is 1e-5 here).
  const std::vector<double> floquet = FloquetExponents(t);
  REQUIRE(orbit.multipliers.size() == static_cast<Eigen::Index>(floquet.size()));
  for (size_t j = 0; j < floquet.size(); ++j) {
    const double expected = std::exp(floquet[j] * t.common_period);
    CHECK(std::abs(std::abs(orbit.multipliers[static_cast<Eigen::Index>(j)]) - expected) <=
          1e-6 * expected);
  }
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

// The loaded two-stage train with a loose gear g5 (30 teeth) driven by g1 against a drag that
// keeps it in contact, idling on the input shaft or on a fixed shaft that stands.
TrainSpec WithIdler(bool standing) {
  TrainSpec spec = testing::TwoStageTrain(1000.0, 0.0, 1000.0);
  spec.operating.excitation.clear();
  spec.gears.push_back(testing::TrainGearOf("g5", "input", 30, Mounting::kLoose));
  if (standing) {
    spec.shafts.push_back(testing::RigidShaft("carrier", 0.01));
    spec.shafts.back().fixed = true;
    spec.gears.back().shaft = "carrier";
  }
  spec.meshes.push_back(testing::TrainMeshOf("g1", "g5"));
  spec.operating.loads.push_back({"g5", 20.0});
  return spec;
}

TEST_CASE("a standing shaft's rotation is neutral: the orbit's quotient and Lyapunov leave it out",
          "[nvh][train][orbit]") {
  // At tier 1 the carrier of a loose gear does not enter the dynamics, so the orbit of the train
  // with g5 on a standing shaft has the multipliers of the train with g5 on the input shaft; the
  // standing shaft's position and velocity (multiplier 1 and its Jordan partner) are taken out
  // like the free rotation's, leaving 2n - 4 multipliers.
  const Model turning(WithIdler(false)), standing(WithIdler(true));
  REQUIRE(standing.tables.n == turning.tables.n + 1);
  REQUIRE(standing.tables.standing_rotations.cols() == 1);
  const auto orbit_of = [](const TrainTables& t) {
    const auto [z0, states0] = TrainStaticState(t);
    return FindTrainPeriodicOrbit(t, z0, states0, {});
  };
  const TrainOrbit a = orbit_of(turning.tables), b = orbit_of(standing.tables);
  REQUIRE(a.info == TrainOrbit::Info::kConverged);
  REQUIRE(b.info == TrainOrbit::Info::kConverged);
  CHECK(b.events_per_period == 0);
  CHECK(b.stable);
  REQUIRE(b.multipliers.size() == 2 * standing.tables.n - 4);
  REQUIRE(b.multipliers.size() == a.multipliers.size());
  // Tolerance: one dynamics, one period map up to an inert body's rows: the moduli agree to the
  // rounding of the products times their conditioning, 1e-6 of the largest (the smallest are
  // rounding, ~1e-14; without the standing rotation taken out, two multipliers would be 1).
  INFO("multipliers " << a.multipliers.transpose() << " | " << b.multipliers.transpose());
  REQUIRE(std::abs(a.multipliers[0]) > 1e-9);  // 2.2e-6 measured (a well damped train)
  for (Eigen::Index j = 0; j < a.multipliers.size(); ++j) {
    CHECK(std::abs(std::abs(b.multipliers[j]) - std::abs(a.multipliers[j])) <=
          1e-6 * std::abs(a.multipliers[0]));
  }
  TrainLyapunovOptions too_many;
  too_many.exponents = 2 * standing.tables.n - 2;
  const auto [z0, states0] = TrainStaticState(standing.tables);
  CHECK_THROWS_AS(EstimateTrainLyapunov(standing.tables, z0, states0, too_many), InputError);
  // The largest exponent of a stable orbit is negative, as with the carrier turning: the standing
  // rotation's neutral pair (whose linear growth would read as +ln(t)/t) is projected out.
  TrainLyapunovOptions options;
  options.transient_cycles = 20;
  options.alignment_cycles = 20;
  options.cycles = 200;
  const auto largest = [&](const TrainTables& t) {
    const auto [z, st] = TrainStaticState(t);
    const TrainLyapunovSummary l = EstimateTrainLyapunov(t, z, st, options);
    REQUIRE(l.info == TrainLyapunovSummary::Info::kSuccess);
    return l.exponents.front();
  };
  const double lambda_turning = largest(turning.tables), lambda_standing = largest(standing.tables);
  INFO("largest exponent: turning carrier " << lambda_turning << " 1/s, standing "
                                            << lambda_standing << " 1/s");
  CHECK(lambda_turning < 0.0);
  CHECK(lambda_standing < 0.0);
  // One linear periodic dynamics, and the start directions differ only in the inert coordinate
  // (projected out): equal to 6 digits measured; 1e-6 relative allowed.
  CHECK(lambda_standing == Approx(lambda_turning).epsilon(1e-6));
}

TEST_CASE("a rattling train's periodic orbit closes on the independent dense path",
          "[nvh][train][orbit]") {
  // Light load, engine excitation: the two-stage train rattles periodically (impacts every
  // period). Newton from the static state (not on the orbit) must converge; the orbit is then
  // checked by the independent dense locator (max_condition = 1: every tuple on the Taylor path,
  // polynomial gaps bisected to rounding) from the orbit's state over one period: it comes back.
  const Model s(testing::TwoStageTrain(5.0, 300.0, 1000.0));
  const TrainTables& t = s.tables;
  const int n = t.n;
  const auto [z0, states0] = TrainStaticState(t);
  const TrainOrbit orbit = FindTrainPeriodicOrbit(t, z0, states0, {});
  INFO("residual " << orbit.residual << " after " << orbit.iterations << " iterations, "
                   << orbit.events_per_period << " events per period");
  REQUIRE(orbit.info == TrainOrbit::Info::kConverged);
  CHECK(orbit.iterations >= 1);
  REQUIRE(orbit.events_per_period >= 4);
  CHECK(orbit.stable);

  TrainStepperOptions dense;
  dense.tables.max_condition = 1.0;
  TrainStepper stepper(t, dense, orbit.z, orbit.states);
  REQUIRE(stepper.Run(orbit.period));
  CHECK(stepper.summary().events == orbit.events_per_period);
  CHECK(stepper.summary().dense_pieces > 0);
  CHECK(stepper.states() == orbit.states);
  // TE after one period. Tolerance: the two locators agree to rounding (1e-8 of the TE over 8 ms
  // of chaotic rattle in the solver's test); the orbit is strongly stable (|mu| ~ 1e-5), so
  // nothing amplifies the difference over 60 ms: 1e-7 of the TE scale.
  double scale = 0.0;
  for (const TrainMeshTable& mt : t.meshes)
    scale = std::max(scale, std::abs(mt.v.dot(orbit.z.head(n))));
  for (const TrainMeshTable& mt : t.meshes) {
    const double start = mt.v.dot(orbit.z.head(n));
    const double end = mt.v.dot(stepper.state().head(n));
    CHECK(std::abs(end - start) <= 1e-7 * scale);
  }

  // The CVODE reference from the orbit's state (an impact may sit within rounding of a grid
  // boundary there) comes back too. Tolerance: rtol 1e-12 over 8 events, the orbit strongly
  // stable: 1e-6 of the TE scale.
  TrainReferenceOptions reference;
  reference.end_time = orbit.period;
  const TrainReferenceResult cvode = SimulateTrainReference(t, orbit.z, orbit.states, reference);
  INFO(cvode.message);
  REQUIRE(cvode.success);
  CHECK(static_cast<long>(cvode.events.size()) == orbit.events_per_period);
  for (const TrainMeshTable& mt : t.meshes) {
    const double start = mt.v.dot(orbit.z.head(n));
    CHECK(std::abs(mt.v.dot(cvode.final_state.head(n)) - start) <= 1e-6 * scale);
  }
}

TEST_CASE("a stopped train run says why in the solver's own words", "[nvh][train][lyapunov]") {
  // The rattler has grid segments with two or more events (train_stepper_test.cc), so a limit of
  // one event per segment stops the exponents' transient and the orbit's first shot.
  const Model s(testing::RattlerTrain(1500.0));
  const auto [z0, states0] = TrainStaticState(s.tables);
  TrainLyapunovOptions lyapunov;
  lyapunov.stepper.max_events_per_segment = 1;
  const TrainLyapunovSummary l = EstimateTrainLyapunov(s.tables, z0, states0, lyapunov);
  INFO(l.message);
  REQUIRE(l.info == TrainLyapunovSummary::Info::kSolverFailed);
  REQUIRE(l.run.info == TrainStepperSummary::Info::kTooManyEvents);
  CHECK(l.message == "the train stepper stopped: " + TrainStepperMessage(l.run));
  CHECK(l.message.find("more than 1 contact events in the") != std::string::npos);

  TrainOrbitOptions orbit_options;
  orbit_options.stepper.max_events_per_segment = 1;
  const TrainOrbit orbit = FindTrainPeriodicOrbit(s.tables, z0, states0, orbit_options);
  INFO(orbit.stop_reason);
  REQUIRE(orbit.info == TrainOrbit::Info::kSolverFailed);
  CHECK(orbit.stop_reason.find("more than 1 contact events in the") == 0);
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("a viscous drag damps the free rotation: the orbit keeps its speed, Lyapunov projects it",
          "[nvh][train][orbit]") {
  // The loaded reducer in permanent contact with a viscous drag c on its output's speed. Turned
  // faster as one body (by q along r, M-normalised) the train slows back at sigma = c r_out^2
  // (tests/solver/train_drag_test.cc), so its free rotation's speed is a decaying direction of
  // multiplier e^(-sigma T), and only its angle is neutral: the orbit has 2n - 1 multipliers, one
  // of them that one (every mesh mode decays faster, at zeta omega ~ 60 1/s and more).
  TrainSpec spec = testing::TwoStageTrain(1000.0, 0.0, 1000.0);
  spec.operating.excitation.clear();
  for (TrainMesh& m : spec.meshes) m.mesh.damping_ratio = 0.01;
  const double c = 0.5;
  spec.operating.loads[0].viscous = c;
  const Model s(spec);
  const TrainTables& t = s.tables;
  REQUIRE(t.free_rotation_damped);
  const double sigma = c * t.rigid_rotation[2] * t.rigid_rotation[2];
  const auto [z0, states0] = TrainStaticState(t);
  const TrainOrbit orbit = FindTrainPeriodicOrbit(t, z0, states0, {});
  REQUIRE(orbit.info == TrainOrbit::Info::kConverged);
  CHECK(orbit.stable);
  REQUIRE(orbit.multipliers.size() == 2 * t.n - 1);
  // The slowest mode is the rotation's speed: the largest multiplier, real. Tolerance: its
  // exponent differs from -sigma by the mesh modes' coupling, of order (sigma / omega_mesh)^2 ~
  // 1e-6 relative; 1e-4 allowed (an undamped speed would give 1, twice the rate e^(-2 sigma T)).
  const std::complex<double> mu = orbit.multipliers[0];
  INFO("multipliers " << orbit.multipliers.transpose() << "; e^(-sigma T) "
                      << std::exp(-sigma * t.common_period));
  CHECK(std::abs(mu.imag()) <= 1e-12);
  CHECK(std::log(mu.real()) / t.common_period == Approx(-sigma).epsilon(1e-4));
  // Over two common periods the same rate (the quotient's map is Pi J, whatever phase the
  // stepper last recentred at).
  TrainOrbitOptions two;
  two.periods = 2;
  const TrainOrbit twice = FindTrainPeriodicOrbit(t, z0, states0, two);
  REQUIRE(twice.info == TrainOrbit::Info::kConverged);
  REQUIRE(twice.multipliers.size() == 2 * t.n - 1);
  CHECK(std::log(std::abs(twice.multipliers[0])) / (2.0 * t.common_period) ==
        Approx(-sigma).epsilon(1e-4));

  // Lyapunov exponents project the rotation's speed out as well (its exponent -sigma, ~-11 1/s
  // here, would otherwise be the largest and hide the relative motion's, ~-60 1/s): at most
  // 2n - 2, the largest the orbit's next multiplier's exponent ln|mu_1| / T.
  TrainLyapunovOptions too_many;
  too_many.exponents = 2 * t.n - 1;
  CHECK_THROWS_AS(EstimateTrainLyapunov(t, z0, states0, too_many), InputError);
  TrainLyapunovOptions options;
  options.exponents = 2;
  options.transient_cycles = 20;
  options.alignment_cycles = 20;
  options.cycles = 1000;
  const TrainLyapunovSummary l = EstimateTrainLyapunov(t, z0, states0, options);
  REQUIRE(l.info == TrainLyapunovSummary::Info::kSuccess);
  const double averaged = options.cycles * t.meshes[0].period;
  const double relative = std::log(std::abs(orbit.multipliers[1])) / t.common_period;
  INFO("exponents " << l.exponents[0] << ", " << l.exponents[1] << " 1/s; the orbit's next "
                    << relative << " 1/s, sigma " << sigma << " 1/s over " << averaged << " s");
  CHECK(l.exponents.front() < -2.0 * sigma);  // not the rotation's speed
  // A linear periodic flow: the exponents are its Floquet exponents, up to the finite-time
  // estimate's bias ln|a| / T (1 / T allowed) and the projection's second-order error in the
  // drag's coupling (measured below 1e-3 relative): 1 / T + 1e-2 |lambda|.
  CHECK(std::abs(l.exponents.front() - relative) <= 1.0 / averaged + 1e-2 * std::abs(relative));
}

}  // namespace
}  // namespace gearnvh
