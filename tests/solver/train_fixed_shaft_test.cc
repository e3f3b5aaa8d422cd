// A fixed shaft (TrainShaft::fixed, neutral at standstill): it stands, loose gears turn on it, and
// nothing in the dynamics moves it.
#include <catch2/catch.hpp>
#include <cmath>

#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;
using testing::MeshTe;

// The rattler (input -> layshaft -> loose g4) with g4 idling on a fixed shaft of its own.
TrainSpec StandingCarrier(double excitation) {
  TrainSpec spec = testing::RattlerTrain(excitation);
  spec.shafts.push_back(testing::RigidShaft("carrier", 0.01));
  spec.shafts.back().fixed = true;
  spec.gears[3].shaft = "carrier";
  return spec;
}

TEST_CASE("fixed shaft: at tier 1 a loose gear's carrier does not enter, standing or turning",
          "[solver][train]") {
  // Tier 1 has no lateral DOF and the drag acts on the loose gear's absolute speed, so g4 idling
  // on the input shaft or on a standing shaft is one model; the standing shaft only adds an inert
  // body. Rattling (engine order 2 at 1500 rad/s^2), which is chaotic: a rounding difference
  // grows tenfold every ~0.75 mesh cycle (measured: 1e-19 m after 6 samples, 1e-14 m after 30,
  // 1e-5 m after 90), so both meshes' TE are compared over the first 30 samples (3.75 cycles).
  const Model turning(testing::RattlerTrain(1500.0)), standing(StandingCarrier(1500.0));
  REQUIRE(standing.tables.n == turning.tables.n + 1);
  const auto [z_a, s_a] = TrainStaticState(turning.tables);
  const auto [z_b, s_b] = TrainStaticState(standing.tables);
  TrainStepper a(turning.tables, {}, z_a, s_a), b(standing.tables, {}, z_b, s_b);
  const double period = turning.tables.meshes[0].period;
  double worst = 0.0, te = 0.0;
  for (int k = 1; k <= 30; ++k) {
    REQUIRE(a.Run(k * period / 8.0));
    REQUIRE(b.Run(k * period / 8.0));
    for (int i = 0; i < 2; ++i) {
      worst = std::max(worst, std::abs(MeshTe(turning.tables, a, i) - MeshTe(standing.tables, b, i)));
      te = std::max(te, std::abs(MeshTe(turning.tables, a, i)));
    }
    CHECK(b.state()[2] == 0.0);  // the carrier's angle: its rows are zero, it never moves
  }
  INFO("largest TE difference " << worst << " m of TE up to " << te << " m; "
                                << a.summary().events << " contact events");
  REQUIRE(a.summary().events >= 15);  // it rattles (21 events)
  CHECK(b.summary().events == a.summary().events);
  // Two generators that differ by an inert body: the same events, TE to rounding grown by the
  // rattle (1.2e-14 m measured); 1e-11 m is far below any model difference (a wrong carrier, drag
  // or inertia moves the TE by micrometres within a cycle).
  CHECK(worst <= 1e-11);
}

TEST_CASE("fixed shaft: at tier 3 the standing shaft carries its loose gear's bearing and stays",
          "[solver][train]") {
  // Tier 3: the carrier's node holds g4's bearing laterally (radial forces pass), but no torque
  // reaches its rotation: its angle stays at rest to rounding while g4 rattles.
  const TrainSpec spec = StandingCarrier(1500.0);
  const GearTrain train = BuildGearTrain(spec);
  const TrainTables t = BuildTrainTablesAtTier(spec, train, Tier::kTier3, {});
  REQUIRE(t.tier == Tier::kTier3);
  const auto [z0, s0] = TrainStaticState(t);
  TrainStepper stepper(t, {}, z0, s0);
  const Eigen::RowVectorXd carrier = t.body_angles.row(2);
  const double period = t.meshes[0].period;
  double worst = 0.0, loose = 0.0;
  for (int k = 1; k <= 160; ++k) {
    REQUIRE(stepper.Run(k * period / 8.0));
    worst = std::max(worst, std::abs(carrier.dot(stepper.state().head(t.n))));
    loose = std::max(loose, std::abs(t.body_angles.row(3).dot(stepper.state().head(t.n))));
  }
  INFO("carrier angle up to " << worst << " rad, g4's up to " << loose << " rad; "
                              << stepper.summary().events << " contact events");
  REQUIRE(stepper.summary().events > 10);
  // g4 turns with the train (0.35 rad measured) while the carrier's rotation, decoupled from
  // every force, keeps the static state's (0) to rounding: 1e-12 rad allowed, a coupling of any
  // kind would move it by the loose gear's order.
  CHECK(loose > 1e-5);
  CHECK(worst <= 1e-12);
}

TEST_CASE("fixed shaft: certified jumps leave the standing rotation out and keep it at rest",
          "[solver][train]") {
  // The loaded two-stage reducer (every mesh in drive contact) with a loose gear g5 driven by g1
  // against a drag that keeps it in contact, idling on a standing shaft: the period map has the
  // standing rotation's two unit multipliers, which the quotient removes, so the map is built,
  // jumps, and equals the stepped run.
  TrainSpec spec = testing::TwoStageTrain(300.0, 100.0, 300.0);
  spec.shafts.push_back(testing::RigidShaft("carrier", 0.01));
  spec.shafts.back().fixed = true;
  spec.gears.push_back(testing::TrainGearOf("g5", "carrier", 30, Mounting::kLoose));
  spec.meshes.push_back(testing::TrainMeshOf("g1", "g5"));
  spec.operating.loads.push_back({"g5", 20.0});
  const Model s(spec);
  const TrainTables& t = s.tables;
  REQUIRE(t.standing_rotations.cols() == 1);
  // As the reducer's own jump test: the same orbit to rounding, 1e-10 of the TE p-p.
  const auto [stepped, jumped] = testing::CheckJumpsMatchStepping(t);
  // The standing shaft (body 3) is at rest in both.
  CHECK(stepped.state[3] == 0.0);
  CHECK(jumped.state[3] == 0.0);
  CHECK(jumped.state[t.n + 3] == 0.0);
}

}  // namespace
}  // namespace gearnvh
