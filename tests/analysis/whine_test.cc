// Frequency-domain whine (analysis/whine.h) against closed forms: a pair at tier 1 is the 2-DOF
// mesh transfer applied to its static input's Fourier coefficient and to its runout; a rigid spur
// shaft on two bearings carries the mesh force by statics at low frequency; pitch errors' lines
// against a sampled spectrum of the solver's own error input.
#include "gearnvh/analysis/whine.h"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <numbers>

#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/manufacturing_errors.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/reduction/train_reduction.h"
#include "model/test_specs.h"
#include "model/test_trains.h"

using namespace gearnvh;
using gearnvh::testing::ElasticTwoStage;
using gearnvh::testing::StandardPair;

namespace {

using Complex = std::complex<double>;

// The line at `order` (within rounding), or fails.
size_t LineAt(const WhineResult& r, double order) {
  for (size_t l = 0; l < r.lines.size(); ++l) {
    if (std::abs(r.lines[l].order - order) <= 1e-9 * order) return l;
  }
  FAIL("no line at order " << order);
  return 0;
}

// The loaded pair at 1200 rpm of the pinion, 20 segments per cycle, swept 600..6000 rpm.
TrainSpec LoadedPair() {
  GearboxSpec pair = StandardPair(23, 41, 2e-3, 20e-3);
  pair.operating.torque = 40.0;
  pair.operating.speed = 1200.0 * testing::kRpm;
  pair.analysis.segments_per_cycle = 20;
  pair.analysis.speed_sweep = {600.0 * testing::kRpm, 6000.0 * testing::kRpm, 2,
                               AxisScale::kLinear};
  return TrainOf(pair);
}

// The 2-DOF transfer of the pair's mesh: k / (k - w^2 m_e + i w c).
Complex MeshTransfer(const GearTrain& train, const TrainStructure& structure, double w) {
  const TrainMeshModel& mm = train.meshes[0];
  const double ja = train.body_inertia[static_cast<size_t>(mm.body_a)];
  const double jb = train.body_inertia[static_cast<size_t>(mm.body_b)];
  const double ra = mm.geometry.pinion.base, rb = mm.geometry.wheel.base;
  const double me = ja * jb / (ja * rb * rb + jb * ra * ra);
  const double k = mm.stiffness.mean, c = structure.mesh_damping[0];
  return k / (k - w * w * me + Complex(0.0, w * c));
}

// The elastic two-stage train made spur, at 10-20 rpm of its input: far below every lateral mode,
// so its shafts are in static equilibrium; tier 3, the 1x mesh order of every mesh.
std::pair<TrainSpec, WhineOptions> SpurTwoStageAtLowSpeed() {
  TrainSpec spec = ElasticTwoStage();
  for (TrainGear& g : spec.gears) g.gear.helix_angle = 0.0;
  spec.operating.speed = 20.0 * testing::kRpm;
  spec.analysis.speed_sweep = {10.0 * testing::kRpm, 20.0 * testing::kRpm, 2, AxisScale::kLinear};
  WhineOptions options;
  options.tier = Tier::kTier3;
  options.speeds = 2;
  options.mesh_harmonics = 1;
  return {spec, options};
}

}  // namespace

TEST_CASE("whine: a pair at tier 1 is the mesh transfer times its static input's harmonics",
          "[analysis][whine]") {
  const TrainSpec spec = LoadedPair();
  const GearTrain train = BuildGearTrain(spec);
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  WhineOptions options;
  options.speeds = 7;
  options.mesh_harmonics = 3;
  const WhineResult r = RunWhine(spec, options);
  REQUIRE(r.meshes.size() == 1);
  CHECK(r.bearings.empty());  // tier 1
  // The static input per segment (e_j + F / k_j) and its harmonic k in closed form, written
  // here with cos and sin: X_k = (1 / (pi k)) sum_j d_j [sin(2 pi k t) + i cos(2 pi k t)]_b^e.
  const TrainMeshModel& mm = train.meshes[0];
  for (int k = 1; k <= 3; ++k) {
    Complex x = 0.0;
    for (const MeshSegment& s : mm.segmentation.segments) {
      const double d = s.unloaded_error + mm.cycle.load / s.drive.stiffness;
      const double a = 2.0 * std::numbers::pi * k;
      x += d * Complex(std::sin(a * s.tau_end) - std::sin(a * s.tau_begin),
                       std::cos(a * s.tau_end) - std::cos(a * s.tau_begin));
    }
    x /= std::numbers::pi * k;
    const size_t line = LineAt(r, 23.0 * k);
    for (size_t s = 0; s < r.speed_rad_s.size(); ++s) {
      const double w = 23.0 * k * r.speed_rad_s[s];
      const Complex te = MeshTransfer(train, structure, w) * x;
      // Both are the same exact arithmetic on a 2-DOF system (LU of 2 x 2 after the reduction's
      // rigid tier-1 basis): rounding, 1e-9 for the reduction's projections.
      CHECK(r.meshes[0].te_amplitude_m[line][s] == Approx(std::abs(te)).epsilon(1e-9));
    }
  }
}

TEST_CASE("whine: a pinion's runout is a line at 1x its shaft through the mesh transfer",
          "[analysis][whine]") {
  TrainSpec spec = LoadedPair();
  spec.gears[0].gear.runout = Runout{12e-6, 0.7};
  const GearTrain train = BuildGearTrain(spec);
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  WhineOptions options;
  options.speeds = 5;
  const WhineResult r = RunWhine(spec, options);
  const size_t line = LineAt(r, 1.0);
  CHECK(r.lines[line].kind == WhineLineKind::kShaftOrder);
  for (size_t s = 0; s < r.speed_rad_s.size(); ++s) {
    const double te = std::abs(MeshTransfer(train, structure, r.speed_rad_s[s])) * 12e-6;
    CHECK(r.meshes[0].te_amplitude_m[line][s] == Approx(te).epsilon(1e-9));
  }
}

TEST_CASE("whine: pitch-error lines match the spectrum of the solver's own error input",
          "[analysis][whine]") {
  TrainSpec spec = LoadedPair();
  std::vector<double> pitch(23, 0.0);
  pitch[4] = 8e-6;
  pitch[5] = 8e-6;
  pitch[11] = -3e-6;
  spec.gears[0].gear.pitch_errors = pitch;
  const GearTrain train = BuildGearTrain(spec);
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  const TrainMeshModel& mm = train.meshes[0];
  // The solver's error input (MeshErrorExcitation: per cycle and segment the pairs' weighted
  // deviations) over one pinion revolution, sampled on a fine grid, and its DFT at shaft order n.
  const MeshErrorExcitation errors(mm.pair, mm.segmentation);
  const int per_cycle = 4000;
  const auto sampled = [&](int n) {
    Complex x = 0.0;
    for (long c = 0; c < 23; ++c) {
      size_t j = 0;
      for (int i = 0; i < per_cycle; ++i) {
        const double tau = (i + 0.5) / per_cycle;
        while (mm.segmentation.segments[j].tau_end <= tau) ++j;
        const double e = errors.SegmentMean(c, static_cast<int>(j), 0.0, 1.0);
        x += e * std::exp(Complex(0.0, -2.0 * std::numbers::pi * n * (c + tau) / 23.0));
      }
    }
    return 2.0 * x / (23.0 * per_cycle);
  };
  WhineOptions options;
  options.speeds = 3;
  options.sideband_orders = 2;
  const WhineResult r = RunWhine(spec, options);
  // Lines at shaft orders 1, 2 and the sidebands 21, 22, 24, 25 of the 1x mesh.
  for (int n : {1, 2, 21, 22, 24, 25}) {
    const size_t line = LineAt(r, n);
    const double w = n * r.speed_rad_s[1];
    const double te = std::abs(MeshTransfer(train, structure, w) * sampled(n));
    // Midpoint sampling of a piecewise-constant signal: each jump costs O(1 / per_cycle) of its
    // size in the coefficient; 1e-3 of the amplitude at 4000 samples per cycle.
    CHECK(r.meshes[0].te_amplitude_m[line][1] == Approx(te).epsilon(1e-3));
  }
}

TEST_CASE("whine: a rigid spur shaft on two bearings carries the mesh force by statics",
          "[analysis][whine]") {
  // The elastic two-stage train made spur, g1 moved to 20 mm on its rigid input shaft, whose
  // bearings at 0 and L = 80 mm have radial springs k and tilt springs k_t. At a low speed the
  // shaft is in static equilibrium under the mesh force F at a = 20 mm: with u its deflection at
  // the first bearing and theta its tilt (in the force's plane),
  //   k u + k (u + theta L) = F,   k (u + theta L) L + 2 k_t theta = F a,
  // so the bearings carry k u and k (u + theta L) (the lever rule 3/4 : 1/4, moved ~1e-3 by the
  // tilt springs). A wrong sign of a bearing's offset would swap the shares.
  auto [spec, options] = SpurTwoStageAtLowSpeed();
  spec.gears[0].at = 0.02;
  const WhineResult r = RunWhine(spec, options);
  const size_t line = LineAt(r, 20.0);
  std::vector<const WhineBearing*> input;
  for (const WhineBearing& b : r.bearings) {
    if (b.shaft == "input") input.push_back(&b);
  }
  REQUIRE(input.size() == 2);
  const double k = spec.shafts[0].bearings[0].radial_stiffness;
  const double kt = spec.shafts[0].bearings[0].tilt_stiffness, length = 0.08, a = 0.02;
  Eigen::Matrix2d statics;
  statics << 2.0 * k, k * length, k * length, k * length * length + 2.0 * kt;
  const Eigen::Vector2d unit = statics.lu().solve(Eigen::Vector2d(1.0, a));  // u, theta per N
  const double share[2] = {k * unit[0], k * (unit[0] + unit[1] * length)};
  CHECK(share[0] == Approx(0.75).epsilon(5e-3));
  for (size_t s = 0; s < 2; ++s) {
    const double mesh = r.meshes[0].force_amplitude_n[line][s];
    REQUIRE(mesh > 0.0);
    for (int j = 0; j < 2; ++j) {
      const auto& f = input[static_cast<size_t>(j)]->force_amplitude_n[line];
      const double radial = std::hypot(f[0][s], f[1][s]);
      // The inertia forces at 7 Hz against lateral modes above 1 kHz: (f / f_n)^2 < 1e-4.
      CHECK(radial == Approx(share[j] * mesh).epsilon(1e-4));
    }
  }
}

TEST_CASE("whine: options are checked by name", "[analysis][whine]") {
  WhineOptions options;
  options.speeds = 1;
  CHECK_THROWS_WITH(options.Validate(),
                    Catch::Contains("--speeds") && Catch::Contains("from 2 to 100000"));
  options.speeds = 10;
  options.mesh_harmonics = 0;
  CHECK_THROWS_WITH(options.Validate(), Catch::Contains("--harmonics"));
}

TEST_CASE("whine: equals the exact time-domain solver on a mesh of constant stiffness",
          "[analysis][whine]") {
  // Tier 1 (torsional) and tier 3 (every gear DOF on the rigid supports: lateral, axial and tilt
  // modes in the response).
  const Tier tier = GENERATE(Tier::kTier1, Tier::kTier3);
  // The mesh written wheel first: power then flows from its second gear to its first, and the
  // load sits on the back flank.
  const bool reversed = GENERATE(false, true);
  // A constant stiffness makes the time-domain model LTI in contact: the same model as `mean`.
  // Sources superposed at one order check their relative phases and signs: the user's STE with
  // the pitch errors at the mesh orders, the pinion's runout with an engine order at order 1.
  GearboxSpec pair = StandardPair(23, 41, 2e-3, 20e-3);
  pair.operating.torque = 40.0;
  pair.operating.speed = 1200.0 * testing::kRpm;
  pair.mesh.stiffness = FourierStiffness{3e8, {}, {}};
  pair.mesh.static_transmission_error = {{2e-6, 0.5e-6}, {0.3, -0.2}};
  pair.pinion.runout = Runout{3e-6, 0.4};
  pair.pinion.pitch_errors.assign(23, 0.0);
  pair.pinion.pitch_errors[4] = pair.pinion.pitch_errors[5] = 4e-6;
  pair.pinion.pitch_errors[11] = -2e-6;
  pair.operating.excitation = {{1.0, 300.0, 1.1}};
  pair.analysis.speed_sweep = {1200.0 * testing::kRpm, 1300.0 * testing::kRpm, 2,
                               AxisScale::kLinear};
  TrainSpec spec = TrainOf(pair);
  if (reversed) std::swap(spec.meshes[0].gear_a, spec.meshes[0].gear_b);

  TrainRunOptions run;
  run.tier = tier;
  run.transient = 600;
  run.cycles = 23 * 8;  // 8 pinion revolutions: every line has whole periods
  run.samples_per_cycle = 256;
  run.histories = true;
  const TrainOperatingPoint op = RunTrainOperatingPoint(spec, run);
  REQUIRE(op.ok());
  REQUIRE(op.train.meshes[0].back_flank_loaded == reversed);
  REQUIRE(op.stats.meshes[0].free_time_fraction == 0.0);  // in contact throughout
  const std::vector<double>& te = op.histories.te[0];
  const size_t window = static_cast<size_t>(23 * 4 * 256);  // the last 4 revolutions
  REQUIRE(te.size() >= window);
  const auto coefficient = [&](double order) {
    Complex x = 0.0;
    const double w = order * spec.operating.speed;
    for (size_t s = te.size() - window; s < te.size(); ++s) {
      const double t = op.histories.start + static_cast<double>(s) * op.histories.dt;
      x += te[s] * std::exp(Complex(0.0, -w * t));
    }
    return 2.0 * x / static_cast<double>(window);
  };
  WhineOptions options;
  options.speeds = 2;
  options.tier = tier;
  const WhineResult r = RunWhine(spec, options);
  const std::vector<double> orders{1.0, 2.0, 22.0, 23.0, 24.0, 46.0};
  std::vector<double> expected;
  for (double order : orders) expected.push_back(std::abs(coefficient(order)));
  const double largest = *std::max_element(expected.begin(), expected.end());
  for (size_t o = 0; o < orders.size(); ++o) {
    const double whine = r.meshes[0].te_amplitude_m[LineAt(r, orders[o])][0];
    INFO("tier " << TierName(tier) << (reversed ? ", reversed" : "") << ", order " << orders[o]
                 << ": whine " << whine << " m, time domain " << expected[o]);
    // The time-domain solver holds the runout and the engine order at their means over each
    // segment of its grid (736 per revolution, periodic per mesh cycle): at their own order a
    // sinc loss ~3e-6, and images at the mesh orders +-1 ~1e-6 of them (the sidebands here are
    // 1e-2 of the largest line, so those images are 1e-4 of them: issue "exact inputs"). The
    // sampled DFT folds in the response near 256 mesh orders (~5e-6). 2e-5 of the largest line
    // bounds both; it still resolves each sideband to 0.6 %.
    CHECK(std::abs(whine - expected[o]) <= 2e-5 * largest);
  }
}

TEST_CASE("whine: a torque order on the output shaft equals the exact time-domain solver",
          "[analysis][whine]") {
  // A 20:40 pair of constant mesh stiffness (the time-domain model is then the LTI `mean` model in
  // contact) with one input: order 2 of the OUTPUT shaft's speed as a torque on the output, which
  // is order 1 of the input's. Its TE line from whine against the Fourier coefficient of the
  // exact TE over 4 input revolutions (2 of the output: whole periods). Tier 1, and tier 3,
  // where it acts on the wheel's node through the structure (the output turns -z).
  const Tier tier = GENERATE(Tier::kTier1, Tier::kTier3);
  GearboxSpec pair = StandardPair(20, 40, 2e-3, 20e-3);
  pair.operating.torque = 40.0;
  pair.operating.speed = 1200.0 * testing::kRpm;
  pair.mesh.stiffness = FourierStiffness{3e8, {}, {}};
  pair.analysis.speed_sweep = {1200.0 * testing::kRpm, 1300.0 * testing::kRpm, 2,
                               AxisScale::kLinear};
  TrainSpec spec = TrainOf(pair);
  ExcitationOrder e;
  e.kind = ExcitationKind::kTorque;
  e.on = "output";
  e.order = 2.0;
  e.amplitude = 6.0;
  e.phase = 0.8;
  spec.operating.excitation = {e};
  TrainRunOptions run;
  run.tier = tier;
  run.transient = 600;
  run.cycles = 20 * 8;
  run.samples_per_cycle = 256;
  run.histories = true;
  const TrainOperatingPoint op = RunTrainOperatingPoint(spec, run);
  REQUIRE(op.ok());
  REQUIRE(op.stats.meshes[0].free_time_fraction == 0.0);
  const std::vector<double>& te = op.histories.te[0];
  const size_t window = static_cast<size_t>(20 * 4 * 256);
  REQUIRE(te.size() >= window);
  Complex x = 0.0;
  const double w = spec.operating.speed;  // order 2 of the output = order 1 of the input
  for (size_t k = te.size() - window; k < te.size(); ++k) {
    const double t = op.histories.start + static_cast<double>(k) * op.histories.dt;
    x += te[k] * std::exp(Complex(0.0, -w * t));
  }
  const double expected = std::abs(2.0 * x / static_cast<double>(window));
  WhineOptions options;
  options.speeds = 2;
  options.tier = tier;
  const WhineResult r = RunWhine(spec, options);
  const double whine = r.meshes[0].te_amplitude_m[LineAt(r, 1.0)][0];
  INFO("tier " << TierName(tier) << ": whine " << whine << " m, time domain " << expected);
  REQUIRE(expected > 1e-9);  // the order moves the mesh (1.1e-7 m here)
  // The exact solver carries the order exactly; the sampled DFT folds in the response near 256
  // mesh orders and the transient's remainder: 1e-4 of the line (the sign or the frequency
  // wrong, or the order on the input instead, would miss by its whole size).
  CHECK(whine == Approx(expected).epsilon(1e-4));
}

TEST_CASE(
    "simulate's bearing forces: the housing carries no net force, and the lines are the window's "
    "spectrum",
    "[analysis][whine]") {
  // The loaded spur two-stage train on rigid shafts at tier 3 (every gear DOF on the default
  // supports, lateral modes damped ~4 %), no excitation, its loose gear held in contact by a 5 N m
  // drag: after the transient the periodic steady state, recorded over one common period. The
  // mesh forces are internal and the loads are torques, so the supports' mean forces sum to zero
  // in x, y and z: the means are the exact integrals of the polynomial pieces, and over a whole
  // period the mean acceleration vanishes. Rounding in sums of ~100 N forces leaves ~1e-13; 1e-9
  // of the largest mean bounds it and the orbit's periodicity. (With the file's 0.2 N m the loose
  // gear rattles, its momentum differs between the window's ends, and the sum is that change over
  // the window, ~1e-5 of the largest mean; the uniform samples' mean misses by ~1e-2 on the
  // elastic two-stage train, the mesh stiffness steps putting force images above the sampling
  // rate.)
  TrainSpec spec = testing::RigidTwoStage();
  for (TrainGear& g : spec.gears) g.gear.helix_angle = 0.0;
  spec.operating.loads = {{"output", 30.0}, {"g5", 5.0}};
  TrainRunOptions run;
  run.tier = Tier::kTier3;
  run.transient = 400;
  const GearTrain train = BuildGearTrain(spec);
  const TrainTables probe = BuildTrainTables(spec, train);
  run.cycles = std::lround(probe.common_period / probe.meshes.front().period);
  REQUIRE(std::abs(run.cycles * probe.meshes.front().period - probe.common_period) <=
          1e-12 * probe.common_period);
  run.bearing_forces = true;
  run.histories = true;
  const TrainOperatingPoint op = RunTrainOperatingPoint(spec, run);
  REQUIRE(op.ok());
  for (const TrainMeshStatistics& m : op.stats.meshes) REQUIRE(m.free_time_fraction == 0.0);
  REQUIRE(op.bearing_forces.size() == op.tables.bearings.size());
  REQUIRE(op.bearing_forces.size() == 3);  // a default support per shaft
  std::array<double, 3> sum{}, largest{};
  for (const TrainBearingForce& f : op.bearing_forces) {
    for (size_t d = 0; d < 3; ++d) {
      sum[d] += f.mean[d];
      largest[d] = std::max(largest[d], std::abs(f.mean[d]));
      CHECK(f.min[d] <= f.mean[d]);
      CHECK(f.mean[d] <= f.max[d]);
      CHECK(f.rms[d] <= std::max(f.max[d] - f.mean[d], f.mean[d] - f.min[d]));
    }
    REQUIRE(f.lines.size() == 3 * op.tables.meshes.size());
  }
  const double scale = std::max({largest[0], largest[1], largest[2]});
  REQUIRE(scale > 100.0);  // the reactions of a loaded train
  for (size_t d = 0; d < 3; ++d) {
    INFO("direction " << d << ": sum " << sum[d] << " N of " << scale << " N");
    CHECK(std::abs(sum[d]) <= 1e-9 * scale);
  }
  // Each reported line is the Hann-windowed amplitude 2 |sum (x_s - mean) w_s e^(-i w t_s)| /
  // sum w_s of the window's samples (the record's last common period here) at its mesh harmonic,
  // summed directly at that frequency: the FFT's bin and scale against a plain sum (rounding of
  // ~1e3 samples of ~100 N, 1e-9 of the largest line bounds it).
  REQUIRE(op.sideband_window_common_periods == 1);
  const auto window = static_cast<size_t>(std::llround(op.tables.common_period / op.histories.dt));
  double largest_line = 0.0;
  for (const TrainBearingForce& f : op.bearing_forces) {
    for (const TrainBearingForce::Line& l : f.lines) {
      largest_line = std::max({largest_line, l.amplitude[0], l.amplitude[1], l.amplitude[2]});
    }
  }
  REQUIRE(largest_line > 1.0);  // N: the stiffness variation's force at the mesh frequencies
  for (size_t b = 0; b < op.bearing_forces.size(); ++b) {
    for (size_t d = 0; d < 3; ++d) {
      const std::vector<double>& x = op.histories.bearing_force[3 * b + d];
      REQUIRE(x.size() >= window);
      const size_t first = x.size() - window;
      double mean = 0.0;
      for (size_t k = first; k < x.size(); ++k) mean += x[k] / static_cast<double>(window);
      for (const TrainBearingForce::Line& l : op.bearing_forces[b].lines) {
        Complex sum_x = 0.0;
        double sum_w = 0.0;
        for (size_t k = 0; k < window; ++k) {
          const double w = 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * static_cast<double>(k) /
                                                 static_cast<double>(window)));
          const double t = static_cast<double>(k) * op.histories.dt;
          sum_x += (x[first + k] - mean) * w *
                   std::exp(Complex(0.0, -2.0 * std::numbers::pi * l.frequency_hz * t));
          sum_w += w;
        }
        INFO("bearing " << b << " direction " << d << " " << l.label);
        CHECK(std::abs(l.amplitude[d] - 2.0 * std::abs(sum_x) / sum_w) <= 1e-9 * largest_line);
      }
    }
  }
}

TEST_CASE("simulate's bearing forces: equal whine's under torque orders, and Parseval holds",
          "[analysis][whine]") {
  // The loaded pair of constant mesh stiffness at tier 3 (lateral, axial and tilt modes in the
  // response), in contact throughout: LTI, so its steady state under torque orders 1 and 3.5 is
  // whine's `mean` response at those orders. The error inputs are left out: the time-domain solver
  // holds them per grid segment, stepping the mesh force (issue "exact inputs"). The held torque
  // loses sinc^2 at its own order (2944 segments per revolution: 2e-6 at order 3.5), and the
  // sampled DFT folds in the response near 256 mesh orders (~1e-7 here); 1e-5 of the largest line
  // bounds both. Parseval: with those two lines the only motion, each bearing direction's exact
  // RMS about the mean is sqrt(sum A^2 / 2) of whine's amplitudes, to the same 1e-5.
  const bool reversed = GENERATE(false, true);
  GearboxSpec pair = StandardPair(23, 41, 2e-3, 20e-3);
  pair.operating.torque = 40.0;
  pair.operating.speed = 1200.0 * testing::kRpm;
  pair.mesh.stiffness = FourierStiffness{3e8, {}, {}};
  pair.operating.excitation = {{1.0, 300.0, 1.1}, {3.5, 200.0, -0.4}};
  pair.analysis.segments_per_cycle = 128;
  pair.analysis.speed_sweep = {1200.0 * testing::kRpm, 1300.0 * testing::kRpm, 2,
                               AxisScale::kLinear};
  TrainSpec spec = TrainOf(pair);
  if (reversed) std::swap(spec.meshes[0].gear_a, spec.meshes[0].gear_b);
  TrainRunOptions run;
  run.tier = Tier::kTier3;
  run.transient = 600;
  run.cycles = 23 * 4;  // 4 pinion revolutions: whole periods of both orders
  run.samples_per_cycle = 256;
  run.histories = true;
  run.bearing_forces = true;
  const TrainOperatingPoint op = RunTrainOperatingPoint(spec, run);
  REQUIRE(op.ok());
  REQUIRE(op.stats.meshes[0].free_time_fraction == 0.0);
  WhineOptions options;
  options.speeds = 2;
  options.tier = Tier::kTier3;
  const WhineResult r = RunWhine(spec, options);
  const std::vector<std::vector<double>>& bearing = op.histories.bearing_force;
  REQUIRE(r.bearings.size() == op.bearing_forces.size());
  REQUIRE(bearing.size() == 3 * r.bearings.size());
  const size_t window = static_cast<size_t>(23 * 4 * 256);
  const std::vector<double> orders{1.0, 3.5};
  double largest = 0.0;
  for (const WhineBearing& b : r.bearings) {
    for (size_t d = 0; d < 3; ++d) {
      for (double order : orders)
        largest = std::max(largest, b.force_amplitude_n[LineAt(r, order)][d][0]);
    }
  }
  REQUIRE(largest > 0.5);  // N: 300 and 200 rad/s^2 on the pinion
  // The two supports carry the mesh's mean force between them: their means sum to zero (rounding
  // in ~1e3 N forces; 1e-9 of the largest bounds it, as for the two-stage train above).
  for (size_t d = 0; d < 3; ++d) {
    const double sum = op.bearing_forces[0].mean[d] + op.bearing_forces[1].mean[d];
    const double scale = std::max(std::abs(op.bearing_forces[0].mean[d]), 1.0);
    INFO("direction " << d << ": mean forces sum to " << sum << " N");
    CHECK(std::abs(sum) <= 1e-9 * scale);
  }
  for (size_t b = 0; b < r.bearings.size(); ++b) {
    for (size_t d = 0; d < 3; ++d) {
      const std::vector<double>& samples = bearing[3 * b + d];
      REQUIRE(samples.size() >= window);
      double square = 0.0;
      for (double order : orders) {
        Complex x = 0.0;
        const double w = order * spec.operating.speed;
        for (size_t s = samples.size() - window; s < samples.size(); ++s) {
          const double t = op.histories.start + static_cast<double>(s) * op.histories.dt;
          x += samples[s] * std::exp(Complex(0.0, -w * t));
        }
        const double time_domain = std::abs(2.0 * x / static_cast<double>(window));
        const double whine = r.bearings[b].force_amplitude_n[LineAt(r, order)][d][0];
        INFO("bearing " << b << " direction " << d << " order " << order << ": whine " << whine
                        << " N, time domain " << time_domain << " N");
        CHECK(std::abs(whine - time_domain) <= 1e-5 * largest);
        square += 0.5 * whine * whine;
      }
      INFO("bearing " << b << " direction " << d << ": exact RMS " << op.bearing_forces[b].rms[d]
                      << " N, Parseval " << std::sqrt(square) << " N");
      CHECK(std::abs(op.bearing_forces[b].rms[d] - std::sqrt(square)) <= 1e-5 * largest);
    }
  }
}

TEST_CASE("whine: the housing's response sums the bearings' forces with their phases",
          "[analysis][whine]") {
  // The spur two-stage train at low speed: the input shaft's two bearings carry equal forces in
  // phase (statics), so transfers +H and -H on their x directions cancel, +H and +H double.
  // Named, not a structured binding: lambdas cannot capture those before clang 16.
  const std::pair<TrainSpec, WhineOptions> fixture = SpurTwoStageAtLowSpeed();
  const TrainSpec& spec = fixture.first;
  const WhineOptions& options = fixture.second;
  const Complex h(2e-3, -1e-3);
  const auto with = [&](const Complex& second, double f_low, double f_high) {
    HousingTransfer table{"table.csv",
                          {{"input", 0, 0, {f_low, f_high}, {h, h}, 2},
                           {"input", 1, 0, {f_low, f_high}, {second, second}, 4}}};
    WhineOptions o = options;
    o.housing = table;
    return RunWhine(spec, o);
  };
  const WhineResult plus = with(h, 0.0, 100.0), minus = with(-h, 0.0, 100.0);
  const size_t line = LineAt(plus, 20.0);
  for (size_t s = 0; s < 2; ++s) {
    const double fx = plus.bearings[0].force_amplitude_n[line][0][s];
    REQUIRE(fx > 0.0);
    // Statics to (f / f_n)^2 ~ 1e-5 of the lateral modes (the bearing-force test's 1e-4).
    CHECK(plus.housing->acceleration_m_s2[line][s] == Approx(2.0 * std::abs(h) * fx).epsilon(1e-4));
    CHECK(minus.housing->acceleration_m_s2[line][s] <= 1e-4 * std::abs(h) * fx);
  }
  // A table that ends below the line's frequency (7 Hz at 20 rpm) gives no response there.
  const WhineResult short_table = with(h, 0.0, 1.0);
  CHECK(std::isnan(short_table.housing->acceleration_m_s2[line][1]));
  // Linear interpolation between two points: at the line's frequency f, (1 - t) H0 + t H1.
  HousingTransfer ramp{"ramp.csv", {{"input", 0, 1, {0.0, 100.0}, {h, 3.0 * h}, 2}}};
  WhineOptions o = options;
  o.housing = ramp;
  const WhineResult r = RunWhine(spec, o);
  for (size_t s = 0; s < 2; ++s) {
    const double f = 20.0 * r.speed_rad_s[s] / (2.0 * std::numbers::pi);
    const double t = f / 100.0;
    const double expected =
        std::abs((1.0 - t) * h + t * 3.0 * h) * r.bearings[0].force_amplitude_n[line][1][s];
    CHECK(r.housing->acceleration_m_s2[line][s] == Approx(expected).epsilon(1e-12));
  }
  // A bearing the gearbox does not have, and tier 1, are refused by name.
  HousingTransfer wrong{"wrong.csv", {{"input", 7, 0, {0.0, 1.0}, {h, h}, 9}}};
  o.housing = wrong;
  CHECK_THROWS_WITH(RunWhine(spec, o), Catch::Contains("wrong.csv") &&
                                           Catch::Contains("input.bearings[7]") &&
                                           Catch::Contains("input.bearings[0]"));
  o.housing = ramp;
  o.tier = Tier::kTier1;
  CHECK_THROWS_WITH(RunWhine(spec, o), Catch::Contains("tier 2 or higher"));
}

TEST_CASE("whine: a pair's one elastic mode at tier 1 is the mesh mode, all its energy in the mesh",
          "[analysis][whine]") {
  // Two rigid bodies joined by the mesh: one elastic mode at sqrt(k / m_e) / 2 pi with all of its
  // strain energy in the mesh spring; critical speeds where each line's frequency meets it.
  const TrainSpec spec = LoadedPair();
  const GearTrain train = BuildGearTrain(spec);
  const TrainMeshModel& mm = train.meshes[0];
  const double ja = train.body_inertia[0], jb = train.body_inertia[1];
  const double ra = mm.geometry.pinion.base, rb = mm.geometry.wheel.base;
  const double me = ja * jb / (ja * rb * rb + jb * ra * ra);
  WhineOptions options;
  options.speeds = 50;
  options.mesh_harmonics = 20;  // lines up to 46 kHz: the mode (8.7 kHz) is inside the range
  const WhineResult r = RunWhine(spec, options);
  REQUIRE(r.modes.size() == 1);
  // A 2 x 2 generalised eigenproblem: rounding.
  CHECK(r.modes[0].frequency_hz ==
        Approx(std::sqrt(mm.stiffness.mean / me) / (2.0 * std::numbers::pi)).epsilon(1e-10));
  CHECK(r.modes[0].MeshEnergy() == Approx(1.0).epsilon(1e-10));
  for (const WhineCriticalSpeed& c : r.critical_speeds) {
    CHECK(c.speed_rad_s * r.lines[c.line].order ==
          Approx(2.0 * std::numbers::pi * r.modes[0].frequency_hz).epsilon(1e-12));
    CHECK(c.speed_rad_s >= r.speed_rad_s.front());
    CHECK(c.speed_rad_s <= r.speed_rad_s.back());
  }
}

TEST_CASE("whine: strain energy shares of an elastic train's modes are shares",
          "[analysis][whine]") {
  WhineOptions options;
  options.tier = Tier::kTier3;
  options.speeds = 5;
  const WhineResult r = RunWhine(ElasticTwoStage(), options);
  REQUIRE_FALSE(r.modes.empty());
  for (const WhineMode& m : r.modes) {
    double sum = m.MeshEnergy();
    for (double e : m.bearing_energy) {
      CHECK(e >= 0.0);
      sum += e;
    }
    // Meshes and bearings hold part of phi^T K phi; the elastic shafts the rest.
    CHECK(sum <= 1.0 + 1e-12);
  }
  // Ranked by the modes' mesh strain energy, non-increasing.
  for (size_t k = 1; k < r.critical_speeds.size(); ++k) {
    CHECK(r.modes[r.critical_speeds[k].mode].MeshEnergy() <=
          r.modes[r.critical_speeds[k - 1].mode].MeshEnergy());
  }
}

TEST_CASE("whine: on rigid shafts the meshes and bearings hold all of a mode's strain energy",
          "[analysis][whine]") {
  // Rigid shafts on their default supports (radial, axial and tilt springs) and two meshes: there
  // is no other spring, so the shares of every mode add up to 1 (rounding of the eigenvectors).
  WhineOptions options;
  options.tier = Tier::kTier3;
  options.speeds = 3;
  options.mesh_harmonics = 20;
  const WhineResult r = RunWhine(testing::TwoStageTrain(150.0, 0.0, 600.0), options);
  REQUIRE(r.modes.size() >= 3);
  REQUIRE(r.bearings.size() == 3);  // one support per shaft
  for (const WhineMode& m : r.modes) {
    double sum = m.MeshEnergy();
    for (double e : m.bearing_energy) sum += e;
    CHECK(sum == Approx(1.0).epsilon(1e-9));
  }
}

TEST_CASE("whine: a result too large for memory is refused before it is built",
          "[analysis][whine]") {
  // 100,000 speeds of a pair with pitch errors on both gears, 20 harmonics and 10 sidebands: a few
  // hundred lines, each speed and line holding the mesh's TE and force, 2 supports' 3 forces and
  // 2 shaft speeds: several GB, over the 2 GB limit, so nothing is solved.
  TrainSpec spec = LoadedPair();
  spec.gears[0].gear.pitch_errors.assign(23, 1e-6);
  spec.gears[0].gear.pitch_errors[3] = 3e-6;
  spec.gears[1].gear.pitch_errors.assign(41, 1e-6);
  spec.gears[1].gear.pitch_errors[7] = 2e-6;
  WhineOptions options;
  options.tier = Tier::kTier3;
  options.speeds = 100000;
  options.mesh_harmonics = 20;
  options.sideband_orders = 10;
  CHECK_THROWS_WITH(RunWhine(spec, options), Catch::Contains("--speeds") && Catch::Contains("GB") &&
                                                 Catch::Contains("--harmonics"));
}
