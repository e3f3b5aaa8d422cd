// Closed-form gaps over a segment: the V3 event path (docs/design.md §4.4).
//
// A generator A (balanced: velocities scaled by 1/w_ref) is brought to an ordered real Schur form
// A = Q T Q^T (LAPACK dgees, the near-zero eigenvalues first) and T is block-diagonalised: the
// near-zero cluster T11 from the rest T22 by a Sylvester equation (LAPACK dtrsyl, Bartels–Stewart)
//   T = [[T11, T12], [0, T22]],  T11 X - X T22 = -T12,  [[I, -X], [0, I]] T [[I, X], [0, I]]
//     = diag(T11, T22),
// then T22 = V diag(B1, ..., Bp) V^-1 with V unit upper triangular, its block columns the
// eigenvectors of T22 (LAPACK dtrevc3) scaled to identity diagonal blocks.
// The result is A = S diag(B0, B1, ..., Bp) S^-1 with B0 the cluster of eigenvalues |lambda| <=
// zero_tolerance * rho (rigid-body rotations, the constant and error slots, an engine order's
// exosystem when its frequency is that low: nilpotent or nearly so, so e^{B0 t} is a short power
// series) and B1..Bp single real eigenvalues (1x1) or
// complex pairs sigma +- i omega (2x2, e^{Bt} = e^{sigma t}[cos(omega t) I + sin(omega t)/omega
// (B - sigma I)]). cond(S) = |S|_1 |S^-1|_1 is recorded; above the caller's limit (nearly equal
// eigenvalues of different blocks) the decomposition reports kIllConditioned and the solver
// falls back to the dense path for that segment and state.
//
// For a gap row c and decoupled coordinates w = S^-1 z, the gap over the segment is
//   g(t) = c S e^{Dt} w = p(t) + sum_k e^{sigma_k t}(alpha_k cos omega_k t + beta_k sin omega_k t)
//                              + sum_r gamma_r e^{lambda_r t},
// scalar work only. FirstRise() finds the first t in (0, H] where sign * g(t) rises above 0:
// interval bisection with two certificates, (1) |g'| <= R on [a, b] and g(a) + R (b - a) <= 0:
// no root; (2) |g'(a)| > C (b - a) with |g''| <= C on [a, b]: g is monotone there, so a root
// exists iff g(b) > 0 and is polished by safeguarded Newton. Roots are exact to rounding; no
// time grid is involved.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace gearnvh {

struct SpectralDecomposition {
  enum class Info { kSuccess, kSchurFailed, kIllConditioned, kSeriesDiverged };
  Info info = Info::kSchurFailed;
  Eigen::MatrixXd S, S_inv;  // in the caller's (unbalanced) coordinates
  int zero_size = 0;         // size of the leading block B0
  Eigen::MatrixXd B0;
  struct Block {
    int start = 0, size = 1;  // rows/columns in the block diagonal
    double sigma = 0.0;       // real part (the eigenvalue itself for size 1)
    double omega = 0.0;       // imaginary part (> 0) for size 2
    Eigen::Matrix2d B = Eigen::Matrix2d::Zero();
  };
  std::vector<Block> blocks;
  // sigma and omega of the blocks (omega = 0 for a 1x1 block), padded with zeros to a multiple of
  // 8 entries: PropagateDecoupled evaluates exp, cos and sin of 8 blocks at a time.
  Eigen::ArrayXd block_sigma, block_omega;
  double condition = 0.0;  // |S|_1 |S^-1|_1 of the balanced transformation
  int series_terms = 0;    // powers of B0 kept for e^{B0 t}, t <= horizon
};
const char* SpectralInfoName(SpectralDecomposition::Info info);

// The balancing D of DecomposeGenerator (balanced generator D A D^-1): 1 on positions, 1/w_ref on
// velocities, and on each constant or input slot the scale that gives its forcing column the norm
// w_ref. Norms of D z weigh positions, velocities and forcing alike.
Eigen::VectorXd BalancingScale(const Eigen::MatrixXd& A, int n, double w_ref);
// BalancingScale with each exosystem pair (an engine order's two states) scaled to the response it
// forces, a / (w min(w, w_ref)) per unit forcing a: the decomposition's balance (its eigenvectors
// of +-i w would be out of balance by (w_ref / w)^2 under the forcing scale) and the norm of the
// carry's error bound. The max-norm bounds of the dense path and of segment-run fusion take
// BalancingScale, which keeps the exosystem's states small.
Eigen::VectorXd DecompositionScale(const Eigen::MatrixXd& A, int n, double w_ref);
// ||D A D^-1||_inf for a diagonal scale D (e.g. BalancingScale): with q = this norm times d, the
// degree-P Taylor polynomial of e^{A tau} y, 0 <= tau <= d, is within e^q q^(P+1) / (P+1)!
// ||D y||_inf of it in the norm ||D .||_inf.
double ScaledRowNorm(const Eigen::MatrixXd& A, const Eigen::VectorXd& scale);

// Decomposes the augmented generator A (n reduced DOF, velocities balanced by w_ref as in
// BalancedExpm) for times up to `horizon`.
SpectralDecomposition DecomposeGenerator(const Eigen::MatrixXd& A, int n, double w_ref,
                                         double horizon, double max_condition);

// The terms of e^{B0 t} = sum_k B0^k t^k / k! that matter for t <= horizon: examines at least
// `min_terms`, then until a term is below 1e-18 of the largest, and keeps the terms up to the last
// one above that cut (every term dropped is at or below it); 0 when 64 terms do not get there.
int ZeroClusterSeriesTerms(const Eigen::MatrixXd& B0, double horizon, int min_terms);

// e^{Dt} w for the block-diagonal D of `d`. No allocation: `out` has the size of w and `scratch`
// at least zero_size entries.
void PropagateDecoupled(const SpectralDecomposition& d, const Eigen::VectorXd& w, double t,
                        Eigen::VectorXd& out, Eigen::VectorXd& scratch);

// The closed form of one gap row on one decomposition. Construction precomputes rows and each
// term's rate |sigma + i omega|; Load() takes the decoupled state of a segment start (and each
// term's amplitude); the rest is scalar work without allocation. The terms are stored as arrays
// (a real eigenvalue is a term with omega = 0 and beta = 0), so the per-term work of Load() and of
// every evaluation (exp(sigma t) included) runs over contiguous arrays in vector instructions.
// The search evaluates value and rate together (one exp and one sincos per term and point) and
// reuses every point it has evaluated, and its derivative bounds cost one division per damped
// term: e^{sigma a} <= 1 / (1 - sigma a) for sigma <= 0 (equal at a = 0, within
// 1 + (sigma a)^2 / 2 for small sigma a).
class ClosedFormGap {
 public:
  ClosedFormGap() = default;
  ClosedFormGap(const SpectralDecomposition& d, const Eigen::RowVectorXd& row);
  // As above, with the rows of g(H) and g'(H) in w precomputed for the segment length H
  // (u e^{DH} and u D e^{DH}, u = row S): Load() then takes both at the segment end with two dot
  // products, and a search over the whole segment evaluates its end point without exp or sincos.
  ClosedFormGap(const SpectralDecomposition& d, const Eigen::RowVectorXd& row, double horizon);
  ClosedFormGap(const ClosedFormGap& other);
  ClosedFormGap& operator=(const ClosedFormGap& other);
  ClosedFormGap(ClosedFormGap&&) noexcept = default;
  ClosedFormGap& operator=(ClosedFormGap&&) noexcept = default;

  void Load(const Eigen::VectorXd& w);
  // As Load(w) for the gap g(t) + constant: one closed form serves every wall that differs from
  // the row only by a constant (the train solver's walls e_ij +- b_i). Needs zero_size > 0 (an
  // augmented generator always has the constant slot's zero eigenvalue).
  void Load(const Eigen::VectorXd& w, double constant);
  // Adds `delta` to the loaded constant (the other wall of the same loaded state, without a
  // reload: the rates and bounds do not depend on the constant).
  void ShiftConstant(double delta) { poly()[0] += delta; }
  double Value(double t) const { return Evaluate(t, 0); }
  // g(0) of the loaded state, without exp or sincos.
  double StartValue() const;
  // g(H) and g'(H) of the loaded state from the end rows (constructed with a horizon H).
  double EndValue() const { return end_value_; }
  double EndRate() const { return end_rate_; }
  double Rate(double t) const { return Evaluate(t, 1); }
  // Whether |g'(t)| <= limit at a root t returned by FirstRise, decided without exp or sincos
  // where the search's last evaluation (time t_l, rate r_l) settles it: within 8 eps horizon of
  // t (Newton's last iterate, which the root is within 4 eps horizon of) r_l is taken as g'(t)
  // (they differ by |g''| 8 eps horizon at most, far below the grazing tolerance this is
  // compared with); when the root was accepted from Newton's error bound one step from t_l,
  // |g'(t) - r_l| <= C |t - t_l| with C the search's bound of |g''|, which decides unless the
  // limit lies within that spread. Otherwise Rate(t).
  bool RateWithin(double t, double limit) const;
  double Curvature(double t) const { return Evaluate(t, 2); }
  // The screen of a segment start (constructed with a horizon H), without Load(): true when
  // sign * g(t) <= -gap_floor for every t in [0, H], so FirstRise(sign, H) finds no root. It
  // costs two dot products of length m:
  //   sign g(t) <= sign g(0) + t max|g'| <= sign g(0) + reach . |w| - margin . |w|,
  // with max|g'| on [0, H] bounded by sum_k k H^(k-1) |P_k . w0| (the polynomial part) plus, per
  // term, e^{max(sigma, 0) H} |sigma + i omega| |(alpha, beta)|, and |(alpha, beta)| <= |w_a|
  // |(r1a, r2a)| + |w_b| |(r1b, r2b)| (triangle inequality), so reach_i = H (those weights of
  // w_i) + margin_i, where margin_i = (4 m + 64) eps (the largest magnitude of w_i's terms on
  // [0, H]) keeps the evaluated closed form of the search below 0 as well (its rounding).
  // When that linear bound fails (a wall within reach), the curved one decides: with C >=
  // max|g''| on [0, H] (weights of |w| as above, rate^2 per term), f = sign g lies below both
  //   U0(t) = f(0) + f'(0) t + C t^2 / 2  and  UH(t) = f(H) - f'(H)(H - t) + C (H - t)^2 / 2;
  // U0 - UH is linear in t, so max of min(U0, UH) on [0, H] is at 0, H or where they cross.
  // A template over the vector type: a caller that knows m at compile time (a fixed-size vector
  // or map, SpectralLocator at tier 1) gets unrolled dot products (w is the left operand: Eigen
  // takes an expression's compile-time size from it).
  template <class Vector>
  bool ClearOfWall(const Eigen::MatrixBase<Vector>& w, double sign, double gap_floor) const {
    const double start = sign * w.dot(Row(kScreenStart));
    if (start + w.cwiseAbs().dot(Row(kScreenReach)) + gap_floor <= 0.0) return true;
    return start < -gap_floor && ClearOfWallCurved(w, sign, start, gap_floor);
  }
  // The rows of ClearOfWall's linear test, g(0) = start . w and the reach weights (constructed
  // with a horizon): SpectralLocator keeps copies in its carried-segment blocks.
  Eigen::Map<const Eigen::RowVectorXd> ScreenStartRow() const {
    return {Data(kScreenStart), row_size_};
  }
  Eigen::Map<const Eigen::RowVectorXd> ScreenReachRow() const {
    return {Data(kScreenReach), row_size_};
  }
  // The curved test's rows (constructed with a horizon): first the kCurvedSignedRows rows of
  // g(H), g'(0) and g'(H) (their products with w times the wall's sign), then the weights of |w|:
  // the rounding margin and the bound of max|g''| on [0, H]. SpectralLocator keeps copies
  // beside its blocks.
  static constexpr int kCurvedRows = 5, kCurvedSignedRows = 3;
  Eigen::Map<const Eigen::RowVectorXd> CurvedScreenRow(int k) const {
    constexpr Part kRows[kCurvedRows] = {kEndValueRow, kScreenRate, kEndRateRow, kScreenMargin,
                                         kScreenCurve};
    return {Data(kRows[k]), row_size_};
  }
  // ClearOfWall's curved test from its products with w (CurvedScreenRow order): start = sign g(0),
  // end = sign g(H), start_rate = sign g'(0), end_rate = sign g'(H), the margin, curve >=
  // max|g''| on [0, H = horizon].
  static bool CurvedScreenClear(double start, double end, double start_rate, double end_rate,
                                double margin, double curve, double horizon, double gap_floor);
  // The bytes it occupies (the object and its arrays).
  size_t bytes() const {
    return sizeof(*this) + storage_doubles_ * sizeof(double) + growing_.capacity() * sizeof(int);
  }
  // An upper bound of |d^order g / dt^order| on [a, b], 0 <= a <= b, order 1 or 2.
  double DerivativeBound(double a, double b, int order) const;
  // First t in (0, horizon] where sign * g(t) - offset > 0, or -1; offset = max(0, sign g(0)) so
  // a start on the wall (within rounding, right after an event) counts as inside.
  double FirstRise(double sign, double horizon) const;

 private:
  // sign * g - offset and sign * g' at one time.
  struct Jet {
    double value = 0.0, rate = 0.0;
  };
  // Builds the arrays (horizon < 0: without the end and screen rows).
  void Build(const SpectralDecomposition& d, const Eigen::RowVectorXd& row, double horizon);
  double Evaluate(double t, int order) const;
  // grow = e^{sigma t}, cosines = cos(omega t), sines = sin(omega t) for every term.
  void EvaluateTerms(double t) const;
  Jet SearchJet(double t) const;
  // ClearOfWall's second test, given start = sign g(0).
  template <class Vector>
  bool ClearOfWallCurved(const Eigen::MatrixBase<Vector>& w, double sign, double start,
                         double gap_floor) const;
  double Search(double a, Jet at_a, double b, std::optional<Jet> at_b, int depth) const;
  // The root on [a, b] where f rises monotonically from f(a) <= 0 to f(b) > 0 with |f''| <=
  // curvature: safeguarded Newton to 4 eps horizon, from the root of the quadratic through f(a),
  // f'(a), f(b), stopping without a last evaluation when Newton's error bound already places the
  // next iterate within the tolerance.
  double Polish(double a, Jet at_a, double b, Jet at_b, double curvature) const;

  // Every array of the closed form lives in one block (storage_), each part at a 64-byte aligned
  // offset as Eigen's own arrays are (so the vectorised sums add in the same order), in the order
  // Load() and the search read them: a piece touches consecutive cache lines, not ~20 heap
  // blocks. The parts:
  //   kIndex: index_a (padded ints) then index_b. One entry per block of the decomposition: a 2x2
  //     block's term e^{sigma t}(alpha cos omega t + beta sin omega t), alpha = r1a w[index_a] +
  //     r1b w[index_b], beta = r2a w[index_a] + r2b w[index_b]; a 1x1 block's term alpha
  //     e^{sigma t} with omega = 0, index_b = index_a and r1b = r2a = r2b = 0. Padded to a
  //     multiple of 8 entries with zero terms; terms_ are real.
  //   kRates: |sigma + i omega|, the factor each derivative adds.
  //   kAlpha, kBeta, kBound1 (loaded): the coefficients, and amplitude sqrt(alpha^2 + beta^2)
  //     times rate (the bound of |g''| has one more factor rate), with the sums of both.
  //   kPolyRows: p_k = poly_rows.row(k) . w0, with w0 the B0 part of w; kPoly the loaded p_k.
  //   kDampedSigma: min(sigma, 0), for the bound 1 / (1 - sigma a).
  //   kGrow, kCosines, kSines: scratch of the evaluations (no allocation after construction).
  //   With a horizon H: the rows of g(H) and g'(H) (kEndValueRow, kEndRateRow); the screen's rows
  //     (ClearOfWall): g(0) = start . w and the reach weights; the curved test's rows: g'(0) =
  //     rate . w, the weights of max|g''| on [0, H], and the rounding margin alone (margin_i).
  enum Part {
    kIndex,
    kR1a,
    kR1b,
    kR2a,
    kR2b,
    kRates,
    kAlpha,
    kBeta,
    kBound1,
    kPolyRows,
    kPoly,
    kSigma,
    kOmega,
    kDampedSigma,
    kGrow,
    kCosines,
    kSines,
    kEndValueRow,
    kEndRateRow,
    kScreenStart,
    kScreenReach,
    kScreenRate,
    kScreenCurve,
    kScreenMargin,
    kParts
  };
  struct FreeAligned {
    void operator()(double* p) const;
  };
  using ArrayMap = Eigen::Map<Eigen::ArrayXd, Eigen::AlignedMax>;
  // Writable maps also from const methods: the evaluation scratch (kGrow, kCosines, kSines) is
  // written by the const search, as the mutable members it replaces were.
  double* Data(Part part) const { return storage_.get() + part_offset_[part]; }
  ArrayMap Terms(Part part) const { return ArrayMap(Data(part), padded_); }
  const int* index_a() const { return reinterpret_cast<const int*>(Data(kIndex)); }
  const int* index_b() const { return index_a() + padded_; }
  ArrayMap sigma() const { return Terms(kSigma); }
  ArrayMap omega() const { return Terms(kOmega); }
  ArrayMap rates() const { return Terms(kRates); }
  ArrayMap damped_sigma() const { return Terms(kDampedSigma); }
  ArrayMap r1a() const { return Terms(kR1a); }
  ArrayMap r1b() const { return Terms(kR1b); }
  ArrayMap r2a() const { return Terms(kR2a); }
  ArrayMap r2b() const { return Terms(kR2b); }
  ArrayMap alpha() const { return Terms(kAlpha); }
  ArrayMap beta() const { return Terms(kBeta); }
  ArrayMap bound1() const { return Terms(kBound1); }
  ArrayMap grow() const { return Terms(kGrow); }
  ArrayMap cosines() const { return Terms(kCosines); }
  ArrayMap sines() const { return Terms(kSines); }
  Eigen::Map<Eigen::MatrixXd, Eigen::AlignedMax> poly_rows() const {
    return {Data(kPolyRows), poly_terms_, zero_size_};
  }
  Eigen::Map<Eigen::VectorXd, Eigen::AlignedMax> poly() const { return {Data(kPoly), poly_terms_}; }
  Eigen::Map<Eigen::RowVectorXd, Eigen::AlignedMax> Row(Part part) const {
    return {Data(part), row_size_};
  }
  std::unique_ptr<double[], FreeAligned> storage_;
  size_t storage_doubles_ = 0;
  std::array<int, kParts> part_offset_{};  // in storage_, doubles
  int terms_ = 0;                          // live terms (blocks of the decomposition)
  int padded_ = 0;                         // terms padded to a multiple of 8
  int poly_terms_ = 0;                     // rows of poly_rows (at least 1)
  int row_size_ = 0;                       // m with a horizon, else 0
  std::vector<int> growing_;               // the terms with sigma > 0 (bounded by e^{sigma b})
  double bound1_sum_ = 0.0, bound2_sum_ = 0.0;
  // The coefficients of g': d/dt [e^{st}(a cos wt + b sin wt)] = e^{st}(A cos wt + B sin wt).
  auto RateAlpha() const { return sigma() * alpha() + omega() * beta(); }
  auto RateBeta() const { return sigma() * beta() - omega() * alpha(); }
  int zero_size_ = 0;
  // The segment end H (< 0: none) and g(H), g'(H) of the loaded state.
  double end_ = -1.0;
  double end_value_ = 0.0, end_rate_ = 0.0;
  // Search state (set by FirstRise).
  mutable double sign_ = 1.0, offset_ = 0.0, horizon_ = 0.0;
  // The search's last evaluated time and g' there (RateWithin; last_time_ < 0: none yet), and
  // the bound of |g''| when Polish accepted its root one Newton step from there (< 0: not so).
  mutable double last_time_ = -1.0, last_rate_ = 0.0, last_curvature_ = -1.0;
};

template <class Vector>
bool ClosedFormGap::ClearOfWallCurved(const Eigen::MatrixBase<Vector>& w, double sign, double start,
                                      double gap_floor) const {
  return CurvedScreenClear(start, sign * w.dot(Row(kEndValueRow)), sign * w.dot(Row(kScreenRate)),
                           sign * w.dot(Row(kEndRateRow)), w.cwiseAbs().dot(Row(kScreenMargin)),
                           w.cwiseAbs().dot(Row(kScreenCurve)), end_, gap_floor);
}

// Inline: the carried path calls it on the segments that approach a wall.
inline bool ClosedFormGap::CurvedScreenClear(double start, double end, double start_rate,
                                             double end_rate, double margin, double curve,
                                             double horizon, double gap_floor) {
  const double h = horizon, c = curve;
  if (!(end + margin + gap_floor < 0.0)) return false;
  // The rounding of the quantities below, relative to their size.
  const double slack = 1e-12 * (std::abs(start) + std::abs(end) +
                                (std::abs(start_rate) + std::abs(end_rate)) * h + c * h * h);
  double bound = std::max(start, end);
  // U0(t) - UH(t) = (f(0) - f(H) + f'(H) H - C H^2 / 2) + t (f'(0) - f'(H) + C H).
  const double offset = start - end + end_rate * h - 0.5 * c * h * h;
  const double slope = start_rate - end_rate + c * h;
  if (slope != 0.0) {
    const double cross = -offset / slope;
    if (cross > 0.0 && cross < h)
      bound = std::max(bound, start + start_rate * cross + 0.5 * c * cross * cross);
  }
  return bound + slack + margin + gap_floor <= 0.0;
}

}  // namespace gearnvh
