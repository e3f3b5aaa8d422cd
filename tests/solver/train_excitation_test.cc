// Engine orders on a gear train are carried exactly, as an exosystem in the augmented state
// (train_tables.h): checked against CVODE integrating the continuous s(t) itself.
#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "model/test_trains.h"
#include "train_model.h"

namespace gearnvh {
namespace {

using testing::TrainModel;

// Every mesh's TE from the static state at `times` (V3, the default options).
std::vector<double> TeAt(const TrainTables& t, const std::vector<double>& times) {
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepper stepper(t, {}, z0, states0);
  std::vector<double> te;
  for (const double time : times) {
    REQUIRE(stepper.Run(time));
    for (const TrainMeshTable& mt : t.meshes) te.push_back(mt.v.dot(stepper.state().head(t.n)));
  }
  return te;
}

double MaxAbsDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  return worst;
}

TEST_CASE("train: an engine order that fits no segment grid is exact against CVODE",
          "[solver][train][excitation]") {
  // Order 100 at 8 segments per mesh cycle on the loaded two-stage train (20 teeth on the input:
  // 5 periods of the order per mesh cycle, 1.6 segments per period). Held at its mean per segment
  // it would keep sinc^2(pi / 1.6) = 0.3 % of its amplitude, aliased; carried exactly it equals
  // the continuous reference. Tolerance 1e-8 of the TE: CVODE at rtol 1e-13 in permanent contact
  // is accurate to ~1e-11 (measured 6.7e-12 against V3, 3.6e-14 between V2 and V3).
  TrainSpec spec = testing::TwoStageTrain(150.0, 2e4, 600.0);
  spec.operating.excitation = {{100.0, 3e3, 0.3}};
  spec.analysis.segments_per_cycle = 8;
  const TrainModel s(spec);
  REQUIRE(s.tables.excitation_states() == 2);
  const double end = 6.0 * s.tables.meshes[0].period;
  const testing::ReferenceAgreement a = testing::AgreeWithReference(s.tables, end);
  INFO("V3 vs CVODE: " << a.worst_reference / a.scale
                       << " of the TE; V2: " << a.worst_v2 / a.scale);
  CHECK(a.reference_events == 0);
  CHECK(a.v3_events == 0);
  CHECK(a.worst_reference <= 1e-8 * a.scale);
  CHECK(a.worst_v2 <= 1e-8 * a.scale);
  // Not vacuous: the order moves the TE by far more than the tolerance.
  spec.operating.excitation.clear();
  const TrainModel quiet(spec);
  std::vector<double> times;
  for (int k = 1; k <= 96; ++k) times.push_back(end * k / 96.0);
  const double effect = MaxAbsDifference(TeAt(s.tables, times), TeAt(quiet.tables, times));
  INFO("the order's effect: " << effect / a.scale << " of the TE");
  CHECK(effect >= 1e-4 * a.scale);
}

TEST_CASE("train: a rattle under a high engine order follows CVODE event by event",
          "[solver][train][excitation]") {
  // The rattler's loose gear under order 23 (11.5 periods per input revolution on a 20-tooth
  // mesh at 16 segments per cycle: 1.4 segments per period). Over the first two mesh cycles the
  // impacts' amplification (~10^3 per cycle) leaves CVODE (rtol 1e-13) accurate to ~1e-10
  // (measured 3.7e-10 with 3 impacts).
  TrainSpec spec = testing::RattlerTrain(1500.0);
  spec.operating.excitation = {{23.0, 3000.0, 0.0}};
  const TrainModel s(spec);
  testing::CheckRattleFollowsReference(
      testing::AgreeWithReference(s.tables, 2.0 * s.tables.meshes[0].period));
}

TEST_CASE("train: an engine order of zero amplitude reproduces the unexcited run to rounding",
          "[solver][train][excitation]") {
  // The exosystem adds two states and the eigenvalues +-i w to every generator; at amplitude 0
  // its states stay 0, so the TE is the unexcited run's up to the decompositions' rounding
  // (cond(S) eps of the state per piece: 1e-12 of the TE leaves room over 40 loaded cycles;
  // measured 1.6e-14).
  TrainSpec spec = testing::TwoStageTrain(150.0, 0.0, 600.0);
  spec.operating.excitation = {{2.0, 0.0, 0.0}};
  const TrainModel zero(spec);
  spec.operating.excitation.clear();
  const TrainModel none(spec);
  REQUIRE(zero.tables.m == none.tables.m + 2);
  std::vector<double> times;
  const double end = 40.0 * none.tables.meshes[0].period;
  for (int k = 1; k <= 320; ++k) times.push_back(end * k / 320.0);
  const std::vector<double> a = TeAt(zero.tables, times), b = TeAt(none.tables, times);
  double scale = 0.0;
  for (const double te : b) scale = std::max(scale, std::abs(te));
  INFO("difference " << MaxAbsDifference(a, b) / scale << " of the TE");
  CHECK(MaxAbsDifference(a, b) <= 1e-12 * scale);
}

}  // namespace
}  // namespace gearnvh
