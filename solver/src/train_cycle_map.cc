#include "gearnvh/solver/train_cycle_map.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <map>

#include "flush_subnormals.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_stepper.h"
#include "taylor_root.h"

namespace gearnvh {
namespace {

// Every grid segment of one common period from t = 0: f(grid); stops after `limit` segments.
// Returns the number walked. `cancel` is polled before each f.
template <typename F>
long ForEachPeriodSegment(const TrainTables& t, long limit, const std::atomic<bool>* cancel,
                          F&& f) {
  const double until = t.common_period * (1.0 - 1e-12);
  long count = 0;
  for (TrainGrid grid(t); grid.start() < until && count < limit; grid.Next(), ++count) {
    ThrowIfCancelled(cancel);
    f(grid);
  }
  return count;
}

// The input slots of the grid segment's start (the orders' states, the errors' means) into z.
void SetGridInputs(const TrainTables& t, const TrainGrid& grid, Eigen::Ref<Eigen::VectorXd> z) {
  t.SetInputs(grid.cycles(), grid.segments(), grid.start(), grid.end() - grid.start(), z);
}

constexpr long kWholePeriod = std::numeric_limits<long>::max();

// Nodes per sub-step for the extrema of its gap polynomials, and the chord's loss 1 / (8 K^2).
constexpr int kNodes = 16;
constexpr double kChordLoss = 1.0 / (8.0 * kNodes * kNodes);

// sum_p c_p x^p.
template <typename V>
double Horner(const V& c, double x) {
  double value = 0.0;
  for (Eigen::Index p = c.size() - 1; p >= 0; --p) value = value * x + c[p];
  return value;
}

}  // namespace

long CountCommonPeriodSegments(const TrainTables& tables, long limit) {
  return ForEachPeriodSegment(tables, limit, nullptr, [](const TrainGrid&) {});
}

TrainCycleMap::TrainCycleMap(const TrainTables& tables, const std::vector<ContactState>& states,
                             double margin_fraction, long grid_segments,
                             const std::atomic<bool>* cancel)
    : t_(tables), states_(states), margin_fraction_(margin_fraction) {
  const int m = t_.m, e = 2 * t_.n;
  dev_.resize(e);
  dev0_.resize(e);
  next_.resize(m);
  dev_complex_.resize(e);
  coeff_.resize(e);
  rebuilt_.resize(e);
  margin_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(t_.meshes.size()));
  bound_ = margin_;
  TupleMemo memo;  // the tuples of one period (a few per cent of its grid segments)
  std::vector<Eigen::MatrixXd> propagators;
  BuildMap(memo, propagators, grid_segments, cancel);
  if (info_ == Info::kSuccess) BuildCertificate(memo, propagators, cancel);
}

void TrainCycleMap::BuildMap(TupleMemo& memo, std::vector<Eigen::MatrixXd>& propagators,
                             long grid_segments, const std::atomic<bool>* cancel) {
  const int n = t_.n, m = t_.m, e = 2 * n;
  const int c = t_.constant_slot();
  phi_ = Eigen::MatrixXd::Identity(m, m);
  Eigen::VectorXd inputs = Eigen::VectorXd::Zero(m);
  const bool keep = static_cast<double>(grid_segments) * m * m * sizeof(double) <= kKeepBytes;
  if (keep) propagators.reserve(static_cast<size_t>(grid_segments));
  ForEachPeriodSegment(t_, kWholePeriod, cancel, [&](const TrainGrid& grid) {
    const std::vector<int>& segments = grid.segments();
    const double h = grid.end() - grid.start();
    // R_g: the input slots are set to the engine orders' states at the segment's start and the
    // manufacturing errors' means (times the constant slot).
    SetGridInputs(t_, grid, inputs);
    for (int slot = t_.input_slot(); slot < m; ++slot) phi_.row(slot) = inputs[slot] * phi_.row(c);
    const Tuple& tuple = Lookup(memo, segments);
    const Eigen::MatrixXd full = BalancedExpm(tuple.A, h, n, tuple.w_ref);
    phi_ = (full * phi_).eval();
    if (keep) propagators.push_back(full);
  });
  // The quotient by the free rotation (position, and velocity unless a drag damps it: the map then
  // carries its decay), and by each fixed shaft's standing rotation, which is as neutral (nothing
  // moves it; Jump keeps it as it is).
  Eigen::VectorXd rp = Eigen::VectorXd::Zero(m), rv = Eigen::VectorXd::Zero(m);
  Eigen::RowVectorXd mp = Eigen::RowVectorXd::Zero(m);
  rp.head(n) = t_.rigid_rotation;
  rv.segment(n, n) = t_.rigid_rotation;
  mp.head(n) = t_.recenter_row;
  mv_ = Eigen::RowVectorXd::Zero(m);
  if (!t_.free_rotation_damped) mv_.segment(n, n) = t_.recenter_row;
  projector_ = Eigen::MatrixXd::Identity(m, m) - rp * mp - rv * mv_;
  standing_ = Eigen::VectorXd::Zero(2 * t_.standing_rotations.cols());
  for (Eigen::Index s = 0; s < t_.standing_rotations.cols(); ++s) {
    const Eigen::VectorXd ms = t_.inertia.cwiseProduct(t_.standing_rotations.col(s));
    projector_.topLeftCorner(n, n) -= t_.standing_rotations.col(s) * ms.transpose();
    projector_.block(n, n, n, n) -= t_.standing_rotations.col(s) * ms.transpose();
  }
  pq_ = projector_ * phi_ * projector_;
  const Eigen::MatrixXd Le = projector_.topLeftCorner(e, e);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(e, e);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(I - pq_.topLeftCorner(e, e) + (I - Le));
  orbit_ = Eigen::VectorXd::Zero(m);
  orbit_[c] = 1.0;
  if (!lu.isInvertible()) {
    info_ = Info::kNoOrbit;
    return;
  }
  orbit_.head(e) = lu.solve(pq_.block(0, c, e, 1));
  velocity_row_ = mv_ * (phi_ - Eigen::MatrixXd::Identity(m, m)) * projector_;
  velocity_drift_ = velocity_row_.dot(orbit_);
  velocity_sum_row_ = velocity_row_.head(e) * lu.inverse();

  const Eigen::EigenSolver<Eigen::MatrixXd> eig(pq_.topLeftCorner(e, e));
  spectral_radius_ = eig.eigenvalues().cwiseAbs().maxCoeff();
  if (!(spectral_radius_ < 1.0)) {
    info_ = Info::kNotContracting;
    return;
  }
  eigenvectors_ = eig.eigenvectors();
  const Eigen::FullPivLU<Eigen::MatrixXcd> vlu(eigenvectors_);
  if (!vlu.isInvertible()) {
    info_ = Info::kDefectiveBasis;
    return;
  }
  eigenvectors_inv_ = vlu.inverse();
  powers_.push_back(pq_.topLeftCorner(e, e));
  for (int l = 1; l < kMaxJumpLog2; ++l) {
    powers_.push_back(powers_.back() * powers_.back());
    internal::FlushSubnormals(powers_.back());
  }
}

void TrainCycleMap::BuildCertificate(TupleMemo& memo,
                                     const std::vector<Eigen::MatrixXd>& propagators,
                                     const std::atomic<bool>* cancel) {
  const int n = t_.n, m = t_.m, e = 2 * n;
  const int meshes = static_cast<int>(t_.meshes.size());
  const int terms = kTaylorTerms + 1;
  Eigen::VectorXd z = orbit_;
  // Y(t) = Phi(t) V, real and imaginary parts side by side (slots zero: Phi(t) keeps them).
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(m, 2 * e);
  Y.topLeftCorner(e, e) = eigenvectors_.real();
  Y.topRightCorner(e, e) = eigenvectors_.imag();
  margin_.setConstant(std::numeric_limits<double>::infinity());
  gain_ = Eigen::MatrixXd::Zero(meshes, e);
  Eigen::MatrixXd rows(meshes * terms, m), E(m, m), term(m, m), next(m, m),
      Q(meshes * terms, 2 * e);
  Eigen::VectorXd f(meshes * terms), zn(m);
  Eigen::MatrixXd Yn(m, 2 * e);
  // ||S y||_inf of a state or mode: the velocities balanced by w_ref as in Lookup's norm.
  const auto balanced_norm = [n, e](const auto& y, double w_ref) {
    return std::max(y.head(n).cwiseAbs().maxCoeff(),
                    std::max(y.segment(n, n).cwiseAbs().maxCoeff() / w_ref,
                             y.tail(y.size() - e).cwiseAbs().maxCoeff()));
  };
  size_t index = 0;
  ForEachPeriodSegment(t_, kWholePeriod, cancel, [&](const TrainGrid& grid) {
    const std::vector<int>& segments = grid.segments();
    const double h = grid.end() - grid.start();
    SetGridInputs(t_, grid, z);
    const Tuple& tuple = Lookup(memo, segments);
    // Tightness asks rho(A) d <= 1 (the chord bounds lose ~(rho d)^2 e^(rho d) / (8 K^2) of an
    // oscillation); the Taylor tail asks q <= kMaxStepNorm.
    const int substeps = std::max({1, static_cast<int>(std::ceil(tuple.rho * h)),
                                   static_cast<int>(std::ceil(tuple.rate * h / kMaxStepNorm))});
    const double d = h / substeps;
    const double tail = taylor_root::Tail(tuple.rate * d, kTaylorTerms);
    if (substeps == 1 && index < propagators.size()) {
      E = propagators[index];  // the map's own expm(A h)
    } else {
      // E = sum_p (A d)^p / p!, the sub-step's propagator (remainder below `tail` relative).
      E.setIdentity();
      term.setIdentity();
      for (int p = 1; p <= kTaylorTerms; ++p) {
        next.noalias() = tuple.A * term;
        term = next * (d / p);
        E += term;
      }
    }
    ++index;
    // rows (mesh j, p) = c_j A^p d^p / p!: mesh j's gap as a polynomial in (tau / d).
    double scale = 1.0;
    for (int p = 0; p < terms; ++p) {
      if (p > 0) scale *= d / p;
      for (int j = 0; j < meshes; ++j)
        rows.row(j * terms + p) = scale * tuple.gap_powers.row(j * terms + p);
    }
    for (int k = 0; k < substeps; ++k) {
      f.noalias() = rows * z;
      Q.noalias() = rows * Y;
      const double z_scale = balanced_norm(z, tuple.w_ref);
      for (int j = 0; j < meshes; ++j) {
        // The polynomial's truncation: |c_j sum_{p > P} (A tau)^p / p! y| <= ||c_j||_1 tail ||S
        // y||.
        const double truncation = tuple.gap_norms[j] * tail;
        const ContactState state = states_[static_cast<size_t>(j)];
        const bool drive = state == ContactState::kDrive;
        const int segment = segments[static_cast<size_t>(j)];
        const double sign = drive ? 1.0 : -1.0;  // inside: g+ > 0 (drive), g- < 0 (back)
        const double wall = t_.Wall(j, segment, drive, z);
        // A free coupling stage (its drive and back rows are one): inside between both walls.
        const bool between = state == ContactState::kFree;
        const double drive_wall = between ? t_.Wall(j, segment, true, z) : 0.0;
        const auto fj = f.segment(j * terms, terms);
        double curvature = 0.0;
        for (int p = 2; p < terms; ++p) curvature += p * (p - 1) * std::abs(fj[p]);
        // The orbit's margin: between nodes s_k = k / K of [0, 1] (s = tau / d) a C^2 function
        // is above its chord less sup|g''| / (8 K^2).
        double lowest = std::numeric_limits<double>::infinity();
        for (int k = 0; k <= kNodes; ++k) {
          const double delta = Horner(fj, static_cast<double>(k) / kNodes);
          lowest = std::min(
              lowest, between ? std::min(drive_wall - delta, delta - wall) : sign * (delta - wall));
        }
        margin_[j] = std::min(margin_[j], lowest - kChordLoss * curvature - truncation * z_scale);
        // Each mode's gap: max |.| <= max over the nodes + sup|g''| / (8 K^2) (componentwise
        // chord errors, summed by Minkowski into the modulus).
        for (int i = 0; i < e; ++i) {
          const auto re = Q.col(i).segment(j * terms, terms);
          const auto im = Q.col(e + i).segment(j * terms, terms);
          double mode_curvature = 0.0;
          for (int p = 2; p < terms; ++p)
            mode_curvature += p * (p - 1) * std::sqrt(re[p] * re[p] + im[p] * im[p]);
          double largest = 0.0;
          for (int k = 0; k <= kNodes; ++k) {
            const double x = static_cast<double>(k) / kNodes;
            largest = std::max(largest, std::hypot(Horner(re, x), Horner(im, x)));
          }
          const double mode_scale = std::max(balanced_norm(Y.col(i), tuple.w_ref),
                                             balanced_norm(Y.col(e + i), tuple.w_ref));
          gain_(j, i) = std::max(
              gain_(j, i), largest + kChordLoss * mode_curvature + 2.0 * truncation * mode_scale);
        }
      }
      zn.noalias() = E * z;
      z = zn;
      Yn.noalias() = E * Y;
      Y = Yn;
    }
  });
  if (!(margin_.minCoeff() > 0.0)) info_ = Info::kNoMargin;
}

const TrainCycleMap::Tuple& TrainCycleMap::Lookup(TupleMemo& memo,
                                                  const std::vector<int>& segments) const {
  auto [it, inserted] = memo.try_emplace(segments);
  Tuple& tuple = it->second;
  if (!inserted) return tuple;
  const int n = t_.n, m = t_.m, terms = kTaylorTerms + 1;
  tuple.A = AssembleTrainGenerator(t_, segments, states_);
  tuple.w_ref = ReferenceFrequency(tuple.A, n);
  tuple.rho =
      Eigen::EigenSolver<Eigen::MatrixXd>(tuple.A, false).eigenvalues().cwiseAbs().maxCoeff();
  // The sub-step rate: ||S A S^-1||_inf with the velocities scaled by 1 / w_ref (BalancedExpm's
  // balance), so rate d <= q bounds the Taylor tail.
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(m);
  scale.segment(n, n).setConstant(1.0 / tuple.w_ref);
  tuple.rate = ScaledRowNorm(tuple.A, scale);
  tuple.gap_norms.resize(static_cast<Eigen::Index>(t_.meshes.size()));
  tuple.gap_powers.resize(static_cast<Eigen::Index>(t_.meshes.size()) * terms, m);
  for (size_t j = 0; j < t_.meshes.size(); ++j) {
    const Eigen::Index r = static_cast<Eigen::Index>(j) * terms;
    tuple.gap_powers.row(r).setZero();
    // The gap of the flank in contact: g+ on v, g- on v_back (they differ from tier 2 on).
    tuple.gap_powers.row(r).head(n) =
        t_.meshes[j].Vector(states_[j] == ContactState::kDrive).transpose();
    tuple.gap_norms[static_cast<Eigen::Index>(j)] = tuple.gap_powers.row(r).cwiseAbs().sum();
    for (int p = 1; p < terms; ++p)
      tuple.gap_powers.row(r + p) = tuple.gap_powers.row(r + p - 1) * tuple.A;
  }
  return tuple;
}

size_t TrainCycleMap::bytes() const {
  size_t doubles =
      static_cast<size_t>(phi_.size() + pq_.size() + projector_.size() + gain_.size()) +
      2 * static_cast<size_t>(eigenvectors_.size() + eigenvectors_inv_.size());
  for (const Eigen::MatrixXd& p : powers_) doubles += static_cast<size_t>(p.size());
  return doubles * sizeof(double);
}

bool TrainCycleMap::Certify(const Eigen::VectorXd& z) {
  if (info_ != Info::kSuccess) return false;
  const int e = 2 * t_.n;
  next_.noalias() = projector_ * z;
  dev_ = next_.head(e) - orbit_.head(e);
  dev_complex_ = dev_.cast<std::complex<double>>();
  coeff_.noalias() = eigenvectors_inv_ * dev_complex_;
  // The expansion must reproduce the deviation (an ill-conditioned basis would not).
  rebuilt_.noalias() = eigenvectors_ * coeff_;
  rebuilt_ -= dev_complex_;
  if (rebuilt_.norm() > 1e-8 * (dev_.norm() + 1e-300)) return false;
  bool certified = true;
  for (Eigen::Index j = 0; j < gain_.rows(); ++j) {
    double bound = 0.0;
    for (int i = 0; i < e; ++i) bound += std::abs(coeff_[i]) * gain_(j, i);
    bound_[j] = bound;
    certified = certified && bound < (1.0 - margin_fraction_) * margin_[j];
  }
  return certified;
}

void TrainCycleMap::Jump(Eigen::VectorXd& z, long long periods) {
  const int n = t_.n, e = 2 * n;
  const double rigid_position = t_.recenter_row.dot(z.head(n));
  const double rigid_velocity = mv_.dot(z);  // 0 when the map carries it (a damped rotation)
  next_.noalias() = projector_ * z;
  dev_ = next_.head(e) - orbit_.head(e);
  dev0_ = dev_;
  const long long total = periods;
  for (int l = 0; periods > 0; ++l, periods >>= 1) {
    if ((periods & 1) == 0) continue;
    next_.head(e).noalias() = powers_[static_cast<size_t>(l)] * dev_;
    dev_ = next_.head(e);
    internal::FlushSubnormals(dev_);
  }
  const double velocity = rigid_velocity + static_cast<double>(total) * velocity_drift_ +
                          velocity_sum_row_.dot(dev0_ - dev_);
  // The standing rotations' positions and velocities as they were (projected out of the map).
  const Eigen::Index standing = t_.standing_rotations.cols();
  for (Eigen::Index s = 0; s < standing; ++s) {
    const auto ms = t_.inertia.cwiseProduct(t_.standing_rotations.col(s));
    standing_[2 * s] = ms.dot(z.head(n));
    standing_[2 * s + 1] = ms.dot(z.segment(n, n));
  }
  z.head(e) = orbit_.head(e) + dev_;
  z.head(n) += rigid_position * t_.rigid_rotation;
  z.segment(n, n) += velocity * t_.rigid_rotation;
  for (Eigen::Index s = 0; s < standing; ++s) {
    z.head(n) += standing_[2 * s] * t_.standing_rotations.col(s);
    z.segment(n, n) += standing_[2 * s + 1] * t_.standing_rotations.col(s);
  }
  z[t_.constant_slot()] = 1.0;
}

}  // namespace gearnvh
