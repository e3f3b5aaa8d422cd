#include "gearnvh/solver/spectral_gap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "bracketed_newton.h"

#if defined(GEARNVH_HAVE_LIBMVEC) && defined(__AVX512F__)
#include <immintrin.h>
// glibc libmvec (ABI of the OpenMP vector variants): 8 doubles at a time, at most 4 ulp.
extern "C" __m512d _ZGVeN8v_sin(__m512d);
extern "C" __m512d _ZGVeN8v_cos(__m512d);
#define GEARNVH_VECTOR_SINCOS 1
#endif

extern "C" {
// LAPACK (Fortran ABI; trailing hidden string lengths).
void dgees_(const char* jobvs, const char* sort, int (*select)(const double*, const double*),
            const int* n, double* a, const int* lda, int* sdim, double* wr, double* wi, double* vs,
            const int* ldvs, double* work, const int* lwork, int* bwork, int* info, size_t, size_t);
void dtrsyl_(const char* trana, const char* tranb, const int* isgn, const int* m, const int* n,
             const double* a, const int* lda, const double* b, const int* ldb, double* c,
             const int* ldc, double* scale, int* info, size_t, size_t);
}

namespace gearnvh {

namespace {

thread_local double zero_threshold = 0.0;
int SelectNearZero(const double* wr, const double* wi) {
  return std::hypot(*wr, *wi) <= zero_threshold ? 1 : 0;
}

// Relative size below which a power-series term of e^{B0 t} no longer changes the sum.
constexpr double kSeriesCut = 1e-18;
constexpr int kMaxSeriesTerms = 64;

// cos(omega_k t) and sin(omega_k t) for k < 8; entries from `live` on (when < 8) are padding.
// Vector calls cost about as much as two scalar ones, so a chunk of 1-3 live terms (tier 1) stays
// scalar.
void VectorSinCos(const double* omega, double t, int live, double* c, double* s) {
  live = std::min(live, 8);
#ifdef GEARNVH_VECTOR_SINCOS
  if (live > 3) {
    const __m512d phase = _mm512_mul_pd(_mm512_loadu_pd(omega), _mm512_set1_pd(t));
    _mm512_storeu_pd(c, _ZGVeN8v_cos(phase));
    _mm512_storeu_pd(s, _ZGVeN8v_sin(phase));
    return;
  }
#endif
  for (int k = 0; k < live; ++k) sincos(omega[k] * t, &s[k], &c[k]);
  for (int k = live; k < 8; ++k) c[k] = 1.0, s[k] = 0.0;
}

}  // namespace

const char* SpectralInfoName(SpectralDecomposition::Info info) {
  switch (info) {
    case SpectralDecomposition::Info::kSuccess:
      return "success";
    case SpectralDecomposition::Info::kSchurFailed:
      return "schur_failed";
    case SpectralDecomposition::Info::kIllConditioned:
      return "ill_conditioned";
    case SpectralDecomposition::Info::kSeriesDiverged:
      return "series_diverged";
  }
  return "unknown";
}

Eigen::VectorXd BalancingScale(const Eigen::MatrixXd& A, int n, double w_ref) {
  const int m = static_cast<int>(A.rows());
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(m);
  scale.segment(n, n).setConstant(1.0 / w_ref);
  // The constant and excitation slots (zero rows) carry the forcing columns, which are tiny next to
  // the stiffness block: a backward error eps |A| would be a large relative error of the forcing,
  // i.e. of the static deflection under it (seen as 1e-16 m in the gap). Scaling the slots so their
  // columns have the norm w_ref makes the forcing as accurate as the rest.
  for (int j = 2 * n; j < m; ++j) {
    const double column = (scale.asDiagonal() * A.col(j)).norm();
    if (column > 0.0) scale[j] = column / w_ref;
  }
  return scale;
}

SpectralDecomposition DecomposeGenerator(const Eigen::MatrixXd& A, int n, double w_ref,
                                         double horizon, double max_condition) {
  SpectralDecomposition d;
  const int m = static_cast<int>(A.rows());
  const Eigen::VectorXd scale = BalancingScale(A, n, w_ref);
  Eigen::MatrixXd T = scale.asDiagonal() * A * scale.cwiseInverse().asDiagonal();

  // Ordered real Schur form: eigenvalues with |lambda| <= 1e-4 w_ref first. A Jordan block of
  // size k at 0 is perturbed to |lambda| ~ (eps)^(1/k) w_ref by rounding (6e-6 w_ref for k = 3),
  // so the cut sits well above that and well below every elastic frequency of the model.
  zero_threshold = 1e-4 * w_ref;
  Eigen::MatrixXd Q(m, m);
  Eigen::VectorXd wr(m), wi(m);
  std::vector<int> bwork(m);
  int sdim = 0, info = 0, lwork = -1;
  // The optimal workspace depends on m only: queried once per size and thread, and the buffer
  // kept (a train decomposes thousands of tuples of a few sizes).
  thread_local std::vector<std::pair<int, int>> optimal_lwork;  // (m, lwork)
  thread_local std::vector<double> work;
  const auto known = std::find_if(optimal_lwork.begin(), optimal_lwork.end(),
                                  [m](const std::pair<int, int>& e) { return e.first == m; });
  if (known != optimal_lwork.end()) {
    lwork = known->second;
  } else {
    double query = 0.0;
    dgees_("V", "S", SelectNearZero, &m, T.data(), &m, &sdim, wr.data(), wi.data(), Q.data(), &m,
           &query, &lwork, bwork.data(), &info, 1, 1);
    lwork = std::max(1, static_cast<int>(query));
    optimal_lwork.emplace_back(m, lwork);
  }
  if (work.size() < static_cast<size_t>(lwork)) work.resize(static_cast<size_t>(lwork));
  dgees_("V", "S", SelectNearZero, &m, T.data(), &m, &sdim, wr.data(), wi.data(), Q.data(), &m,
         work.data(), &lwork, bwork.data(), &info, 1, 1);
  if (info != 0) {
    d.info = SpectralDecomposition::Info::kSchurFailed;
    return d;
  }
  d.zero_size = sdim;

  // Block boundaries after the zero cluster: 1x1 or 2x2 (standardised) diagonal blocks.
  std::vector<std::pair<int, int>> parts;  // (start, size)
  if (sdim > 0) parts.emplace_back(0, sdim);
  for (int i = sdim; i < m;) {
    const int size = (i + 1 < m && T(i + 1, i) != 0.0) ? 2 : 1;
    parts.emplace_back(i, size);
    i += size;
  }
  // Decouple each block from everything after it.
  Eigen::MatrixXd S = Q, S_inv = Q.transpose();
  for (const auto& [start, size] : parts) {
    const int end = start + size, rest = m - end;
    if (rest == 0) break;
    Eigen::MatrixXd X = -T.block(start, end, size, rest);
    double sylvester_scale = 1.0;
    const int isgn = -1;
    const Eigen::MatrixXd T11 = T.block(start, start, size, size);
    const Eigen::MatrixXd T22 = T.block(end, end, rest, rest);
    dtrsyl_("N", "N", &isgn, &size, &rest, T11.data(), &size, T22.data(), &rest, X.data(), &size,
            &sylvester_scale, &info, 1, 1);
    if (info != 0 || sylvester_scale != 1.0) {
      d.info = SpectralDecomposition::Info::kIllConditioned;  // common or close eigenvalues
      return d;
    }
    X /= sylvester_scale;
    T.block(start, end, size, rest).setZero();
    S.rightCols(rest).noalias() += S.middleCols(start, size) * X;
    S_inv.middleRows(start, size).noalias() -= X * S_inv.bottomRows(rest);
  }
  d.condition =
      S.cwiseAbs().colwise().sum().maxCoeff() * S_inv.cwiseAbs().colwise().sum().maxCoeff();
  if (!(d.condition <= max_condition)) {
    d.info = SpectralDecomposition::Info::kIllConditioned;
    return d;
  }
  d.S = scale.cwiseInverse().asDiagonal() * S;
  d.S_inv = S_inv * scale.asDiagonal();
  d.B0 = T.topLeftCorner(sdim, sdim);
  for (const auto& [start, size] : parts) {
    if (start < sdim) continue;
    SpectralDecomposition::Block b;
    b.start = start;
    b.size = size;
    if (size == 1) {
      b.sigma = T(start, start);
    } else {
      b.B = T.block<2, 2>(start, start);
      b.sigma = 0.5 * b.B.trace();
      const double disc =
          -0.25 * (b.B(0, 0) - b.B(1, 1)) * (b.B(0, 0) - b.B(1, 1)) - b.B(0, 1) * b.B(1, 0);
      b.omega = std::sqrt(std::max(disc, 0.0));
      if (!(b.omega > 0.0)) {
        d.info = SpectralDecomposition::Info::kIllConditioned;
        return d;
      }
    }
    d.blocks.push_back(b);
  }
  const int padded = (static_cast<int>(d.blocks.size()) + 7) / 8 * 8;
  d.block_sigma.setZero(padded);
  d.block_omega.setZero(padded);
  for (size_t k = 0; k < d.blocks.size(); ++k) {
    d.block_sigma[k] = d.blocks[k].sigma;
    d.block_omega[k] = d.blocks[k].omega;
  }
  // e^{B0 t} = sum_k B0^k t^k / k!: keep terms until they no longer matter for t <= horizon.
  d.series_terms = 0;
  if (sdim > 0) {
    Eigen::MatrixXd power = Eigen::MatrixXd::Identity(sdim, sdim);
    double largest = 1.0;
    for (int k = 0;; ++k) {
      if (k >= kMaxSeriesTerms) {
        d.info = SpectralDecomposition::Info::kSeriesDiverged;
        return d;
      }
      d.series_terms = k + 1;
      const double size = power.cwiseAbs().maxCoeff() * std::pow(horizon, k);
      largest = std::max(largest, size);
      if (k >= sdim && size <= kSeriesCut * largest) break;
      power = (d.B0 * power) / static_cast<double>(k + 1);
    }
  }
  d.info = SpectralDecomposition::Info::kSuccess;
  return d;
}

void PropagateDecoupled(const SpectralDecomposition& d, const Eigen::VectorXd& w, double t,
                        Eigen::VectorXd& out, Eigen::VectorXd& scratch) {
  const int kz = d.zero_size;
  if (kz > 0) {
    // e^{B0 t} w0 = w0 + (t/1) B0 (w0 + (t/2) B0 (w0 + ...)), Horner from the highest term down.
    auto head = out.head(kz);
    auto tmp = scratch.head(kz);
    head = w.head(kz);
    for (int k = d.series_terms - 1; k >= 1; --k) {
      tmp.noalias() = d.B0 * head;
      head = w.head(kz) + (t / k) * tmp;
    }
  }
  const int count = static_cast<int>(d.blocks.size());
  for (int first = 0; first < count; first += 8) {
    // exp(sigma t), cos(omega t), sin(omega t) of 8 blocks at a time.
    using Eight = Eigen::Array<double, 8, 1>;
    Eight grow, c, s;
    grow = (Eigen::Map<const Eight>(&d.block_sigma[first]) * t).exp();
    VectorSinCos(&d.block_omega[first], t, count - first, c.data(), s.data());
    for (int i = 0; i < std::min(8, count - first); ++i) {
      const auto& b = d.blocks[first + i];
      if (b.size == 1) {
        out[b.start] = grow[i] * w[b.start];
      } else {
        const Eigen::Vector2d wb = w.segment<2>(b.start);
        const Eigen::Vector2d shifted = b.B * wb - b.sigma * wb;
        out.segment<2>(b.start) = grow[i] * (c[i] * wb + (s[i] / b.omega) * shifted);
      }
    }
  }
}

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
}

void ClosedFormGap::Load(const Eigen::VectorXd& w) {
  if (end_ >= 0.0) {
    end_value_ = end_value_row_.dot(w);
    end_rate_ = end_rate_row_.dot(w);
  }
  // A few rows of at most a dozen columns: a plain loop (the general product's set-up cost
  // more than the products).
  for (int k = 0; zero_size_ > 0 && k < poly_rows_.rows(); ++k) {
    double sum = 0.0;
    for (int j = 0; j < zero_size_; ++j) sum += poly_rows_(k, j) * w[j];
    poly_[k] = sum;
  }
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
  grow_ = (sigma_ * t).exp();
  // The arrays are padded to whole vectors (the padding's omega is 0).
  for (int k = 0; k < omega_.size(); k += 8)
    VectorSinCos(&omega_[k], t, terms_ - k, &cos_[k], &sin_[k]);
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
  if (t == end_) return {sign_ * end_value_ - offset_, sign_ * end_rate_};  // two dot products
  const int degree = static_cast<int>(poly_.size()) - 1;
  if (zero_size_ > 0) {
    for (int k = degree; k >= 0; --k) value = value * t + poly_[k];
    for (int k = degree; k >= 1; --k) rate = rate * t + static_cast<double>(k) * poly_[k];
  }
  EvaluateTerms(t);
  value += (grow_ * (alpha_ * cos_ + beta_ * sin_)).sum();
  rate += (grow_ * (RateAlpha() * cos_ + RateBeta() * sin_)).sum();
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

double ClosedFormGap::FirstRise(double sign, double horizon) const {
  sign_ = sign;
  horizon_ = horizon;
  offset_ = 0.0;
  Jet start = SearchJet(0.0);
  offset_ = std::max(start.value, 0.0);
  start.value -= offset_;
  return Search(0.0, start, horizon, std::nullopt, 0);
}

double ClosedFormGap::Search(double a, Jet at_a, double b, std::optional<Jet> at_b,
                             int depth) const {
  const double length = b - a;
  // Certificate 1: the wall cannot be reached on [a, b] (most segments end here, before any
  // evaluation at b).
  if (at_a.value + DerivativeBound(a, b, 1) * length <= 0.0) return -1.0;
  if (!at_b) at_b = SearchJet(b);
  // Certificate 2: f' keeps its sign on [a, b], so f is monotone there.
  if (std::abs(at_a.rate) > DerivativeBound(a, b, 2) * length) {
    if (!(at_b->value > 0.0)) return -1.0;
    // Monotone with f(a) <= 0 < f(b): the root to ~eps H, Newton started from a's tangent.
    return BracketedNewtonJet([this](double t) { return SearchJet(t); }, a, b,
                              a - at_a.value / at_a.rate,
                              4.0 * std::numeric_limits<double>::epsilon() * horizon_, 100);
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
