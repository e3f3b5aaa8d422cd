// One typed conformance suite over every event locator: on a single pair the three locators of
// event_locator.h (SpectralLocator V3, TaylorLocator V2, DyadicLocator V1 behind ExactStepper), on
// a gear train the train stepper's three event methods (train_stepper.h, TrainStepperOptions::
// events). The cases (conformance_cases.h): the pair on tiers 1, 3 and 5 in idle rattle and in a
// near-grazing impact; a rattling train with a loose gear and a near-grazing impact of that gear.
// On every case each method must find the same events at the same times as the two others, reach
// the same states at cycle ends and count the same contact changes; on a rattling pair and the
// rattling train it must step without allocating once its tables are built and carry a tangent
// equal to the finite-difference Jacobian of the map it computes. The methods are independent
// searches on the same exact propagation (closed form in decoupled coordinates, Taylor polynomial
// + Newton, dyadic bisection on dense propagators). The checks are written once, for a case.
#include "gearnvh/solver/event_locator.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/spectral_locator.h"
#include "solver/conformance_cases.h"
#include "support/allocation_counter.h"

namespace gearnvh {
namespace {

using testing::ConformanceCase;
using testing::ConformanceCaseId;
using testing::ConformanceOutcome;

// Largest |a - b| over the positions and over the velocities, each relative to that block's
// largest entry in a (the two blocks have different units).
std::pair<double, double> StateDifference(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                          int n) {
  const double x =
      (a.head(n) - b.head(n)).lpNorm<Eigen::Infinity>() / a.head(n).lpNorm<Eigen::Infinity>();
  const double v = (a.segment(n, n) - b.segment(n, n)).lpNorm<Eigen::Infinity>() /
                   a.segment(n, n).lpNorm<Eigen::Infinity>();
  return {x, v};
}

double RateOf(const EventRecord& e) { return e.gap_rate; }
double RateOf(const TrainEventRecord& e) { return e.event.gap_rate; }

template <typename Record>
double TypicalRate(const std::vector<Record>& events) {
  return testing::TypicalRate(events, [](const Record& e) { return RateOf(e); });
}
using testing::SlowCrossingFactor;

// A case's run by one method, once per process: the suite compares each method with the two
// others, and a run is deterministic (the same binary gives the same outcome).
const ConformanceOutcome& RunOnce(const ConformanceCase& c, EventMethod method) {
  static std::map<std::pair<const ConformanceCase*, EventMethod>, ConformanceOutcome> runs;
  const auto key = std::make_pair(&c, method);
  auto it = runs.find(key);
  if (it == runs.end()) it = runs.emplace(key, c.Run(method)).first;
  return it->second;
}

// The locator types of the pair; on a train the same three methods (kMethod) are options of the
// train stepper.
using Locators = std::tuple<SpectralLocator, TaylorLocator, DyadicLocator>;

TEMPLATE_LIST_TEST_CASE("locator conformance: events, counts and cycle-end states",
                        "[solver][locator][train]", Locators) {
  const ConformanceCaseId id = GENERATE(
      ConformanceCaseId::kPairTier1, ConformanceCaseId::kPairTier1Runout,
      ConformanceCaseId::kPairTier3, ConformanceCaseId::kPairTier5, ConformanceCaseId::kPairGrazing,
      ConformanceCaseId::kTrainRattle, ConformanceCaseId::kTrainGrazing);
  const EventMethod other =
      GENERATE(EventMethod::kSpectral, EventMethod::kTaylor, EventMethod::kDyadic);
  if (other == TestType::kMethod) return;
  const ConformanceCase& c = testing::GetConformanceCase(id);
  INFO(c.name() << ": " << EventMethodName(TestType::kMethod) << " vs " << EventMethodName(other));
  const ConformanceOutcome& a = RunOnce(c, TestType::kMethod);
  const ConformanceOutcome& b = RunOnce(c, other);
  c.CheckPurpose(a);
  // Counts: the same events of every kind.
  CHECK(a.drive_impacts == b.drive_impacts);
  CHECK(a.back_impacts == b.back_impacts);
  CHECK(a.separations == b.separations);
  CHECK(a.grazing == b.grazing);
  // Event times, relative to h (the pair's segment, the train's longest grid segment). V2 and V3
  // are exact to rounding; V1 places an event at the end of its dyadic cell, D 2^-34 <= h 2^-34 =
  // 5.8e-11 h late (the train's V1 may stop bisecting earlier, where the gap's change over a cell
  // is at rounding level: measured 1.9e-9 h on the rattling train, 8e-11 h on its grazing case,
  // V2 against V3 there 1e-13 h). Rattle amplifies a difference from one impact to the next (~40x
  // per 10 cycles of the pair against CVODE, exact_solver_test; ~10x per ms on the train,
  // train_stepper_test), so over the windows here: 5e-9 h between V2 and V3 (measured <= 7.8e-10 h
  // in the release build and 1.005e-9 h in the sanitizer build, whose different rounding the rattle
  // grows the same way; 2.2e-9 h on the pair's runout case once k-bar became the exact cycle mean,
  // which moved the mesh damping by 2.4e-5 and with it the rattle), 2e-8 h with V1 (one cell x 40 x
  // 2 = 4.6e-9 h where the rattle grows 40x in the window; measured <= 1.4e-9 h, but 1.07e-8 h on
  // the runout case in the sanitizer build, whose window grows a difference more). A gap error
  // delta moves a crossing by delta / |g'|: a slow crossing (a separation after long contact, |g'|
  // a hundredth of the typical) is placed less sharply, so the bound is per event, scaled by max(1,
  // v_typ / |g'|) with v_typ the median |g'| of the run (measured up to 1.1e-8 h at |g'| = v_typ /
  // 100 in tier 3, the V3 carry's rounding grown by the rattle; <= 5.3e-10 h elsewhere).
  const bool with_v1 = TestType::kMethod == EventMethod::kDyadic || other == EventMethod::kDyadic;
  const double h = c.segment_length();
  const double time_bound = (with_v1 ? 2e-8 : 5e-9) * h;
  REQUIRE(a.events.size() == b.events.size());
  const double v_typ = TypicalRate(a.events);
  double worst_time = 0.0;
  for (size_t i = 0; i < a.events.size(); ++i) {
    const EventRecord& ea = a.events[i].event;
    const EventRecord& eb = b.events[i].event;
    INFO("event " << i << " of mesh " << a.events[i].mesh << " at " << ea.time << " s");
    CHECK(a.events[i].mesh == b.events[i].mesh);
    CHECK(ea.from == eb.from);
    CHECK(ea.to == eb.to);
    worst_time =
        std::max(worst_time, std::abs(ea.time - eb.time) / SlowCrossingFactor(ea.gap_rate, v_typ));
  }
  // Cycle-end states: positions and velocities, each relative to its block.
  double worst_x = 0.0, worst_v = 0.0;
  REQUIRE(a.cycle_ends.size() == b.cycle_ends.size());
  for (size_t k = 0; k < a.cycle_ends.size(); ++k) {
    const auto [x, v] = StateDifference(a.cycle_ends[k], b.cycle_ends[k], c.positions());
    worst_x = std::max(worst_x, x);
    worst_v = std::max(worst_v, v);
  }
  INFO("events " << a.events.size() << ", worst scaled time " << worst_time / h << " h, positions "
                 << worst_x << ", velocities " << worst_v);
  CHECK(worst_time <= time_bound);
  // The states follow the event times: an event dt late moves the state by |f+ - f-| dt, which
  // the rattle amplifies as above; relative per block, as the case states.
  const double state_bound = c.state_bound(with_v1);
  CHECK(worst_x <= state_bound);
  CHECK(worst_v <= state_bound);
}

TEMPLATE_LIST_TEST_CASE(
    "locator conformance: stepping does not allocate once the tables are built, with and "
    "without a tangent",
    "[solver][locator][train][allocation]", Locators) {
  const ConformanceCaseId id =
      GENERATE(ConformanceCaseId::kPairTier1, ConformanceCaseId::kTrainRattle);
  const bool with_tangent = GENERATE(false, true);
  const ConformanceCase& c = testing::GetConformanceCase(id);
  INFO(c.name() << ": " << EventMethodName(TestType::kMethod)
                << (with_tangent ? " with" : " without") << " tangent");
  const testing::AllocationRun run = c.WarmRun(TestType::kMethod, with_tangent);
  // The counter sees operator new and (outside sanitizer builds) malloc, so Eigen's heap too.
  if (c.keeps_tables(TestType::kMethod)) CHECK(run.allocations == 0);
  CHECK(run.events > 10);  // the event path was exercised
}

TEMPLATE_LIST_TEST_CASE("locator conformance: the tangent equals a finite-difference Jacobian",
                        "[solver][locator][train][tangent]", Locators) {
  // The tangent (segment maps and saltation matrices) against Richardson-extrapolated central
  // differences of the method's own map, over a window with contact changes (the case states its
  // window and bound).
  const ConformanceCaseId id =
      GENERATE(ConformanceCaseId::kPairTier1, ConformanceCaseId::kTrainRattle);
  const ConformanceCase& c = testing::GetConformanceCase(id);
  INFO(c.name() << ": " << EventMethodName(TestType::kMethod));
  const testing::TangentComparison cmp = c.CompareTangent(TestType::kMethod);
  REQUIRE(cmp.found);
  REQUIRE(cmp.tangent.cols() == cmp.finite_difference.cols());
  for (Eigen::Index i = 0; i < cmp.tangent.cols(); ++i) {
    INFO(cmp.detail << ", column " << i << ", bound " << cmp.bound << "\n"
                    << cmp.tangent << "\nvs\n"
                    << cmp.finite_difference);
    CHECK((cmp.tangent.col(i) - cmp.finite_difference.col(i)).norm() <=
          cmp.bound * cmp.tangent.col(i).norm());
  }
}

// ---------------------------------------------------------------------------------------------
// The pair's locators alone: V3's carry, and DoStep driven through the interface.

TEST_CASE("V3 carried in decoupled coordinates equals V3 stepped through z and Phi",
          "[solver][locator][carry]") {
  // SpectralLocator hands a segment without an event to the next one as C_j w (spectral_locator.h)
  // instead of Phi z followed by S^-1 z. Both are exact propagations; they differ by rounding
  // amplified by the decompositions' conditioning (the carry's first-order bound is reported).
  const ConformanceCaseId c =
      GENERATE(ConformanceCaseId::kPairTier1, ConformanceCaseId::kPairTier1Runout,
               ConformanceCaseId::kPairTier3, ConformanceCaseId::kPairTier5,
               ConformanceCaseId::kPairGrazing);
  INFO(testing::GetConformanceCase(c).name());
  const testing::SolverSetup& s = testing::PairSetup(c);
  const testing::PairRun carried = testing::RunPair(EventMethod::kSpectral, c);
  const testing::PairRun dense = testing::RunPair(EventMethod::kSpectral, c, 0.0);
  CHECK(dense.summary.carried_systems == 0);
  CHECK(carried.summary.carried_systems > 0);
  CHECK(carried.summary.carry_error_bound <= SolverOptions{}.carry_max_error);
  CHECK(carried.summary.matvecs < dense.summary.matvecs);
  CHECK(carried.summary.drive_impacts == dense.summary.drive_impacts);
  CHECK(carried.summary.back_impacts == dense.summary.back_impacts);
  CHECK(carried.summary.separations == dense.summary.separations);
  CHECK(carried.summary.grazing == dense.summary.grazing);
  REQUIRE(carried.events.size() == dense.events.size());
  const double h = s.tables.SegmentLength(0);
  const double v_typ = TypicalRate(dense.events);
  double worst_time = 0.0, worst_x = 0.0, worst_v = 0.0;
  for (size_t i = 0; i < carried.events.size(); ++i) {
    CHECK(carried.events[i].to == dense.events[i].to);
    worst_time = std::max(worst_time, std::abs(carried.events[i].time - dense.events[i].time) /
                                          SlowCrossingFactor(dense.events[i].gap_rate, v_typ));
  }
  for (size_t k = 0; k < carried.cycle_ends.size(); ++k) {
    const auto [x, v] = StateDifference(carried.cycle_ends[k], dense.cycle_ends[k], s.tables.n);
    worst_x = std::max(worst_x, x);
    worst_v = std::max(worst_v, v);
  }
  INFO("carry: " << carried.summary.carried_systems << " pairs, bound "
                 << carried.summary.carry_error_bound << ", worst scaled time " << worst_time / h
                 << " h, positions " << worst_x << ", velocities " << worst_v);
  // The same bounds as between the locators above (rounding amplified by the rattle over 10
  // cycles; measured: scaled times <= 2.2e-10 h in the release build and 1.005e-9 h in the
  // sanitizer build, positions <= 4.1e-10, velocities <= 1.1e-11).
  CHECK(worst_time <= 2e-9 * h);
  CHECK(worst_x <= 1e-9);
  CHECK(worst_v <= 1e-9);
}

// A minimal EventHandler: switches the contact state and logs event times into a fixed buffer,
// as a stepper of its own would (a train stepper adopts the interface this way).
class LoggingHandler final : public EventHandler {
 public:
  explicit LoggingHandler(LocatorState& state) : state_(state) { times_.reserve(4096); }
  bool Switch(int, const SegmentSystem&, const GapWall& wall, double time, bool) override {
    state_.contact = wall.target;
    if (times_.size() < times_.capacity()) times_.push_back(time);
    return true;
  }
  bool Graze(double) override { return true; }
  const std::vector<double>& times() const { return times_; }

 private:
  LocatorState& state_;
  std::vector<double> times_;
};

TEMPLATE_LIST_TEST_CASE("locator conformance: DoStep alone reproduces the stepper, allocation-free",
                        "[solver][locator][allocation]", Locators) {
  // The locator driven directly through its interface, segment by segment (inputs set at each
  // segment start, the free rotation recentred at each cycle end, as ExactStepper does). The
  // stepper adds no arithmetic of its own to a stepped run, so the event times are the stepper's
  // bit for bit, and DoStep allocates nothing once the locator is built.
  const ConformanceCaseId c =
      GENERATE(ConformanceCaseId::kPairTier1, ConformanceCaseId::kPairTier1Runout,
               ConformanceCaseId::kPairTier3, ConformanceCaseId::kPairTier5);
  INFO(testing::GetConformanceCase(c).name());
  const testing::SolverSetup& s = testing::PairSetup(c);
  const SegmentTables& t = s.tables;
  const testing::PairStart start = testing::PairStartFor(c);
  SolverOptions opt;
  opt.method = SolverMethod::kStepped;
  opt.events = TestType::kMethod;
  opt.record_trajectory = false;
  TestType locator(t, opt);
  CHECK(locator.method() == TestType::kMethod);
  // The stepper's inputs: the excitation from the cycle's input table (sized here, as the stepper's
  // constructor does, so the walk allocates nothing).
  SegmentTables::CyclePhase phase;
  phase.sin.resize(t.excitation.size());
  phase.cos.resize(t.excitation.size());
  phase.excitation.resize(static_cast<size_t>(t.segments()));
  auto walk = [&](LocatorState& state, LoggingHandler& handler) {
    for (long k = 0; k < start.cycles; ++k) {
      for (int j = 0; j < t.segments(); ++j) {
        t.SetInputs(k, j, state.z, phase);
        REQUIRE(locator.DoStep(j, static_cast<double>(k) * t.mesh_period + t.boundaries[j], state,
                               handler));
      }
      const double drift = t.recenter_row.dot(state.z.head(t.n));
      state.z.head(t.n) -= drift * t.rigid_rotation;
    }
  };
  // The walk once outside the counted region: V3 builds a (segment, state)'s decomposition on
  // its first visit.
  LocatorState warm;
  warm.z = start.z;
  warm.contact = start.state;
  warm.allow_carry = true;  // as the stepper on unrecorded cycles without a tangent
  LoggingHandler warm_handler(warm);
  walk(warm, warm_handler);
  LocatorState state;
  state.z = start.z;
  state.contact = start.state;
  state.allow_carry = true;
  LoggingHandler handler(state);
  {
    testing::AllocationCounter counter;
    walk(state, handler);
    CHECK(counter.count() == 0);
  }
  const testing::PairRun stepped = testing::RunPair(TestType::kMethod, c);
  REQUIRE(handler.times().size() == stepped.events.size());
  CHECK(handler.times().size() >= 4);
  for (size_t i = 0; i < stepped.events.size(); ++i) {
    // The same state and arithmetic; only the time label start + offset may be contracted
    // differently by the compiler (an FMA): 4 ulps of the time.
    CHECK(std::abs(handler.times()[i] - stepped.events[i].time) <=
          4.0 * std::numeric_limits<double>::epsilon() * stepped.events[i].time);
  }
  CHECK(state.matvecs == stepped.summary.matvecs);
  CHECK((state.z - stepped.cycle_ends.back()).lpNorm<Eigen::Infinity>() == 0.0);
}

}  // namespace
}  // namespace gearnvh
