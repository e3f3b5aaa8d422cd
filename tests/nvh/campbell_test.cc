#include "gearnvh/nvh/campbell.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

namespace gearnvh {
namespace {

// A Jeffcott-type rotor: a disk at mid-span of a symmetric shaft, so translation (x, y) and tilt
// (theta_x, theta_y) decouple. Tilt with gyroscopics: It th'' +- Ip Omega th'_other + kt th = 0,
// whirl frequencies omega = (+-Ip Omega + sqrt(Ip^2 Omega^2 + 4 It kt)) / (2 It) (forward +,
// backward -); translation sqrt(k / m) at every speed.
struct Jeffcott {
  double m = 10.0, k = 4e6, It = 0.05, Ip = 0.09, kt = 4e4;
  LinearRotorModel Model() const {
    LinearRotorModel r;
    r.M = Eigen::Vector4d(m, m, It, It).asDiagonal();
    r.K = Eigen::Vector4d(k, k, kt, kt).asDiagonal();
    r.G = Eigen::MatrixXd::Zero(4, 4);
    r.G(2, 3) = Ip;
    r.G(3, 2) = -Ip;
    return r;
  }
  double Forward(double w) const {
    return (Ip * w + std::sqrt(Ip * Ip * w * w + 4 * It * kt)) / (2 * It) / (2 * std::numbers::pi);
  }
  double Backward(double w) const {
    return (-Ip * w + std::sqrt(Ip * Ip * w * w + 4 * It * kt)) / (2 * It) / (2 * std::numbers::pi);
  }
  double Translation() const { return std::sqrt(k / m) / (2 * std::numbers::pi); }
};

TEST_CASE("Jeffcott rotor: forward/backward whirl split matches the closed form",
          "[nvh][campbell]") {
  const Jeffcott j;
  std::vector<double> speeds;
  for (int i = 1; i <= 60; ++i) speeds.push_back(i * 50.0);  // up to 3000 rad/s
  CampbellOptions opt;
  opt.max_frequency_hz = 1000.0;  // all four modes (the forward tilt reaches 470 Hz)
  const CampbellData d = ComputeCampbell(j.Model(), speeds, {}, opt);
  REQUIRE(d.frequency_hz.size() == 4);
  // Classify tracks by their first-speed frequency: translation (x2), backward tilt, forward tilt.
  // Eigenvalues of a 8x8 non-symmetric eigenproblem: relative accuracy ~1e-12 (cond ~ 1); 1e-9.
  int translation_tracks = 0, forward = -1, backward = -1;
  for (int k = 0; k < 4; ++k) {
    const double f0 = d.frequency_hz[k][0];
    if (std::abs(f0 - j.Translation()) <= 1e-9 * f0) {
      ++translation_tracks;
      // Kept apart at the crossing: the translation track stays flat at every speed.
      for (size_t s = 0; s < speeds.size(); ++s) {
        CHECK(std::abs(d.frequency_hz[k][s] - j.Translation()) <= 1e-9 * j.Translation());
      }
    } else if (std::abs(f0 - j.Forward(speeds[0])) <= 1e-9 * f0) {
      forward = k;
    } else if (std::abs(f0 - j.Backward(speeds[0])) <= 1e-9 * f0) {
      backward = k;
    }
  }
  CHECK(translation_tracks == 2);
  REQUIRE(forward >= 0);
  REQUIRE(backward >= 0);
  for (size_t s = 0; s < speeds.size(); ++s) {
    CHECK(std::abs(d.frequency_hz[forward][s] - j.Forward(speeds[s])) <=
          1e-9 * j.Forward(speeds[s]));
    CHECK(std::abs(d.frequency_hz[backward][s] - j.Backward(speeds[s])) <=
          1e-9 * j.Backward(speeds[s]));
  }
  // The backward tilt mode starts above the translation (142.4 vs 100.7 Hz) and ends below it
  // (41 Hz at 3000 rad/s): the tracks really cross.
  CHECK(j.Backward(speeds.front()) > j.Translation());
  CHECK(j.Backward(speeds.back()) < j.Translation());
}

TEST_CASE("critical speeds are where order lines cross tracked modes", "[nvh][campbell]") {
  const Jeffcott j;
  std::vector<double> speeds;
  for (int i = 1; i <= 200; ++i) speeds.push_back(i * 10.0);
  CampbellOptions opt;
  opt.max_frequency_hz = 1000.0;
  const CampbellData d = ComputeCampbell(j.Model(), speeds, {{"1x", 1.0}}, opt);
  // 1x crosses the translation at Omega = sqrt(k/m) = 632.5 rad/s (twice: x and y) and the
  // forward tilt where omega = Omega: It W^2 - Ip W^2 = kt has no solution for Ip > It; the
  // backward tilt where It W^2 + Ip W^2 = kt: W = sqrt(kt / (It + Ip)) = 534.5 rad/s.
  int translation = 0, backward = 0;
  for (const CriticalSpeed& c : d.critical_speeds) {
    // Linear interpolation between speeds 10 rad/s apart on a line and a smooth curve: the
    // crossing error is O(h^2 f'') ~ 1e-2 rad/s here; 0.05 rad/s.
    if (std::abs(c.speed_rad_s - std::sqrt(j.k / j.m)) <= 0.05) ++translation;
    if (std::abs(c.speed_rad_s - std::sqrt(j.kt / (j.It + j.Ip))) <= 0.05) ++backward;
  }
  CHECK(translation == 2);
  CHECK(backward == 1);
  CHECK(d.critical_speeds.size() == 3);
}

TEST_CASE("every mode below the limit is tracked, a high one through a crossing",
          "[nvh][campbell]") {
  // Three decoupled Jeffcott rotors (12 modes): the third, stiffer one has its backward tilt
  // (modes 9-12 by frequency) cross its translation, above the 8 modes a fixed count would keep.
  std::vector<Jeffcott> rotors(3);
  rotors[1].k = 9e6;
  rotors[1].kt = 9e4;
  rotors[2].k = 4e7;
  rotors[2].kt = 4e5;
  LinearRotorModel model;
  model.M = model.K = model.G = Eigen::MatrixXd::Zero(12, 12);
  for (int r = 0; r < 3; ++r) {
    const LinearRotorModel block = rotors[static_cast<size_t>(r)].Model();
    model.M.block(4 * r, 4 * r, 4, 4) = block.M;
    model.K.block(4 * r, 4 * r, 4, 4) = block.K;
    model.G.block(4 * r, 4 * r, 4, 4) = block.G;
  }
  std::vector<double> speeds;
  for (int i = 1; i <= 80; ++i) speeds.push_back(i * 125.0);  // up to 10000 rad/s
  CampbellOptions opt;
  opt.max_frequency_hz = 2000.0;
  const CampbellData d = ComputeCampbell(model, speeds, {}, opt);
  REQUIRE(d.frequency_hz.size() == 12);
  const Jeffcott& j = rotors[2];
  // The third rotor's backward tilt starts above its translation (450 vs 318 Hz) and ends below.
  REQUIRE(j.Backward(speeds.front()) > j.Translation());
  REQUIRE(j.Backward(speeds.back()) < j.Translation());
  int backward = -1, translation = 0;
  for (size_t k = 0; k < d.frequency_hz.size(); ++k) {
    const double f0 = d.frequency_hz[k][0];
    if (std::abs(f0 - j.Backward(speeds[0])) <= 1e-9 * f0) backward = static_cast<int>(k);
    if (std::abs(f0 - j.Translation()) <= 1e-9 * f0) ++translation;
  }
  REQUIRE(backward >= 0);
  CHECK(translation == 2);
  for (size_t s = 0; s < speeds.size(); ++s) {
    CHECK(std::abs(d.frequency_hz[static_cast<size_t>(backward)][s] - j.Backward(speeds[s])) <=
          1e-9 * j.Backward(speeds[s]));
  }
  // Modes that never come below the limit are not kept: the same rotors with a 400 Hz limit lose
  // the third rotor's forward tilt (500 Hz and rising) but keep its backward tilt.
  opt.max_frequency_hz = 400.0;
  const CampbellData low = ComputeCampbell(model, speeds, {}, opt);
  CHECK(low.frequency_hz.size() < 12);
  bool backward_kept = false;
  for (const auto& f : low.frequency_hz) {
    backward_kept |= std::abs(f[0] - j.Backward(speeds[0])) <= 1e-9 * f[0];
  }
  CHECK(backward_kept);
}

TEST_CASE("modes are labelled with type, whirl and damping ratio", "[nvh][campbell]") {
  // A disk with all six motions: lateral translation (x, y) and tilt (th_x, th_y) with
  // gyroscopics, torsion th_z and axial z, decoupled; translation damped by c.
  const Jeffcott j;
  const double jz = 0.09, kz = 3e5, m_axial = 10.0, k_axial = 2.5e7, c = 400.0;
  LinearRotorModel model;
  model.M = Eigen::VectorXd((Eigen::VectorXd(6) << j.m, j.m, j.It, j.It, jz, m_axial).finished())
                .asDiagonal();
  model.K = Eigen::VectorXd((Eigen::VectorXd(6) << j.k, j.k, j.kt, j.kt, kz, k_axial).finished())
                .asDiagonal();
  model.G = Eigen::MatrixXd::Zero(6, 6);
  model.G(2, 3) = j.Ip;
  model.G(3, 2) = -j.Ip;
  model.C = Eigen::MatrixXd::Zero(6, 6);
  model.C(0, 0) = model.C(1, 1) = c;
  const int classes[6] = {1, 1, 1, 1, 0, 2};  // lateral x4, torsional, axial
  for (int c2 = 0; c2 < 3; ++c2) {
    model.class_mass[static_cast<size_t>(c2)] = Eigen::MatrixXd::Zero(6, 6);
    for (int i = 0; i < 6; ++i) {
      if (classes[i] == c2) model.class_mass[static_cast<size_t>(c2)](i, i) = model.M(i, i);
    }
  }
  // The disk's axis point one unit above the disk moves by (th_y, -th_x): its orbit is the tilt
  // whirl. Spin +1 (the G above is that of a disk spinning about +z).
  LinearRotorModel::Disk disk;
  disk.ux = Eigen::RowVectorXd::Unit(6, 3);
  disk.uy = -Eigen::RowVectorXd::Unit(6, 2);
  model.disks = {disk};
  std::vector<double> speeds;
  for (int i = 1; i <= 20; ++i) speeds.push_back(i * 100.0);
  CampbellOptions opt;
  opt.max_frequency_hz = 1000.0;
  const CampbellData d = ComputeCampbell(model, speeds, {}, opt);
  REQUIRE(d.modes.size() == 6);
  int torsional = 0, axial = 0, forward = 0, backward = 0;
  for (size_t k = 0; k < d.modes.size(); ++k) {
    const ModeInfo& info = d.modes[k];
    const std::vector<double>& f = d.frequency_hz[k];
    INFO("mode " << k << " " << info.Label() << " at " << f.front() << " Hz");
    if (info.type == ModeType::kTorsional) {
      ++torsional;
      CHECK(f.front() == Approx(std::sqrt(kz / jz) / (2 * std::numbers::pi)).epsilon(1e-9));
      CHECK(info.whirl == Whirl::kNone);
    } else if (info.type == ModeType::kAxial) {
      ++axial;
      CHECK(info.whirl == Whirl::kNone);
    } else {
      REQUIRE(info.type == ModeType::kLateral);
      // Physics fixes the sign: forward whirl stiffens with speed, backward softens.
      if (f.back() > 1.01 * f.front()) {
        ++forward;
        CHECK(info.whirl == Whirl::kForward);
      } else if (f.back() < 0.99 * f.front()) {
        ++backward;
        CHECK(info.whirl == Whirl::kBackward);
      } else {
        // Translation: zeta = c / (2 sqrt(k m)) at every speed (no gyroscopic coupling).
        for (double zeta : d.damping_ratio[k]) {
          CHECK(zeta == Approx(c / (2 * std::sqrt(j.k * j.m))).epsilon(1e-9));
        }
      }
    }
  }
  CHECK(torsional == 1);
  CHECK(axial == 1);
  CHECK(forward == 1);
  CHECK(backward == 1);
  ModeInfo coupled;
  coupled.type = ModeType::kCoupled;
  coupled.energy_fraction = {0.45, 0.5, 0.05};
  coupled.whirl = Whirl::kForward;
  CHECK(coupled.Label() == "coupled torsional-lateral, forward whirl");
}

TEST_CASE("gear order lines are mesh orders 1-3 and both shafts' orders 1-2", "[nvh][campbell]") {
  const std::vector<OrderLine> lines = GearOrderLines(27, 43);
  REQUIRE(lines.size() == 7);
  CHECK(lines[0].order == 27.0);
  CHECK(lines[2].order == 81.0);
  CHECK(lines[4].order == Approx(27.0 / 43.0).epsilon(1e-15));
}

TEST_CASE("Campbell order lines carry the file's excitation orders", "[nvh][campbell]") {
  // Order 2 coincides with the pinion's 2x line and joins its label; 1.5 is a line of its own.
  const std::vector<OrderLine> lines =
      GearOrderLines(27, 43, {{2.0, 100.0, 0.0}, {1.5, 50.0, 0.0}});
  REQUIRE(lines.size() == 3 + 4 + 1);
  int joined = 0;
  for (const OrderLine& l : lines) joined += l.label == "2x pinion = excitation 2x" ? 1 : 0;
  CHECK(joined == 1);
  CHECK(lines.back().label == "excitation 1.5x");
  CHECK(lines.back().order == 1.5);
}

}  // namespace
}  // namespace gearnvh
