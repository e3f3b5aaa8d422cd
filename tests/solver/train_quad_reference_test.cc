// The exact train solver against an independent quad-precision integration
// (tests/solver/quad_train_reference.h) on a train whose light loose gear rattles and amplifies
// any error about 10^3 per mesh cycle: there CVODE, the validation's reference, is accurate to
// 1e-8 of the TE only over the first cycles, while V3 stays at rounding amplified.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/quad_train_reference.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

// Input (a, 21) -> layshaft (b, 35; c, 19; e, 25) -> output (d, 37) with the loose gear f (31,
// J = 1.6e-4 kg m^2, 0.2 N m drag) on the output driven by e; module 2 mm, 20 N m on the output,
// 1000 rpm, engine order 2 at 1000 rad/s^2 (the new-user trial of `gearnvh validate`).
TrainSpec LooseGearRattle() {
  TrainSpec t;
  t.name = "loose gear rattle";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {testing::RigidShaft("input", 5e-3), testing::RigidShaft("layshaft", 1.5e-3),
              testing::RigidShaft("output", 0.5)};
  const auto gear = [](const char* name, const char* shaft, int teeth, double face, double bore,
                       Mounting mounting = Mounting::kFixed) {
    TrainGear g = testing::TrainGearOf(name, shaft, teeth, mounting);
    g.gear.module = 2e-3;
    g.gear.face_width = face;
    g.gear.bore_diameter = bore;
    return g;
  };
  t.gears = {gear("a", "input", 21, 18e-3, 20e-3),
             gear("b", "layshaft", 35, 18e-3, 20e-3),
             gear("c", "layshaft", 19, 18e-3, 20e-3),
             gear("d", "output", 37, 18e-3, 20e-3),
             gear("e", "layshaft", 25, 15e-3, 20e-3),
             gear("f", "output", 31, 15e-3, 30e-3, Mounting::kLoose)};
  t.meshes = {testing::TrainMeshOf("a", "b", 80e-6), testing::TrainMeshOf("c", "d", 100e-6),
              testing::TrainMeshOf("e", "f", 100e-6)};
  t.operating.input_shaft = "input";
  t.operating.speed = 1000.0 * 2.0 * std::numbers::pi / 60.0;
  t.operating.loads = {{"output", 20.0}, {"f", 0.2}};
  t.operating.excitation = {{2.0, 1000.0, 0.0}};
  return t;
}

TEST_CASE("train: V3 agrees with a quad-precision integration where CVODE's accuracy ends",
          "[solver][train][reference]") {
  const testing::TrainModel s(LooseGearRattle());
  const TrainTables& t = s.tables;
  const auto [z0, states0] = TrainStaticState(t);
  const double period = t.meshes.front().period;
  constexpr int kCycles = 3, kPerCycle = 64;
  std::vector<double> times;
  for (int k = 1; k <= kCycles * kPerCycle; ++k)
    times.push_back(kCycles * period * k / (kCycles * kPerCycle));
  const testing::QuadTrainResult quad = testing::QuadTrainReference(t).Run(z0, states0, times);
  REQUIRE(quad.te.size() == times.size() * t.meshes.size());
  REQUIRE(quad.events.size() >= 20);  // the loose gear rattles from the first cycle

  const size_t meshes = t.meshes.size();
  double scale = 0.0;
  for (const double te : quad.te) scale = std::max(scale, std::abs(te));
  // max |TE - quad TE| / max |TE| over the first `samples` samples.
  const auto error = [&](const std::vector<double>& te, size_t samples) {
    double worst = 0.0;
    for (size_t k = 0; k < samples * meshes; ++k)
      worst = std::max(worst, std::abs(te[k] - quad.te[k]));
    return worst / scale;
  };

  // V3 (closed forms on tuples entered 3 times, the default, and on every tuple from its first
  // entry) and V2 (decompose_after 0: the dense Taylor path) follow it.
  for (const int decompose_after : {3, 1, 0}) {
    {
      TrainStepperOptions options;
      options.events = decompose_after > 0 ? EventMethod::kSpectral : EventMethod::kTaylor;
      if (decompose_after > 0) options.tables.decompose_after_visits = decompose_after;
      const EventMethod method = options.events;
      TrainStepper stepper(t, options, z0, states0);
      std::vector<double> te;
      std::vector<ContactState> states;
      for (const double time : times) {
        REQUIRE(stepper.Run(time));
        for (const TrainMeshTable& mt : t.meshes) te.push_back(mt.v.dot(stepper.state().head(t.n)));
        states.insert(states.end(), stepper.states().begin(), stepper.states().end());
      }
      INFO(EventMethodName(method)
           << " (decomposed after " << decompose_after << " entries): " << error(te, times.size())
           << " of the TE, " << stepper.summary().dense_pieces << " dense pieces");
      // V3 is exact to rounding, which the rattle amplifies ~10^3 per cycle; the closed forms
      // round ~20x more than the dense path (cond(S)). Tolerances: 1e-12 of the TE over the first
      // cycle (measured 4.4e-14 closed forms, 2.2e-15 dense), 1e-9 over two (2.5e-11, 2.2e-12),
      // and the 1e-8 over three on the default path that simulate and validate run
      // (1.2e-10; the closed forms everywhere: 4.3e-9, rounding amplified, so not asserted).
      CHECK(error(te, kPerCycle) <= 1e-12);
      CHECK(error(te, 2 * kPerCycle) <= 1e-9);
      if (decompose_after != 1) CHECK(error(te, times.size()) <= 1e-8);
      CHECK(states == quad.states);
      CHECK(stepper.summary().events == static_cast<long>(quad.events.size()));
      if (decompose_after == 1) CHECK(stepper.summary().dense_pieces == 0);
    }
  }

  {  // CVODE's error estimate (rtol 1e-13 against 1e-12) bounds its error
    // The premise of validate's trusted window
    // (analysis/include/gearnvh/analysis/train_validation.h): the running maximum of |TE(1e-13) -
    // TE(1e-12)| is at least half that of |TE(1e-13) - quad| (measured: 2.5x larger once above
    // rounding with the excitation held per segment; with the continuous engine order 0.9x over
    // samples 52-61, near 4e-12, then larger again), up to a floor of 1e-12 of the TE (both at
    // rounding during the first cycle: 3e-13 against 2e-13). validate trusts the reference while
    // the estimate is within a tenth of its tolerance, so a factor 2 here keeps it inside.
    std::vector<std::vector<double>> cvode;
    for (const double rtol : {1e-13, 1e-12}) {
      TrainReferenceOptions ro;
      ro.end_time = times.back();
      ro.rtol = rtol;
      ro.sample_interval = times.back() / static_cast<double>(times.size());
      const TrainReferenceResult ref = SimulateTrainReference(t, z0, states0, ro);
      REQUIRE(ref.success);
      std::vector<double> te;
      // CVODE samples from t = 0 and stops short of the end time's sample.
      for (Eigen::Index k = 1; k < ref.te.rows() && k <= static_cast<Eigen::Index>(times.size());
           ++k)
        for (size_t i = 0; i < meshes; ++i) te.push_back(ref.te(k, static_cast<Eigen::Index>(i)));
      cvode.push_back(te);
    }
    const size_t samples = std::min(cvode[0].size(), cvode[1].size()) / meshes;
    REQUIRE(samples + 1 >= times.size());
    INFO("CVODE rtol 1e-13: " << error(cvode[0], samples) << " of the TE");
    double estimate = 0.0;
    for (size_t k = 0; k < samples; ++k) {
      for (size_t i = k * meshes; i < (k + 1) * meshes; ++i)
        estimate = std::max(estimate, std::abs(cvode[0][i] - cvode[1][i]) / scale);
      INFO("sample " << k);
      INFO("error " << error(cvode[0], k + 1) << " estimate " << estimate);
      CHECK(error(cvode[0], k + 1) <= std::max(2.0 * estimate, 1e-12));
    }
    // Over the three cycles CVODE at rtol 1e-13 is off by ~4e-7 of the TE (when written): why
    // validate compares only the trusted part.
  }
}

}  // namespace
}  // namespace gearnvh
