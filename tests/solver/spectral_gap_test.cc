#include "gearnvh/solver/spectral_gap.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "gearnvh/solver/exact_solver.h"
#include "model/test_specs.h"
#include "solver/solver_fixture.h"

namespace gearnvh {
namespace {

// A light-load pair with one engine order: its gap moves across the backlash within a segment.
GearboxSpec LightExcitedPair() {
  GearboxSpec spec = testing::StandardPair(27, 43, 2e-3, 15e-3);
  spec.operating.torque = 0.2;
  spec.operating.excitation = {{2.0, 1500.0, 0.0}};
  return spec;
}

constexpr double kEps = std::numeric_limits<double>::epsilon();

// z = [x; v; 1]: x'' = -w^2 (x - rest) + accel. n = 1, m = 3.
Eigen::MatrixXd Oscillator(double w, double rest, double accel) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 3);
  A(0, 1) = 1.0;
  A(1, 0) = -w * w;
  A(1, 2) = w * w * rest + accel;
  return A;
}

TEST_CASE("free flight: the closed-form gap is the parabola and its first root the quadratic's",
          "[solver][spectral]") {
  // x'' = a: all eigenvalues 0, the whole generator is the nilpotent block; g = x - L.
  const double a = -3.0, x0 = 0.0, v0 = 2.0, L = 0.5;
  Eigen::MatrixXd A = Oscillator(0.0, 0.0, a);
  const SpectralDecomposition d = DecomposeGenerator(A, 1, 1.0, 1.0, 1e6);
  REQUIRE(d.info == SpectralDecomposition::Info::kSuccess);
  CHECK(d.zero_size == 3);
  ClosedFormGap gap(d, Eigen::RowVector3d(1.0, 0.0, -L));
  const Eigen::Vector3d z(x0, v0, 1.0);
  gap.Load(d.S_inv * z);
  for (double t : {0.0, 0.25, 0.5, 1.0}) {
    // Exact polynomial identity: a few eps of the terms' size.
    CHECK(std::abs(gap.Value(t) - (x0 + v0 * t + 0.5 * a * t * t - L)) <= 16 * kEps);
    CHECK(std::abs(gap.Rate(t) - (v0 + a * t)) <= 16 * kEps);
  }
  // x rises to 2/3 at t = 2/3 and crosses 0.5 first at t = (2 - sqrt(4 - 3)) / 3 = 1/3.
  const double root = gap.FirstRise(1.0, 1.0);
  CHECK(std::abs(root - 1.0 / 3.0) <= 16 * kEps);
}

TEST_CASE("the precomputed segment end: g(H) and g'(H) equal the closed form's, roots alike",
          "[solver][spectral]") {
  // A damped oscillator with a rest offset (blocks: the constant slot's zero and one complex pair):
  // x = rest + e^{-zeta w t}(...). The end rows u e^{DH} and u D e^{DH} are the same function at
  // t = H evaluated as a dot product: equal to a few eps of the terms' size.
  const double w = 1000.0, rest = 2e-5;
  Eigen::MatrixXd A = Oscillator(w, rest, 0.0);
  A(1, 1) = -0.1 * w;  // damping
  const double horizon = 3e-3;
  const SpectralDecomposition d = DecomposeGenerator(A, 1, w, horizon, 1e6);
  REQUIRE(d.info == SpectralDecomposition::Info::kSuccess);
  const Eigen::RowVector3d row(1.0, 0.0, -1e-5);
  ClosedFormGap plain(d, row), with_end(d, row, horizon);
  const Eigen::Vector3d z(-3e-5, 0.02, 1.0);
  plain.Load(d.S_inv * z);
  with_end.Load(d.S_inv * z);
  const double scale = 1e-4;  // the size of the terms (m): 16 eps of it
  CHECK(std::abs(with_end.EndValue() - plain.Value(horizon)) <= 16 * kEps * scale);
  CHECK(std::abs(with_end.EndRate() - plain.Rate(horizon)) <= 16 * kEps * scale * w);
  // The search over the whole segment uses the end row at H: the same first rise (a few eps H;
  // the crossing of x through 1e-5 on the way up from -3e-5).
  const double a = plain.FirstRise(1.0, horizon), b = with_end.FirstRise(1.0, horizon);
  REQUIRE(a > 0.0);
  CHECK(std::abs(a - b) <= 16 * kEps * horizon);
  // The end rows themselves, against the dense exponential: g(H) = row expm(A H) z.
  const Eigen::Vector3d zH = BalancedExpm(A, horizon, 1, w) * z;
  CHECK(std::abs(with_end.EndValue() - row.dot(zH)) <= 1e-12 * scale);
}

TEST_CASE("a copied closed form is the same function with its own arrays", "[solver][spectral]") {
  // The closed form keeps its arrays in one aligned block: a copy (constructed or assigned) must
  // hold the same numbers in a block of its own. Same operations on the same numbers: equal bit
  // for bit, also after the original is gone.
  const double w = 1000.0, rest = 2e-5, horizon = 3e-3;
  Eigen::MatrixXd A = Oscillator(w, rest, 0.0);
  A(1, 1) = -0.1 * w;
  const SpectralDecomposition d = DecomposeGenerator(A, 1, w, horizon, 1e6);
  REQUIRE(d.info == SpectralDecomposition::Info::kSuccess);
  const Eigen::RowVector3d row(1.0, 0.0, -1e-5);
  const Eigen::Vector3d z(-3e-5, 0.02, 1.0);
  ClosedFormGap reference(d, row, horizon);
  reference.Load(d.S_inv * z);
  auto original = std::make_unique<ClosedFormGap>(d, row, horizon);
  ClosedFormGap constructed(*original);
  ClosedFormGap assigned(d, Eigen::RowVector3d(0.0, 1.0, 0.0));  // another shape first
  assigned = *original;
  original.reset();
  for (ClosedFormGap* copy : {&constructed, &assigned}) {
    copy->Load(d.S_inv * z);
    CHECK(copy->EndValue() == reference.EndValue());
    CHECK(copy->EndRate() == reference.EndRate());
    for (double t : {0.0, 1e-4, 1e-3, horizon}) {
      CHECK(copy->Value(t) == reference.Value(t));
      CHECK(copy->Rate(t) == reference.Rate(t));
    }
    const double root = reference.FirstRise(1.0, horizon);
    REQUIRE(root > 0.0);
    CHECK(copy->FirstRise(1.0, horizon) == root);
    CHECK(copy->ClearOfWall(d.S_inv * z, -1.0, 0.0) ==
          reference.ClearOfWall(d.S_inv * z, -1.0, 0.0));
  }
}

TEST_CASE("oscillator: a brief excursion across the wall is found, a near miss is not",
          "[solver][spectral]") {
  // x = A0 cos(w t): peak A0 at t = 2 pi / w. Wall at L < A0: first root acos(L / A0) ... of the
  // second lobe, since x starts at the peak and falls first. Start at x = -A0 (trough) instead.
  const double w = 1000.0, amp = 1e-5;
  const SpectralDecomposition d = DecomposeGenerator(Oscillator(w, 0.0, 0.0), 1, w, 0.01, 1e6);
  REQUIRE(d.info == SpectralDecomposition::Info::kSuccess);
  REQUIRE(d.blocks.size() == 1);
  CHECK(std::abs(d.blocks[0].omega - w) <= 1e-12 * w);
  const Eigen::Vector3d z(-amp, 0.0, 1.0);
  const double horizon = 2.0 * std::numbers::pi / w;  // one period: peak at pi / w
  // Just below the peak: the excursion lasts 2 acos(L/A)/w ~ 2e-6 of a period, between any
  // reasonable sampling grid points; the root is exact: x = -A cos(w t) = L.
  const double L = amp * (1.0 - 1e-10);
  ClosedFormGap gap(d, Eigen::RowVector3d(1.0, 0.0, -L));
  gap.Load(d.S_inv * z);
  const double root = gap.FirstRise(1.0, horizon);
  const double expected = std::acos(-L / amp) / w;
  REQUIRE(root > 0.0);
  // Near the peak dt = dx / x' with x' ~ w A sqrt(2e-10): the root is determined to
  // eps |x| / |x'| ~ 1.6e-11 s; allow 100x.
  CHECK(std::abs(root - expected) <= 100 * kEps * amp / (w * amp * std::sqrt(2e-10)));
  // Just above the peak: no root anywhere in the period.
  ClosedFormGap above(d, Eigen::RowVector3d(1.0, 0.0, -amp * (1.0 + 1e-9)));
  above.Load(d.S_inv * z);
  CHECK(above.FirstRise(1.0, horizon) < 0.0);
}

TEST_CASE("closed-form gaps and rates equal dense propagation for every segment and state",
          "[solver][spectral]") {
  GearboxSpec spec = testing::StandardPair(27, 43, 2e-3, 15e-3);
  spec.mesh.friction_coefficient = 0.05;
  spec.operating.torque = 0.2;
  spec.operating.excitation = {{2.0, 1500.0, 0.0}};
  const Tier tier = GENERATE(Tier::kTier1, Tier::kTier3);
  const testing::SolverSetup s(spec, tier);
  const SegmentTables& t = s.tables;
  auto [z, state0] = StaticInitialState(t);
  z[t.m - 1] = 50.0;                      // an excitation value
  z.segment(t.n, t.n).setConstant(0.01);  // and a velocity perturbation
  for (int j = 0; j < t.segments(); j += 5) {
    double w_ref = 1.0;
    for (const auto& sys : t.systems[j]) w_ref = std::max(w_ref, ReferenceFrequency(sys.A, t.n));
    const double h = t.SegmentLength(j);
    for (int st = 0; st < 3; ++st) {
      const SegmentSystem& sys = t.systems[j][st];
      const SpectralDecomposition d = DecomposeGenerator(sys.A, t.n, w_ref, h, 1e6);
      INFO("segment " << j << " state " << st << " info " << SpectralInfoName(d.info));
      // Tier 3 in free flight has identical lateral modes of the two gears' y and z directions
      // (isotropic bearings): equal eigenvalues of different blocks, which the decoupling refuses
      // (the solver falls back to V2 there). Every other system must decompose.
      if (tier == Tier::kTier3 && st == static_cast<int>(ContactState::kFree)) {
        CHECK(d.info == SpectralDecomposition::Info::kIllConditioned);
        continue;
      }
      REQUIRE(d.info == SpectralDecomposition::Info::kSuccess);
      ClosedFormGap gap(d, sys.gap_drive);
      const Eigen::VectorXd w = d.S_inv * z;
      gap.Load(w);
      Eigen::VectorXd out(t.m), scratch(t.m);
      for (double f : {0.0, 0.37, 1.0}) {
        const Eigen::VectorXd dense = BalancedExpm(sys.A, f * h, t.n, w_ref) * z;
        PropagateDecoupled(d, w, f * h, out, scratch);
        const Eigen::VectorXd decoupled = d.S * out;
        // Both are exact to rounding of the gap's terms (the unloaded error and the half
        // backlash, ~1e-4 m, times cond(S) ~ 10 and a few eps): 1e-12 of the half backlash.
        CHECK(std::abs(gap.Value(f * h) - sys.gap_drive.dot(dense)) <= 1e-12 * t.half_backlash);
        CHECK(std::abs(sys.gap_drive.dot(decoupled) - sys.gap_drive.dot(dense)) <=
              1e-12 * t.half_backlash);
        // The rate: rounding relative to the largest velocity term w_ref * b.
        CHECK(std::abs(gap.Rate(f * h) - sys.gap_drive_rate.dot(dense)) <=
              1e-12 * w_ref * t.half_backlash);
      }
    }
  }
}

TEST_CASE("the zero cluster's series keeps the terms that matter, not the cluster's size",
          "[solver][spectral]") {
  // A free body's chain slot -> velocity -> angle: B0^3 = 0 exactly, e^{B0 t} = I + t B0 +
  // t^2 B0^2 / 2, so 3 terms, although the minimum examined is the cluster's size + 1 (5).
  Eigen::MatrixXd b0 = Eigen::MatrixXd::Zero(4, 4);
  b0(0, 1) = 1.0;  // angle' = velocity
  b0(1, 2) = 3.0;  // velocity' = 3 slot
  CHECK(ZeroClusterSeriesTerms(b0, 0.5, 5) == 3);
  // The same chain perturbed at rounding level (as a Schur form leaves it): the 1e-17 entries'
  // terms are below 1e-18 of the largest term only from k = 3 on (checked by hand: 1e-17 * 0.5^3
  // / 6 ~ 2e-19 of a largest term 1.0), so still 3.
  Eigen::MatrixXd rounded = b0;
  rounded(2, 0) = 1e-17;
  rounded(3, 1) = -1e-17;
  CHECK(ZeroClusterSeriesTerms(rounded, 0.5, 5) == 3);
  // A genuinely longer chain (B0^4 != 0, B0^5 = 0) keeps all five terms; terms beyond the
  // minimum are kept while they matter: a rotation block with |B0| t = 1 needs ~20.
  Eigen::MatrixXd chain = Eigen::MatrixXd::Zero(5, 5);
  for (int i = 0; i < 4; ++i) chain(i, i + 1) = 1.0;
  CHECK(ZeroClusterSeriesTerms(chain, 0.5, 6) == 5);
  Eigen::MatrixXd rotation = Eigen::MatrixXd::Zero(2, 2);
  rotation(0, 1) = 1.0;
  rotation(1, 0) = -1.0;
  const int rotation_terms = ZeroClusterSeriesTerms(rotation, 1.0, 3);
  // Term k is 1 / k! (every power has entries of size 1): k = 0..19 are kept (1 / 19! = 8e-18
  // is above the cut), k = 20 (4e-19) is the first below it.
  CHECK(rotation_terms == 20);
}

TEST_CASE("nearly equal eigenvalues of different blocks are reported ill-conditioned",
          "[solver][spectral]") {
  // Two oscillators at 1000 and 1000 (1 + 1e-9) rad/s with a strong non-normal coupling: the
  // decoupling X ~ coupling / (lambda1 - lambda2) makes cond(S) ~ 1e9.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6, 6);  // n = 2: [x1 x2 v1 v2 1 s]
  A(0, 2) = A(1, 3) = 1.0;
  A(2, 0) = -1e6;
  A(3, 1) = -1e6 * (1.0 + 2e-9);
  A(2, 1) = 1e5;  // coupling x2 -> x1 only (triangular: eigenvalues unchanged)
  const SpectralDecomposition d = DecomposeGenerator(A, 2, 1000.0, 1e-3, 1e6);
  CHECK(d.info == SpectralDecomposition::Info::kIllConditioned);
}

TEST_CASE("V3 with every decomposition refused falls back to V2 and gives its events",
          "[solver][spectral]") {
  const GearboxSpec spec = testing::IdleRattleSpec();
  const testing::SolverSetup s(spec, Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions v2, refused;
  ApplyLadderMethod(LadderMethod::kV2, v2);
  ApplyLadderMethod(LadderMethod::kV3, refused);
  v2.cycles = refused.cycles = 15;
  refused.spectral_max_condition = 1.0;  // no real decomposition has cond(S) <= 1
  const SolverResult a = SimulateExact(s.tables, z0, state0, v2);
  const SolverResult b = SimulateExact(s.tables, z0, state0, refused);
  // Free flight in tier 1 is all-nilpotent with S = Q orthogonal: cond 1 may pass; the contact
  // states cannot. Decompositions are built on first visit, and the run starts in drive contact
  // (its first impacts come after ~10 cycles), so every segment's drive state was refused.
  CHECK(b.summary.spectral_fallback_systems >= s.tables.segments());
  REQUIRE(!a.trajectory.events.empty());
  // Both locate on the same Taylor polynomials in contact; free flight differs (closed form vs
  // Taylor) by rounding: 1e-9 of a segment.
  testing::CheckSameEvents(a.trajectory, b.trajectory, 1e-9 * s.tables.SegmentLength(0));
}

TEST_CASE("V3 with partial fallback (tier 3) gives V2's events", "[solver][spectral]") {
  // Tier 3's free flight falls back to V2 (equal lateral eigenvalues); contact is closed form.
  const GearboxSpec spec = testing::IdleRattleSpec();
  const testing::SolverSetup s(spec, Tier::kTier3);
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions v2, v3;
  ApplyLadderMethod(LadderMethod::kV2, v2);
  ApplyLadderMethod(LadderMethod::kV3, v3);
  v2.cycles = v3.cycles = 12;
  const SolverResult a = SimulateExact(s.tables, z0, state0, v2);
  const SolverResult b = SimulateExact(s.tables, z0, state0, v3);
  // Only free states fall back (at most one per segment); contact always decomposes.
  CHECK(b.summary.spectral_fallback_systems > 0);
  CHECK(b.summary.spectral_fallback_systems <= s.tables.segments());
  REQUIRE(a.trajectory.events.size() >= 2);
  // Exact to rounding both (the 1e-9 of a segment per event), and the rattle amplifies a
  // difference from one impact to the next: 5e-9 of a segment over these 12 cycles, as in the
  // locator conformance suite (measured 2.2e-9 at the sixth impact).
  testing::CheckSameEvents(a.trajectory, b.trajectory, 5e-9 * s.tables.SegmentLength(0));
}

TEST_CASE("derivative bounds of the closed-form gap hold on every sub-interval",
          "[solver][spectral]") {
  // The search's certificates are only as good as these bounds: |g'| and |g''| sampled densely
  // on [a, b] must never exceed DerivativeBound(a, b, order).
  const Tier tier = GENERATE(Tier::kTier1, Tier::kTier3);
  const testing::SolverSetup s(LightExcitedPair(), tier);
  const SegmentTables& t = s.tables;
  auto [z, state0] = StaticInitialState(t);
  z[t.m - 1] = 50.0;
  z.segment(t.n, t.n).setConstant(0.01);
  const int j = 3;
  const int st = static_cast<int>(ContactState::kDrive);
  const SegmentSystem& sys = t.systems[j][st];
  const double w_ref = ReferenceFrequency(sys.A, t.n);
  const double h = t.SegmentLength(j);
  // Three segment lengths, so that the decaying terms fall noticeably over [0, 3h].
  const SpectralDecomposition d = DecomposeGenerator(sys.A, t.n, w_ref, 3.0 * h, 1e6);
  REQUIRE(d.info == SpectralDecomposition::Info::kSuccess);
  ClosedFormGap gap(d, sys.gap_drive);
  gap.Load(d.S_inv * z);
  for (const auto& [a, b] :
       {std::pair{0.0, 3.0 * h}, std::pair{0.5 * h, 0.75 * h}, std::pair{2.0 * h, 3.0 * h}}) {
    const double bound1 = gap.DerivativeBound(a, b, 1), bound2 = gap.DerivativeBound(a, b, 2);
    double max1 = 0.0, max2 = 0.0;
    for (int k = 0; k <= 400; ++k) {
      const double tk = a + (b - a) * k / 400.0;
      max1 = std::max(max1, std::abs(gap.Rate(tk)));
      max2 = std::max(max2, std::abs(gap.Curvature(tk)));
    }
    INFO("[" << a / h << " h, " << b / h << " h]");
    CHECK(max1 <= bound1);
    CHECK(max2 <= bound2);
    // And not uselessly loose: a bound far above the sampled maximum would make every search
    // bisect to the bottom (the sum of amplitudes can exceed the maximum by the modes' count).
    CHECK(bound1 <= 50.0 * max1);
  }
}

TEST_CASE("the screen of a segment start clears far walls and never one the gap reaches",
          "[solver][spectral]") {
  // ClearOfWall must be sufficient (a cleared wall is not reached on [0, H]: FirstRise finds no
  // root) and useful. The wall is moved by a constant added to the gap row (the constant slot) so
  // that sign * g peaks at q times the spread of g over the segment (sampled densely).
  const Tier tier = GENERATE(Tier::kTier1, Tier::kTier3);
  const testing::SolverSetup s(LightExcitedPair(), tier);
  const SegmentTables& t = s.tables;
  const double floor = 1e-12 * t.half_backlash;
  for (int j = 0; j < t.segments(); j += 7) {
    const SegmentSystem& sys = t.systems[j][static_cast<int>(ContactState::kDrive)];
    const double w_ref = ReferenceFrequency(sys.A, t.n), h = t.SegmentLength(j);
    const SpectralDecomposition d = DecomposeGenerator(sys.A, t.n, w_ref, h, 1e6);
    REQUIRE(d.info == SpectralDecomposition::Info::kSuccess);
    for (double velocity : {0.0, 0.01, 1.0}) {
      auto [z, state0] = StaticInitialState(t);
      z[t.m - 1] = 50.0;
      z.segment(t.n, t.n).setLinSpaced(-velocity, 2.0 * velocity);
      const Eigen::VectorXd w = d.S_inv * z;
      ClosedFormGap base(d, sys.gap_drive, h);
      base.Load(w);
      constexpr int kSamples = 2000;
      std::vector<double> g(kSamples + 1);
      for (int k = 0; k <= kSamples; ++k) g[k] = base.Value(h * k / kSamples);
      const double low = *std::min_element(g.begin(), g.end());
      const double high = *std::max_element(g.begin(), g.end());
      const double spread = high - low + t.half_backlash * 1e-9;
      for (double sign : {1.0, -1.0}) {
        const double top = sign > 0.0 ? high : -low;  // max of sign * g
        for (double q : {-20.0, -3.0, -0.3, 0.05, 0.5}) {
          Eigen::RowVectorXd row = sys.gap_drive;
          row[t.constant_slot()] += sign * (q * spread - top);
          ClosedFormGap gap(d, row, h);
          const bool clear = gap.ClearOfWall(w, sign, floor);
          INFO("segment " << j << " velocity " << velocity << " sign " << sign << " q " << q);
          if (q > 0.0) CHECK_FALSE(clear);  // the sampled gap is beyond the wall
          // The linear bound reaches R H = sum amplitude x rate x H: up to ~4.3 spreads here, where
          // the mesh mode turns ~6 rad per segment (R H ~ (w H / 2) spread); 20 spreads is clear.
          if (q == -20.0) CHECK(clear);
          if (clear) {
            gap.Load(w);
            CHECK(gap.FirstRise(sign, h) < 0.0);
          }
        }
      }
    }
  }
}

TEST_CASE("the screen's curved bound clears a wall just above an oscillation's peak",
          "[solver][spectral]") {
  // x = A cos(w t) on [-H/2, H/2] around its peak, w H = 0.3: x(0) = x(H) = A cos 0.15 =
  // 0.98877 A. The linear bound reaches x(0) + A w H = 1.289 A; the curved one, with C = A w^2,
  // peaks where U0 and UH cross (t = H/2): x(0) + x'(0) H/2 + C H^2/8 = 1.0224 A. So a wall at
  // 1.05 A is cleared (only by the curved bound), one at 0.999 A (crossed) is not.
  const double w = 1000.0, amp = 1e-5, h = 0.3 / w;
  const SpectralDecomposition d = DecomposeGenerator(Oscillator(w, 0.0, 0.0), 1, w, h, 1e6);
  REQUIRE(d.info == SpectralDecomposition::Info::kSuccess);
  const Eigen::Vector3d z(amp * std::cos(0.15), amp * w * std::sin(0.15), 1.0);
  const Eigen::VectorXd wz = d.S_inv * z;
  const double floor = 1e-12 * amp;
  ClosedFormGap far(d, Eigen::RowVector3d(1.0, 0.0, -1.05 * amp), h);
  CHECK(far.ClearOfWall(wz, 1.0, floor));
  ClosedFormGap crossed(d, Eigen::RowVector3d(1.0, 0.0, -0.999 * amp), h);
  CHECK_FALSE(crossed.ClearOfWall(wz, 1.0, floor));
  crossed.Load(wz);
  CHECK(crossed.FirstRise(1.0, h) > 0.0);  // and the search finds the crossing
}

}  // namespace
}  // namespace gearnvh
