// SpectralDecomposition: the generator's block-diagonal form and its propagator (spectral_gap.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "gearnvh/solver/spectral_gap.h"
#include "vector_sincos.h"

extern "C" {
// LAPACK (Fortran ABI; trailing hidden string lengths).
void dgees_(const char* jobvs, const char* sort, int (*select)(const double*, const double*),
            const int* n, double* a, const int* lda, int* sdim, double* wr, double* wi, double* vs,
            const int* ldvs, double* work, const int* lwork, int* bwork, int* info, size_t, size_t);
void dtrsyl_(const char* trana, const char* tranb, const int* isgn, const int* m, const int* n,
             const double* a, const int* lda, const double* b, const int* ldb, double* c,
             const int* ldc, double* scale, int* info, size_t, size_t);
void dtrevc3_(const char* side, const char* howmny, int* select, const int* n, const double* t,
              const int* ldt, double* vl, const int* ldvl, double* vr, const int* ldvr,
              const int* mm, int* m, double* work, const int* lwork, int* info, size_t, size_t);
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
  // The constant and input slots carry the forcing columns, which are tiny next to the stiffness
  // block: a backward error eps |A| would be a large relative error of the forcing, i.e. of the
  // static deflection under it (seen as 1e-16 m in the gap). Scaling the slots so their columns
  // have the norm w_ref makes the forcing as accurate as the rest.
  for (int j = 2 * n; j < m; ++j) {
    const double column = (scale.head(2 * n).asDiagonal() * A.col(j).head(2 * n)).norm();
    if (column > 0.0) scale[j] = column / w_ref;
  }
  // An exosystem's state that forces nothing (an engine order's cosine) takes the scale of the
  // state it turns into (its sine), so the rotation W stays a rotation in the balanced generator.
  for (int j = 2 * n; j < m; ++j) {
    if (!A.col(j).head(2 * n).isZero(0.0)) continue;
    for (int k = 2 * n; k < m; ++k) {
      if (A(j, k) != 0.0 && !A.col(k).head(2 * n).isZero(0.0)) scale[j] = scale[k];
    }
  }
  return scale;
}

// BalancingScale with each exosystem pair (an engine order's states, rows turning into each other
// at w) scaled instead to the response it forces: the acceleration a sin(w t) moves the free
// rotation by a / w^2 and its balanced velocity by a / (w w_ref), far more than a / w_ref^2 below
// the structure's frequencies, and the forcing scale would leave the eigenvectors of +-i w that
// much out of balance (cond(S) ~ (w_ref / w)^2); a / (w min(w, w_ref)) is the larger of the two
// (above w_ref, e.g. a tuple with every mesh free, w_ref = 1, the velocity's).
Eigen::VectorXd DecompositionScale(const Eigen::MatrixXd& A, int n, double w_ref) {
  const int m = static_cast<int>(A.rows());
  Eigen::VectorXd scale = BalancingScale(A, n, w_ref);
  for (int j = 2 * n; j < m; ++j) {
    if (A.row(j).isZero(0.0)) continue;
    Eigen::Index partner = 0;
    const double w = A.row(j).tail(m - 2 * n).cwiseAbs().maxCoeff(&partner);
    partner += 2 * n;
    const double forcing =
        std::max(A.col(j).segment(n, n).norm(), A.col(partner).segment(n, n).norm());
    if (forcing > 0.0) scale[j] = forcing / (w * std::min(w, w_ref));
  }
  return scale;
}

int ZeroClusterSeriesTerms(const Eigen::MatrixXd& B0, double horizon, int min_terms) {
  const int size = static_cast<int>(B0.rows());
  Eigen::MatrixXd power = Eigen::MatrixXd::Identity(size, size);
  std::array<double, kMaxSeriesTerms> terms{};
  double largest = 1.0;
  for (int k = 0; k < kMaxSeriesTerms; ++k) {
    terms[k] = power.cwiseAbs().maxCoeff() * std::pow(horizon, k);
    largest = std::max(largest, terms[k]);
    if (k + 1 >= min_terms && terms[k] <= kSeriesCut * largest) {
      // The chains of a cluster are mostly short (slot -> velocity -> angle: B0^k vanishes to
      // rounding from k = 3 on), so the terms before this one may be below the cut as well.
      int keep = k + 1;
      while (keep > 1 && terms[keep - 1] <= kSeriesCut * largest) --keep;
      return keep;
    }
    power = (B0 * power) / static_cast<double>(k + 1);
  }
  return 0;
}

double ScaledRowNorm(const Eigen::MatrixXd& A, const Eigen::VectorXd& scale) {
  return (scale.asDiagonal() * A * scale.cwiseInverse().asDiagonal())
      .cwiseAbs()
      .rowwise()
      .sum()
      .maxCoeff();
}

SpectralDecomposition DecomposeGenerator(const Eigen::MatrixXd& A, int n, double w_ref,
                                         double horizon, double max_condition) {
  SpectralDecomposition d;
  const int m = static_cast<int>(A.rows());
  const Eigen::VectorXd scale = DecompositionScale(A, n, w_ref);
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
  Eigen::MatrixXd S = Q, S_inv = Q.transpose();
  const int rest = m - sdim;
  // Decouple the zero cluster from the rest: T11 X - X T22 = -T12 (one Sylvester equation).
  if (sdim > 0 && rest > 0) {
    Eigen::MatrixXd X = -T.topRightCorner(sdim, rest);
    double sylvester_scale = 1.0;
    const int isgn = -1;
    const Eigen::MatrixXd T11 = T.topLeftCorner(sdim, sdim);
    const Eigen::MatrixXd T22 = T.bottomRightCorner(rest, rest);
    dtrsyl_("N", "N", &isgn, &sdim, &rest, T11.data(), &sdim, T22.data(), &rest, X.data(), &sdim,
            &sylvester_scale, &info, 1, 1);
    if (info != 0 || sylvester_scale != 1.0) {
      d.info = SpectralDecomposition::Info::kIllConditioned;  // common or close eigenvalues
      return d;
    }
    S.rightCols(rest).noalias() += S.leftCols(sdim) * X;
    S_inv.topRows(sdim).noalias() -= X * S_inv.bottomRows(rest);
  }
  // The rest: T22 = V D V^-1 with D its diagonal blocks and V unit upper triangular (identity
  // diagonal blocks), unique for distinct eigenvalues: the block columns of V are the (real)
  // eigenvectors of T22 (LAPACK dtrevc3, back substitution), each taken so that its own block
  // rows are the identity. In one pass where decoupling block by block (dtrsyl per block) costs
  // a Sylvester solve, with norms of the whole trailing matrix, per block.
  if (rest > 0) {
    // Eigenvalues of different blocks closer than dtrsyl's perturbation threshold: ill-posed.
    const double norm = T.bottomRightCorner(rest, rest).cwiseAbs().maxCoeff();
    const double separation = std::numeric_limits<double>::epsilon() * norm;
    for (size_t a = sdim > 0 ? 1 : 0; a < parts.size(); ++a) {
      for (size_t b = a + 1; b < parts.size(); ++b) {
        const int i = parts[a].first, j = parts[b].first;
        if (std::hypot(wr[i] - wr[j], std::abs(wi[i]) - std::abs(wi[j])) <= separation) {
          d.info = SpectralDecomposition::Info::kIllConditioned;
          return d;
        }
      }
    }
    const Eigen::MatrixXd T22 = T.bottomRightCorner(rest, rest);
    Eigen::MatrixXd vectors(rest, rest), V = Eigen::MatrixXd::Zero(rest, rest);
    thread_local std::vector<double> vector_work;
    vector_work.resize(3 * static_cast<size_t>(rest));
    const int vector_lwork = static_cast<int>(vector_work.size());
    int found = 0;
    dtrevc3_("R", "A", nullptr, &rest, T22.data(), &rest, nullptr, &rest, vectors.data(), &rest,
             &rest, &found, vector_work.data(), &vector_lwork, &info, 1, 1);
    if (info != 0) {
      d.info = SpectralDecomposition::Info::kIllConditioned;
      return d;
    }
    for (const auto& [start, size] : parts) {
      if (start < sdim) continue;
      const int at = start - sdim, top = at + size;  // rows below `top` are zero
      // A complex pair's two columns (real and imaginary part) span the block's invariant plane.
      const Eigen::MatrixXd own = vectors.block(at, at, size, size);
      V.block(0, at, top, size) = vectors.block(0, at, top, size) * own.inverse();
      V.block(at, at, size, size).setIdentity();
    }
    S.rightCols(rest) = S.rightCols(rest) * V;
    V.triangularView<Eigen::UnitUpper>().solveInPlace(S_inv.bottomRows(rest));
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
  // e^{B0 t}: a nilpotent cluster of size sdim needs at least sdim + 1 terms.
  d.series_terms = sdim > 0 ? ZeroClusterSeriesTerms(d.B0, horizon, sdim + 1) : 0;
  d.info = sdim > 0 && d.series_terms == 0 ? SpectralDecomposition::Info::kSeriesDiverged
                                           : SpectralDecomposition::Info::kSuccess;
  return d;
}

namespace {

// e^{B0 t} w0 = w0 + (t/1) B0 (w0 + (t/2) B0 (w0 + ...)), Horner from the highest term down, into
// out.head(kz). K: kz when it is known at compile time (the cluster of a pair's free rotation,
// the constant and one or two input slots: 4 or 5 on every tier; tier 1's free flight, where every
// eigenvalue is zero: 6 or 7, the whole state), else Eigen::Dynamic.
template <int K>
void PropagateZeroCluster(const SpectralDecomposition& d, const Eigen::VectorXd& w, double t,
                          Eigen::VectorXd& out, Eigen::VectorXd& scratch) {
  using Vector = Eigen::Matrix<double, K, 1>;
  const int kz = d.zero_size;
  const Eigen::Map<const Eigen::Matrix<double, K, K>> b0(d.B0.data(), kz, kz);
  const Eigen::Map<const Vector> w0(w.data(), kz);
  Eigen::Map<Vector> head(out.data(), kz), tmp(scratch.data(), kz);
  head = w0;
  for (int k = d.series_terms - 1; k >= 1; --k) {
    tmp.noalias() = b0 * head;
    head = w0 + (t / k) * tmp;
  }
}

}  // namespace

void PropagateDecoupled(const SpectralDecomposition& d, const Eigen::VectorXd& w, double t,
                        Eigen::VectorXd& out, Eigen::VectorXd& scratch) {
  switch (d.zero_size) {
    case 0:
      break;
    case 3:
      PropagateZeroCluster<3>(d, w, t, out, scratch);
      break;
    case 4:
      PropagateZeroCluster<4>(d, w, t, out, scratch);
      break;
    case 5:
      PropagateZeroCluster<5>(d, w, t, out, scratch);
      break;
    case 6:
      PropagateZeroCluster<6>(d, w, t, out, scratch);
      break;
    case 7:
      PropagateZeroCluster<7>(d, w, t, out, scratch);
      break;
    default:
      PropagateZeroCluster<Eigen::Dynamic>(d, w, t, out, scratch);
  }
  const int count = static_cast<int>(d.blocks.size());
  for (int first = 0; first < count; first += 8) {
    // exp(sigma t), cos(omega t), sin(omega t) of 8 blocks at a time.
    using Eight = Eigen::Array<double, 8, 1>;
    Eight grow, c, s;
    internal::VectorGrowSinCos(&d.block_sigma[first], &d.block_omega[first], t, count - first,
                               grow.data(), c.data(), s.data());
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

}  // namespace gearnvh
