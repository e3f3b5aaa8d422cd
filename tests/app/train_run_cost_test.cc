// The slow-run estimate (app/src/train_operating_point.h, EstimateRunCost) against the solver: its
// sub-step is 1 / (2 rho) with the table cache's own bound rho of the same tuple (TrainSystem::rho,
// both from BoundTupleRate), and a run on the dense path takes the sub-steps those bounds allow.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "config/gearbox_loader.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_stepper.h"
#include "gearnvh/solver/train_tables.h"
#include "model/test_trains.h"
#include "support/run_command.h"
#include "train_operating_point.h"

namespace gearnvh {
namespace {

TrainSpec LinearTrain() {
  const config::LoadedGearbox loaded = config::LoadAnyGearboxFromString(
      testing::ReadWholeFile(std::filesystem::path(GEARNVH_TEST_DATA_DIR) / "linear_train.yaml"));
  REQUIRE(loaded.schema == 2);
  return loaded.train;
}

// The rattler's loose gear g4 at 1e-9 kg m^2 (the slow-run warning's case), without excitation.
TrainSpec TinyLooseGear() {
  TrainSpec spec = testing::RattlerTrain(0.0);
  spec.gears[3].gear.inertia = 1e-9;
  return spec;
}

// Every tuple of every mesh in drive contact (the product of the meshes' segments).
void ForEachDriveTuple(const TrainTables& t, const std::vector<int>& prefix,
                       const std::function<void(const std::vector<int>&)>& visit) {
  if (prefix.size() == t.meshes.size()) return visit(prefix);
  for (int j = 0; j < t.meshes[prefix.size()].segments(); ++j) {
    std::vector<int> next = prefix;
    next.push_back(j);
    ForEachDriveTuple(t, next, visit);
  }
}

// The estimate equals the solver's bound of the tuple at t = 0 exactly (one function, the same
// inputs: no tolerance), and a run that never decomposes (every piece on the dense path), stays
// in drive contact (no event) and neither jumps nor fuses takes N sub-steps with
//   T / max_s substep_s <= N <= T / min_s substep_s + G,
// s over the drive tuples, G the grid segments (each may end with one short sub-step; piece
// boundaries inside a grid segment only come from events, none here).
void CheckAgainstRun(const TrainSpec& spec, double seconds) {
  const TrainTables t = BuildTrainTables(spec, BuildGearTrain(spec));
  const app::RunCostEstimate cost = app::EstimateRunCost(t);
  TrainStepperOptions options;
  options.tables.decompose_after_visits = std::numeric_limits<int>::max();
  options.jumps = false;
  options.fusion_levels = 0;
  TrainSystemCache cache(t, options.tables);
  TupleKey key(static_cast<size_t>(cache.KeyWords()));
  const std::vector<ContactState> drive(t.meshes.size(), ContactState::kDrive);
  const TrainSystem& start = cache.Get(std::vector<int>(t.meshes.size(), 0), drive, key);
  REQUIRE(start.rho > 0.0);
  CHECK(cost.substep_s == 0.5 / start.rho);
  double shortest = std::numeric_limits<double>::infinity(), longest = 0.0;
  ForEachDriveTuple(t, {}, [&](const std::vector<int>& segments) {
    const double s = cache.Get(segments, drive, key).substep;
    shortest = std::min(shortest, s);
    longest = std::max(longest, s);
  });

  const auto [z0, states0] = TrainStaticState(t);
  REQUIRE(states0 == drive);
  TrainStepper stepper(t, options, z0, states0);
  REQUIRE(stepper.Run(seconds));
  const TrainStepperSummary& s = stepper.summary();
  REQUIRE(s.events == 0);
  const double n = static_cast<double>(s.dense_pieces);
  INFO("sub-steps " << n << ", estimate " << seconds / cost.substep_s << ", shortest " << shortest
                    << " s, longest " << longest << " s, estimate's " << cost.substep_s
                    << " s, grid segments " << s.grid_segments);
  CHECK(n >= seconds / longest * (1.0 - 1e-12));
  CHECK(n <= seconds / shortest + static_cast<double>(s.grid_segments));
  // The estimate's tuple is one of them, and its sub-step is never shorter than the solver's
  // there (the solver also bounds the balanced row norm).
  CHECK(start.substep <= cost.substep_s);
  CHECK(start.substep >= shortest);
  CHECK(start.substep <= longest);
}

TEST_CASE("the slow-run estimate is the solver's bound and counts a dense run's sub-steps",
          "[train][warnings]") {
  // The linear train's grid segments (31 us) are shorter than its sub-step (50 us): one sub-step
  // each (measured 640 = G against T / s = 396), so there the count only brackets. The tiny loose
  // gear's sub-steps (44-58 ns) are far shorter than its grid segments: measured 45,220 against
  // the estimate's 42,336 (+7 %, its segment 0 being softer than the mean).
  SECTION("linear train (tests/data)") { CheckAgainstRun(LinearTrain(), 0.02); }
  SECTION("tiny loose gear") { CheckAgainstRun(TinyLooseGear(), 2e-3); }
}

}  // namespace
}  // namespace gearnvh
