// ClosedFormGap: the gap over a segment in closed form and its certified first rise
// (spectral_gap.h).
#include "gearnvh/solver/spectral_gap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <optional>

#include "vector_sincos.h"

namespace gearnvh {

namespace {

constexpr size_t kAlignBytes = 64;  // EIGEN_MAX_ALIGN_BYTES with AVX-512; a cache line
constexpr int kAlignDoubles = static_cast<int>(kAlignBytes / sizeof(double));
static_assert(kAlignBytes % EIGEN_MAX_ALIGN_BYTES == 0);

int RoundUp(int doubles) { return (doubles + kAlignDoubles - 1) / kAlignDoubles * kAlignDoubles; }

double* AllocateAligned(size_t doubles) {
  return static_cast<double*>(::operator new (std::max<size_t>(doubles, 1) * sizeof(double),
                                              std::align_val_t{kAlignBytes}));
}

}  // namespace

void ClosedFormGap::FreeAligned::operator()(double* p) const {
  ::operator delete (p, std::align_val_t{kAlignBytes});
}

ClosedFormGap::ClosedFormGap(const SpectralDecomposition& d, const Eigen::RowVectorXd& row) {
  Build(d, row, -1.0);
}

ClosedFormGap::ClosedFormGap(const SpectralDecomposition& d, const Eigen::RowVectorXd& row,
                             double horizon) {
  Build(d, row, horizon);
}

ClosedFormGap::ClosedFormGap(const ClosedFormGap& other) { *this = other; }

ClosedFormGap& ClosedFormGap::operator=(const ClosedFormGap& other) {
  if (this == &other) return *this;
  storage_.reset(other.storage_ ? AllocateAligned(other.storage_doubles_) : nullptr);
  if (other.storage_) std::copy_n(other.storage_.get(), other.storage_doubles_, storage_.get());
  storage_doubles_ = other.storage_doubles_;
  part_offset_ = other.part_offset_;
  terms_ = other.terms_;
  padded_ = other.padded_;
  poly_terms_ = other.poly_terms_;
  row_size_ = other.row_size_;
  growing_ = other.growing_;
  bound1_sum_ = other.bound1_sum_;
  bound2_sum_ = other.bound2_sum_;
  zero_size_ = other.zero_size_;
  end_ = other.end_;
  end_value_ = other.end_value_;
  end_rate_ = other.end_rate_;
  sign_ = other.sign_;
  offset_ = other.offset_;
  horizon_ = other.horizon_;
  last_time_ = other.last_time_;
  last_rate_ = other.last_rate_;
  last_curvature_ = other.last_curvature_;
  return *this;
}

void ClosedFormGap::Build(const SpectralDecomposition& d, const Eigen::RowVectorXd& row,
                          double horizon) {
  const Eigen::RowVectorXd u = row * d.S;
  const int m = static_cast<int>(u.size());
  zero_size_ = d.zero_size;
  poly_terms_ = std::max(d.series_terms, 1);
  const int count = static_cast<int>(d.blocks.size());
  // Padded with zero terms (sigma = omega = 0, coefficients 0: they add exactly 0 everywhere) to
  // whole 8-double vectors.
  terms_ = count;
  padded_ = (count + 7) / 8 * 8;
  row_size_ = horizon >= 0.0 ? m : 0;
  int next = 0;
  for (int part = 0; part < kParts; ++part) {
    part_offset_[static_cast<size_t>(part)] = next;
    int size = padded_;  // kIndex: 2 padded_ ints
    if (part == kPolyRows) size = poly_terms_ * zero_size_;
    if (part == kPoly) size = poly_terms_;
    if (part >= kEndValueRow) size = row_size_;
    next += RoundUp(size);
  }
  storage_doubles_ = static_cast<size_t>(next);
  storage_.reset(AllocateAligned(storage_doubles_));
  std::fill_n(storage_.get(), storage_doubles_, 0.0);
  std::fill_n(reinterpret_cast<int*>(Data(kIndex)), 2 * padded_, 0);

  if (zero_size_ > 0) {
    Eigen::RowVectorXd r = u.head(zero_size_);
    for (int k = 0; k < d.series_terms; ++k) {
      poly_rows().row(k) = r;
      r = (r * d.B0) / static_cast<double>(k + 1);
    }
  }
  int* index = reinterpret_cast<int*>(Data(kIndex));
  for (int k = 0; k < count; ++k) {
    const SpectralDecomposition::Block& b = d.blocks[k];
    sigma()[k] = b.sigma;
    omega()[k] = b.omega;
    rates()[k] = std::hypot(b.sigma, b.omega);
    damped_sigma()[k] = std::min(b.sigma, 0.0);
    if (b.sigma > 0.0) growing_.push_back(k);
    index[k] = b.start;
    if (b.size == 1) {
      index[padded_ + k] = b.start;
      r1a()[k] = u[b.start];
    } else {
      index[padded_ + k] = b.start + 1;
      const Eigen::RowVector2d ub = u.segment<2>(b.start);
      const Eigen::RowVector2d r2 = (ub * b.B - b.sigma * ub) / b.omega;
      r1a()[k] = ub[0];
      r1b()[k] = ub[1];
      r2a()[k] = r2[0];
      r2b()[k] = r2[1];
    }
  }
  if (horizon < 0.0) return;

  // With the rows of g(H) and g'(H) in w for the segment length H (u e^{DH} and u D e^{DH}).
  end_ = horizon;
  auto end_value_row = Row(kEndValueRow);
  auto end_rate_row = Row(kEndRateRow);
  const auto poly_rows = this->poly_rows();
  // Polynomial part: p(H) = sum_k poly_rows_k H^k w0, p'(H) = sum_k k poly_rows_k H^(k-1) w0.
  if (zero_size_ > 0) {
    double power = 1.0;  // H^k
    for (int k = 0; k < poly_rows.rows(); ++k) {
      end_value_row.head(zero_size_) += power * poly_rows.row(k);
      if (k + 1 < poly_rows.rows())
        end_rate_row.head(zero_size_) += static_cast<double>(k + 1) * power * poly_rows.row(k + 1);
      power *= horizon;
    }
  }
  for (const auto& b : d.blocks) {
    const double grow = std::exp(b.sigma * horizon);
    if (b.size == 1) {
      end_value_row[b.start] = u[b.start] * grow;
      end_rate_row[b.start] = u[b.start] * b.sigma * grow;
      continue;
    }
    // e^{B H} = e^{sigma H}(cos(omega H) I + sin(omega H) / omega (B - sigma I)); the rate row
    // is u_b B e^{B H}.
    const Eigen::Matrix2d E = grow * (std::cos(b.omega * horizon) * Eigen::Matrix2d::Identity() +
                                      std::sin(b.omega * horizon) / b.omega *
                                          (b.B - b.sigma * Eigen::Matrix2d::Identity()));
    const Eigen::RowVector2d ub = u.segment<2>(b.start);
    end_value_row.segment<2>(b.start) = ub * E;
    end_rate_row.segment<2>(b.start) = ub * b.B * E;
  }
  // The screen (ClearOfWall): per coordinate of w, the bound of its share of |g'| on [0, H]
  // (slope) and of its terms' magnitude (size).
  Row(kScreenStart) = u;
  auto screen_rate = Row(kScreenRate);
  Eigen::RowVectorXd slope = Eigen::RowVectorXd::Zero(m), size = Eigen::RowVectorXd::Zero(m);
  Eigen::RowVectorXd curve = Eigen::RowVectorXd::Zero(m);
  if (zero_size_ > 0 && poly_rows.rows() > 1) screen_rate.head(zero_size_) = poly_rows.row(1);
  double power = 1.0;  // H^k
  for (int k = 0; k < poly_rows.rows() && zero_size_ > 0; ++k) {
    size.head(zero_size_) += power * poly_rows.row(k).cwiseAbs();
    if (k + 1 < poly_rows.rows())
      slope.head(zero_size_) +=
          static_cast<double>(k + 1) * power * poly_rows.row(k + 1).cwiseAbs();
    if (k + 2 < poly_rows.rows())
      curve.head(zero_size_) +=
          static_cast<double>((k + 2) * (k + 1)) * power * poly_rows.row(k + 2).cwiseAbs();
    power *= horizon;
  }
  const int* index_a = this->index_a();
  const int* index_b = this->index_b();
  for (int k = 0; k < terms_; ++k) {
    const double grow = std::exp(std::max(sigma()[k], 0.0) * horizon);
    const double a = grow * std::hypot(r1a()[k], r2a()[k]),
                 b = grow * std::hypot(r1b()[k], r2b()[k]);
    const double rate = rates()[k];
    size[index_a[k]] += a;
    slope[index_a[k]] += rate * a;
    curve[index_a[k]] += rate * rate * a;
    size[index_b[k]] += b;
    slope[index_b[k]] += rate * b;
    curve[index_b[k]] += rate * rate * b;
    // g'(0) of the term: sigma alpha + omega beta.
    screen_rate[index_a[k]] += sigma()[k] * r1a()[k] + omega()[k] * r2a()[k];
    screen_rate[index_b[k]] += sigma()[k] * r1b()[k] + omega()[k] * r2b()[k];
  }
  const double eps = std::numeric_limits<double>::epsilon();
  // 1 + 1e-12: the rounding of the bounds' own evaluation (as in DerivativeBound).
  Row(kScreenMargin) = (1.0 + 1e-12) * (4.0 * m + 64.0) * eps * size;
  Row(kScreenReach) = (1.0 + 1e-12) * horizon * slope + Row(kScreenMargin);
  Row(kScreenCurve) = (1.0 + 1e-12) * curve;
}

void ClosedFormGap::Load(const Eigen::VectorXd& w) {
  if (end_ >= 0.0) {
    end_value_ = Row(kEndValueRow).dot(w);
    end_rate_ = Row(kEndRateRow).dot(w);
  }
  // Eigen's product (a plain loop, a little faster on trains, sums in another order: equal to
  // rounding; it once moved the saltation test to a window where its finite difference had not
  // converged, which that test now checks).
  if (zero_size_ > 0) poly().noalias() = poly_rows() * w.head(zero_size_);
  // One scalar pass: a vector pass over values just stored one by one would wait for the stores
  // (no store-to-load forwarding from narrow stores into a wide load).
  const int* index_a = this->index_a();
  const int* index_b = this->index_b();
  const double *r1a = Data(kR1a), *r1b = Data(kR1b), *r2a = Data(kR2a), *r2b = Data(kR2b);
  const double* rates = Data(kRates);
  double *alpha = Data(kAlpha), *beta = Data(kBeta), *bound1 = Data(kBound1);
  double sum1 = 0.0, sum2 = 0.0;
  for (int k = 0; k < terms_; ++k) {
    const double wa = w[index_a[k]], wb = w[index_b[k]];
    const double a = r1a[k] * wa + r1b[k] * wb, b = r2a[k] * wa + r2b[k] * wb;
    alpha[k] = a;
    beta[k] = b;
    const double bound = std::sqrt(a * a + b * b) * rates[k];
    bound1[k] = bound;
    sum1 += bound;
    sum2 += bound * rates[k];
  }
  bound1_sum_ = sum1;
  bound2_sum_ = sum2;
}

void ClosedFormGap::Load(const Eigen::VectorXd& w, double constant) {
  Load(w);
  poly()[0] += constant;
  end_value_ += constant;
}

double ClosedFormGap::StartValue() const {
  return (zero_size_ > 0 ? poly()[0] : 0.0) + alpha().sum();
}

void ClosedFormGap::EvaluateTerms(double t) const {
  // The arrays are padded to whole vectors (the padding's coefficients are 0).
  for (int k = 0; k < padded_; k += 8) {
    internal::VectorGrowSinCos(&sigma()[k], &omega()[k], t, terms_ - k, &grow()[k], &cosines()[k],
                               &sines()[k]);
  }
}

double ClosedFormGap::Evaluate(double t, int order) const {
  // Polynomial part (Horner on the order-th derivative).
  double value = 0.0;
  const int degree = poly_terms_ - 1;
  if (zero_size_ > 0) {
    for (int k = degree; k >= order; --k) {
      double factor = 1.0;
      for (int i = 0; i < order; ++i) factor *= static_cast<double>(k - i);
      value = value * t + factor * poly()[k];
    }
  }
  EvaluateTerms(t);
  if (order == 0) return value + (grow() * (alpha() * cosines() + beta() * sines())).sum();
  // d/dt [e^{st}(a cos wt + b sin wt)] = e^{st}((s a + w b) cos wt + (s b - w a) sin wt).
  if (order == 1) return value + (grow() * (RateAlpha() * cosines() + RateBeta() * sines())).sum();
  return value + (grow() * ((sigma() * RateAlpha() + omega() * RateBeta()) * cosines() +
                            (sigma() * RateBeta() - omega() * RateAlpha()) * sines()))
                     .sum();
}

ClosedFormGap::Jet ClosedFormGap::SearchJet(double t) const {
  // The same sums as Evaluate(t, 0) and Evaluate(t, 1), sharing each term's exp and sincos.
  double value = 0.0, rate = 0.0;
  if (t == 0.0) {  // every segment's search starts here: no exp, no sincos
    if (zero_size_ > 0) value = poly()[0], rate = poly_terms_ > 1 ? poly()[1] : 0.0;
    value += alpha().sum();
    rate += RateAlpha().sum();
    return {sign_ * value - offset_, sign_ * rate};
  }
  if (t == end_) {  // two dot products
    last_time_ = t;
    last_rate_ = end_rate_;
    return {sign_ * end_value_ - offset_, sign_ * end_rate_};
  }
  const int degree = poly_terms_ - 1;
  if (zero_size_ > 0) {
    for (int k = degree; k >= 0; --k) value = value * t + poly()[k];
    for (int k = degree; k >= 1; --k) rate = rate * t + static_cast<double>(k) * poly()[k];
  }
  EvaluateTerms(t);
  value += (grow() * (alpha() * cosines() + beta() * sines())).sum();
  rate += (grow() * (RateAlpha() * cosines() + RateBeta() * sines())).sum();
  last_time_ = t;
  last_rate_ = rate;
  return {sign_ * value - offset_, sign_ * rate};
}

double ClosedFormGap::DerivativeBound(double a, double b, int order) const {
  double bound = 0.0;
  const int degree = poly_terms_ - 1;
  if (zero_size_ > 0) {
    for (int k = degree; k >= order; --k) {
      double factor = 1.0;
      for (int i = 0; i < order; ++i) factor *= static_cast<double>(k - i);
      bound = bound * b + factor * std::abs(poly()[k]);
    }
  }
  // max over [a, b] of e^{sigma t} is e^{sigma a} (sigma <= 0), bounded by 1 / (1 - sigma a) since
  // e^{-x} (1 + x) <= 1 for x >= 0 (1 at a = 0: the loaded sum); or e^{sigma b} (sigma > 0: the
  // damped sum counts such a term once, the loop below adds e^{sigma b} - 1).
  if (a == 0.0)
    bound += order == 1 ? bound1_sum_ : bound2_sum_;
  else if (order == 1)
    bound += (bound1() / (1.0 - damped_sigma() * a)).sum();
  else
    bound += (bound1() * rates() / (1.0 - damped_sigma() * a)).sum();
  for (const int k : growing_)
    bound += bound1()[k] * (order == 1 ? 1.0 : rates()[k]) * std::expm1(sigma()[k] * b);
  // Rounding of the evaluated bound itself: a hair of slack keeps the certificate conservative.
  return bound * (1.0 + 1e-12);
}

bool ClosedFormGap::RateWithin(double t, double limit) const {
  const double near = 8.0 * std::numeric_limits<double>::epsilon() * horizon_;
  const double distance = std::abs(t - last_time_);
  if (last_time_ >= 0.0 && distance <= near) return std::abs(last_rate_) <= limit;
  if (last_time_ >= 0.0 && last_curvature_ >= 0.0) {
    // |g'(t) - g'(t_l)| <= C |t - t_l|: decided unless the limit lies within that spread.
    const double spread = last_curvature_ * distance * (1.0 + 1e-12);
    if (std::abs(last_rate_) - spread > limit) return false;
    if (std::abs(last_rate_) + spread <= limit) return true;
  }
  return std::abs(Rate(t)) <= limit;
}

double ClosedFormGap::FirstRise(double sign, double horizon) const {
  sign_ = sign;
  horizon_ = horizon;
  offset_ = 0.0;
  last_time_ = -1.0;
  last_curvature_ = -1.0;
  Jet start = SearchJet(0.0);
  offset_ = std::max(start.value, 0.0);
  start.value -= offset_;
  return Search(0.0, start, horizon, std::nullopt, 0);
}

double ClosedFormGap::Polish(double a, Jet at_a, double b, Jet at_b, double curvature) const {
  // f rises monotonically on [a, b] from f(a) <= 0 to f(b) > 0, with f' >= slope > 0 there
  // (certificate 2: f'(a) > C (b - a), |f''| <= C). A Newton step from x then leaves an error of
  // at most q (r - x)^2, q = C / (2 slope), at the root r.
  const double tolerance = 4.0 * std::numeric_limits<double>::epsilon() * horizon_;
  const double slope = at_a.rate - curvature * (b - a);
  const double q =
      slope > 0.0 ? curvature / (2.0 * slope) : std::numeric_limits<double>::infinity();
  double lo = a, hi = b;
  // First iterate: the root of the quadratic through f(a), f'(a) and f(b) (error O((b - a)^3),
  // the tangent's is O((b - a)^2)); p(s) = f(a) + f'(a) s + c s^2 has p(b - a) = f(b) > 0.
  const double length = b - a;
  const double c = (at_b.value - at_a.value - at_a.rate * length) / (length * length);
  const double discriminant = at_a.rate * at_a.rate - 4.0 * c * at_a.value;
  double x = discriminant >= 0.0 ? a - 2.0 * at_a.value / (at_a.rate + std::sqrt(discriminant))
                                 : a - at_a.value / at_a.rate;
  if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
  for (int it = 0; it < 100; ++it) {
    const Jet at = SearchJet(x);
    if (at.value > 0.0)
      hi = x;
    else
      lo = x;
    if (hi - lo <= tolerance) return hi;
    // Converged when Newton's step is within the tolerance, tested before the bracket's
    // safeguard: a step below half an ulp of x (f(x) within rounding of 0) leaves next == x, on
    // the bracket's end, and bisecting from there used to halve the bracket down to the
    // tolerance (~20 evaluations) instead of stopping.
    const double next = at.rate > 0.0 ? x - at.value / at.rate : 0.5 * (lo + hi);
    const double step = std::abs(next - x);
    if (step <= tolerance) return std::clamp(next, lo, hi);
    if (!(next > lo && next < hi)) {
      x = 0.5 * (lo + hi);
      continue;
    }
    // The root r is in [lo, hi] and x is one of its ends, so e = |r - x| <= hi - lo; with
    // q (hi - lo) <= 1/2, e <= step + q e^2 gives e <= 2 step, and next is within 4 q step^2 of
    // r: when that is below the tolerance, next is the root without evaluating there
    // (RateWithin bounds g' at it from this evaluation).
    if (q * (hi - lo) <= 0.5 && 4.0 * q * step * step <= tolerance) {
      last_curvature_ = curvature;
      return next;
    }
    x = next;
  }
  return hi;
}

double ClosedFormGap::Search(double a, Jet at_a, double b, std::optional<Jet> at_b,
                             int depth) const {
  const double length = b - a;
  // Certificate 1: the wall cannot be reached on [a, b] (most segments end here, before any
  // evaluation at b).
  if (at_a.value + DerivativeBound(a, b, 1) * length <= 0.0) return -1.0;
  if (!at_b) at_b = SearchJet(b);
  // Certificate 2: f' keeps its sign on [a, b], so f is monotone there.
  const double curvature = DerivativeBound(a, b, 2);
  if (std::abs(at_a.rate) > curvature * length) {
    if (!(at_b->value > 0.0)) return -1.0;
    // Monotone with f(a) <= 0 < f(b).
    return Polish(a, at_a, b, *at_b, curvature);
  }
  // Neither certificate at rounding resolution: a grazing contact (f and f' both ~ 0).
  if (depth >= 60 || length <= 8.0 * std::numeric_limits<double>::epsilon() * horizon_) {
    return at_b->value > 0.0 ? b : -1.0;
  }
  const double mid = a + 0.5 * length;
  const Jet at_mid = SearchJet(mid);
  const double left = Search(a, at_a, mid, at_mid, depth + 1);
  if (left >= 0.0) return left;
  if (at_mid.value > 0.0) return mid;  // the left half ends outside: the crossing is at its end
  return Search(mid, at_mid, b, at_b, depth + 1);
}

}  // namespace gearnvh
