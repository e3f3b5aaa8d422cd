// ClosedFormGap: the gap over a segment in closed form and its certified first rise
// (spectral_gap.h).
#include "gearnvh/solver/spectral_gap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "vector_sincos.h"

namespace gearnvh {

ClosedFormGap::ClosedFormGap(const SpectralDecomposition& d, const Eigen::RowVectorXd& row) {
  const Eigen::RowVectorXd u = row * d.S;
  zero_size_ = d.zero_size;
  poly_rows_.resize(std::max(d.series_terms, 1), zero_size_);
  poly_rows_.setZero();
  if (zero_size_ > 0) {
    Eigen::RowVectorXd r = u.head(zero_size_);
    for (int k = 0; k < d.series_terms; ++k) {
      poly_rows_.row(k) = r;
      r = (r * d.B0) / static_cast<double>(k + 1);
    }
  }
  poly_ = Eigen::VectorXd::Zero(poly_rows_.rows());
  const int count = static_cast<int>(d.blocks.size());
  // Padded with zero terms (sigma = omega = 0, coefficients 0: they add exactly 0 everywhere) to
  // whole 8-double vectors.
  terms_ = count;
  const int padded = (count + 7) / 8 * 8;
  index_a_.setZero(padded);
  index_b_.setZero(padded);
  for (auto* a : {&sigma_, &omega_, &rate_, &damped_sigma_, &r1a_, &r1b_, &r2a_, &r2b_, &alpha_,
                  &beta_, &bound1_, &grow_, &cos_, &sin_})
    a->setZero(padded);
  for (int k = 0; k < count; ++k) {
    const SpectralDecomposition::Block& b = d.blocks[k];
    sigma_[k] = b.sigma;
    omega_[k] = b.omega;
    rate_[k] = std::hypot(b.sigma, b.omega);
    damped_sigma_[k] = std::min(b.sigma, 0.0);
    if (b.sigma > 0.0) growing_.push_back(k);
    index_a_[k] = b.start;
    if (b.size == 1) {
      index_b_[k] = b.start;
      r1a_[k] = u[b.start];
    } else {
      index_b_[k] = b.start + 1;
      const Eigen::RowVector2d ub = u.segment<2>(b.start);
      const Eigen::RowVector2d r2 = (ub * b.B - b.sigma * ub) / b.omega;
      r1a_[k] = ub[0];
      r1b_[k] = ub[1];
      r2a_[k] = r2[0];
      r2b_[k] = r2[1];
    }
  }
}

ClosedFormGap::ClosedFormGap(const SpectralDecomposition& d, const Eigen::RowVectorXd& row,
                             double horizon)
    : ClosedFormGap(d, row) {
  const Eigen::RowVectorXd u = row * d.S;
  const int m = static_cast<int>(u.size());
  end_ = horizon;
  end_value_row_ = Eigen::RowVectorXd::Zero(m);
  end_rate_row_ = Eigen::RowVectorXd::Zero(m);
  // Polynomial part: p(H) = sum_k poly_rows_k H^k w0, p'(H) = sum_k k poly_rows_k H^(k-1) w0.
  if (zero_size_ > 0) {
    double power = 1.0;  // H^k
    for (int k = 0; k < poly_rows_.rows(); ++k) {
      end_value_row_.head(zero_size_) += power * poly_rows_.row(k);
      if (k + 1 < poly_rows_.rows())
        end_rate_row_.head(zero_size_) +=
            static_cast<double>(k + 1) * power * poly_rows_.row(k + 1);
      power *= horizon;
    }
  }
  for (const auto& b : d.blocks) {
    const double grow = std::exp(b.sigma * horizon);
    if (b.size == 1) {
      end_value_row_[b.start] = u[b.start] * grow;
      end_rate_row_[b.start] = u[b.start] * b.sigma * grow;
      continue;
    }
    // e^{B H} = e^{sigma H}(cos(omega H) I + sin(omega H) / omega (B - sigma I)); the rate row
    // is u_b B e^{B H}.
    const Eigen::Matrix2d E = grow * (std::cos(b.omega * horizon) * Eigen::Matrix2d::Identity() +
                                      std::sin(b.omega * horizon) / b.omega *
                                          (b.B - b.sigma * Eigen::Matrix2d::Identity()));
    const Eigen::RowVector2d ub = u.segment<2>(b.start);
    end_value_row_.segment<2>(b.start) = ub * E;
    end_rate_row_.segment<2>(b.start) = ub * b.B * E;
  }
  // The screen (ClearOfWall): per coordinate of w, the bound of its share of |g'| on [0, H]
  // (slope) and of its terms' magnitude (size).
  screen_start_ = u;
  screen_rate_ = Eigen::RowVectorXd::Zero(m);
  Eigen::RowVectorXd slope = Eigen::RowVectorXd::Zero(m), size = Eigen::RowVectorXd::Zero(m);
  Eigen::RowVectorXd curve = Eigen::RowVectorXd::Zero(m);
  if (zero_size_ > 0 && poly_rows_.rows() > 1) screen_rate_.head(zero_size_) = poly_rows_.row(1);
  double power = 1.0;  // H^k
  for (int k = 0; k < poly_rows_.rows() && zero_size_ > 0; ++k) {
    size.head(zero_size_) += power * poly_rows_.row(k).cwiseAbs();
    if (k + 1 < poly_rows_.rows())
      slope.head(zero_size_) +=
          static_cast<double>(k + 1) * power * poly_rows_.row(k + 1).cwiseAbs();
    if (k + 2 < poly_rows_.rows())
      curve.head(zero_size_) +=
          static_cast<double>((k + 2) * (k + 1)) * power * poly_rows_.row(k + 2).cwiseAbs();
    power *= horizon;
  }
  for (int k = 0; k < terms_; ++k) {
    const double grow = std::exp(std::max(sigma_[k], 0.0) * horizon);
    const double a = grow * std::hypot(r1a_[k], r2a_[k]), b = grow * std::hypot(r1b_[k], r2b_[k]);
    size[index_a_[k]] += a;
    slope[index_a_[k]] += rate_[k] * a;
    curve[index_a_[k]] += rate_[k] * rate_[k] * a;
    size[index_b_[k]] += b;
    slope[index_b_[k]] += rate_[k] * b;
    curve[index_b_[k]] += rate_[k] * rate_[k] * b;
    // g'(0) of the term: sigma alpha + omega beta.
    screen_rate_[index_a_[k]] += sigma_[k] * r1a_[k] + omega_[k] * r2a_[k];
    screen_rate_[index_b_[k]] += sigma_[k] * r1b_[k] + omega_[k] * r2b_[k];
  }
  const double eps = std::numeric_limits<double>::epsilon();
  // 1 + 1e-12: the rounding of the bounds' own evaluation (as in DerivativeBound).
  screen_margin_ = (1.0 + 1e-12) * (4.0 * m + 64.0) * eps * size;
  screen_reach_ = (1.0 + 1e-12) * horizon * slope + screen_margin_;
  screen_curve_ = (1.0 + 1e-12) * curve;
}

void ClosedFormGap::Load(const Eigen::VectorXd& w) {
  if (end_ >= 0.0) {
    end_value_ = end_value_row_.dot(w);
    end_rate_ = end_rate_row_.dot(w);
  }
  // Eigen's product: a plain loop (a little faster on trains) sums in another order, which moved
  // the pair's settled idle-rattle trajectory to a window where the saltation test's finite
  // difference disagrees with the tangent (cause not established; kept as it was).
  if (zero_size_ > 0) poly_.noalias() = poly_rows_ * w.head(zero_size_);
  // One scalar pass: a vector pass over values just stored one by one would wait for the stores
  // (no store-to-load forwarding from narrow stores into a wide load).
  double sum1 = 0.0, sum2 = 0.0;
  for (int k = 0; k < terms_; ++k) {
    const double wa = w[index_a_[k]], wb = w[index_b_[k]];
    const double alpha = r1a_[k] * wa + r1b_[k] * wb, beta = r2a_[k] * wa + r2b_[k] * wb;
    alpha_[k] = alpha;
    beta_[k] = beta;
    const double bound = std::sqrt(alpha * alpha + beta * beta) * rate_[k];
    bound1_[k] = bound;
    sum1 += bound;
    sum2 += bound * rate_[k];
  }
  bound1_sum_ = sum1;
  bound2_sum_ = sum2;
}

void ClosedFormGap::Load(const Eigen::VectorXd& w, double constant) {
  Load(w);
  poly_[0] += constant;
  end_value_ += constant;
}

double ClosedFormGap::StartValue() const {
  return (zero_size_ > 0 ? poly_[0] : 0.0) + alpha_.sum();
}

void ClosedFormGap::EvaluateTerms(double t) const {
  // The arrays are padded to whole vectors (the padding's coefficients are 0).
  for (int k = 0; k < omega_.size(); k += 8) {
    internal::VectorGrowSinCos(&sigma_[k], &omega_[k], t, terms_ - k, &grow_[k], &cos_[k],
                               &sin_[k]);
  }
}

double ClosedFormGap::Evaluate(double t, int order) const {
  // Polynomial part (Horner on the order-th derivative).
  double value = 0.0;
  const int degree = static_cast<int>(poly_.size()) - 1;
  if (zero_size_ > 0) {
    for (int k = degree; k >= order; --k) {
      double factor = 1.0;
      for (int i = 0; i < order; ++i) factor *= static_cast<double>(k - i);
      value = value * t + factor * poly_[k];
    }
  }
  EvaluateTerms(t);
  if (order == 0) return value + (grow_ * (alpha_ * cos_ + beta_ * sin_)).sum();
  // d/dt [e^{st}(a cos wt + b sin wt)] = e^{st}((s a + w b) cos wt + (s b - w a) sin wt).
  if (order == 1) return value + (grow_ * (RateAlpha() * cos_ + RateBeta() * sin_)).sum();
  return value + (grow_ * ((sigma_ * RateAlpha() + omega_ * RateBeta()) * cos_ +
                           (sigma_ * RateBeta() - omega_ * RateAlpha()) * sin_))
                     .sum();
}

ClosedFormGap::Jet ClosedFormGap::SearchJet(double t) const {
  // The same sums as Evaluate(t, 0) and Evaluate(t, 1), sharing each term's exp and sincos.
  double value = 0.0, rate = 0.0;
  if (t == 0.0) {  // every segment's search starts here: no exp, no sincos
    if (zero_size_ > 0) value = poly_[0], rate = poly_.size() > 1 ? poly_[1] : 0.0;
    value += alpha_.sum();
    rate += RateAlpha().sum();
    return {sign_ * value - offset_, sign_ * rate};
  }
  if (t == end_) {  // two dot products
    last_time_ = t;
    last_rate_ = end_rate_;
    return {sign_ * end_value_ - offset_, sign_ * end_rate_};
  }
  const int degree = static_cast<int>(poly_.size()) - 1;
  if (zero_size_ > 0) {
    for (int k = degree; k >= 0; --k) value = value * t + poly_[k];
    for (int k = degree; k >= 1; --k) rate = rate * t + static_cast<double>(k) * poly_[k];
  }
  EvaluateTerms(t);
  value += (grow_ * (alpha_ * cos_ + beta_ * sin_)).sum();
  rate += (grow_ * (RateAlpha() * cos_ + RateBeta() * sin_)).sum();
  last_time_ = t;
  last_rate_ = rate;
  return {sign_ * value - offset_, sign_ * rate};
}

double ClosedFormGap::DerivativeBound(double a, double b, int order) const {
  double bound = 0.0;
  const int degree = static_cast<int>(poly_.size()) - 1;
  if (zero_size_ > 0) {
    for (int k = degree; k >= order; --k) {
      double factor = 1.0;
      for (int i = 0; i < order; ++i) factor *= static_cast<double>(k - i);
      bound = bound * b + factor * std::abs(poly_[k]);
    }
  }
  // max over [a, b] of e^{sigma t} is e^{sigma a} (sigma <= 0), bounded by 1 / (1 - sigma a) since
  // e^{-x} (1 + x) <= 1 for x >= 0 (1 at a = 0: the loaded sum); or e^{sigma b} (sigma > 0: the
  // damped sum counts such a term once, the loop below adds e^{sigma b} - 1).
  if (a == 0.0)
    bound += order == 1 ? bound1_sum_ : bound2_sum_;
  else if (order == 1)
    bound += (bound1_ / (1.0 - damped_sigma_ * a)).sum();
  else
    bound += (bound1_ * rate_ / (1.0 - damped_sigma_ * a)).sum();
  for (const int k : growing_)
    bound += bound1_[k] * (order == 1 ? 1.0 : rate_[k]) * std::expm1(sigma_[k] * b);
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
