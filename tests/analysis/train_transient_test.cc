// The slowest decaying mode of a train and the transient warning (analysis/train_transient.h).
#include "gearnvh/analysis/train_transient.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/gear_train.h"
#include "model/test_trains.h"

namespace gearnvh {
namespace {

// A flywheel (0.12 kg m^2) on a clutch damper of k = 500 N m/rad, c = 0.2 N m s/rad in front of the
// rattler's input (a 20/30 mesh to the layshaft, a loose gear): the clutch damper's mode is far
// below the meshes' (about 12 Hz against kHz).
TrainSpec FlywheelRattler(double stiffness, double damping) {
  TrainSpec spec = testing::RattlerTrain(0.0);
  spec.shafts.insert(spec.shafts.begin(), testing::RigidShaft("flywheel", 0.12));
  TrainCoupling c;
  c.name = "clutch_damper";
  c.shaft_a = "flywheel";
  c.shaft_b = "input";
  c.stiffness = stiffness;
  c.damping = damping;
  spec.couplings = {c};
  spec.operating.input_shaft = "flywheel";
  return spec;
}

TEST_CASE("the slowest decaying mode is the clutch damper's, as two inertias on a spring-damper",
          "[analysis][train]") {
  // The meshes are ~1e4 times stiffer than the coupling, so the gearbox moves as one inertia J2
  // (the input, the layshaft referred by (20/30)^2, the loose gear by its ratio): two inertias on
  // k, c, lambda = -c / 2J + i sqrt(k / J - (c / 2J)^2), J = J1 J2 / (J1 + J2). The meshes'
  // compliance moves it by about k / k_mesh: 1e-3 on frequency and rate.
  const double k = 500.0, c = 0.2;
  const TrainSpec spec = FlywheelRattler(k, c);
  const GearTrain train = BuildGearTrain(spec);
  const TrainTables tables = BuildTrainTables(spec, train);
  double j2 = 0.0;
  for (size_t b = 1; b < train.topology.bodies.size(); ++b) {
    const double ratio = train.topology.bodies[b].speed / train.topology.bodies[1].speed;
    j2 += train.body_inertia[b] * ratio * ratio;
  }
  const double j1 = train.body_inertia[0], j = j1 * j2 / (j1 + j2);
  const double sigma = c / (2.0 * j);
  const double f = std::sqrt(k / j - sigma * sigma) / (2.0 * std::numbers::pi);
  const auto mode = SlowestDecayingMode(tables);
  REQUIRE(mode);
  INFO("closed form " << f << " Hz, " << sigma << " 1/s");
  CHECK(mode->frequency_hz == Approx(f).epsilon(1e-3));
  CHECK(mode->decay_rate == Approx(sigma).epsilon(1e-3));
  // Three decay times are 3 / sigma: a transient of half that is warned about, twice it is not.
  const double period = tables.meshes.front().period;
  const long short_cycles = static_cast<long>(1.5 / sigma / period);
  const std::string warning = TransientDecayWarning(
      tables, static_cast<double>(short_cycles) * period, short_cycles, "--transient");
  CHECK_THAT(warning, Catch::Contains("--transient"));
  const long long_cycles = static_cast<long>(6.0 / sigma / period);
  CHECK(TransientDecayWarning(tables, static_cast<double>(long_cycles) * period, long_cycles,
                              "--transient")
            .empty());
  // Without the coupling's damper only the meshes' damping (which that mode hardly strains) damps
  // it, below a damping ratio of 1e-3: undamped for this purpose (no transient removes it), so the
  // slowest reported is a mesh mode, far above it.
  const TrainSpec undamped = FlywheelRattler(k, 0.0);
  const auto other = SlowestDecayingMode(BuildTrainTables(undamped, BuildGearTrain(undamped)));
  REQUIRE(other);
  CHECK(other->frequency_hz > 10.0 * f);
}

}  // namespace
}  // namespace gearnvh
