// exp, cos and sin of 8 terms e^{sigma_k t}, omega_k t at a time, shared by the decomposition's
// propagator and the closed-form gaps (spectral_decomposition.cc, spectral_gap.cc).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "gearnvh/solver/small_angle_sincos.h"

#if defined(GEARNVH_HAVE_LIBMVEC) && defined(__AVX512F__)
#include <immintrin.h>
// glibc libmvec (ABI of the OpenMP vector variants): 8 doubles at a time, at most 4 ulp.
extern "C" __m512d _ZGVeN8v_sin(__m512d);
extern "C" __m512d _ZGVeN8v_cos(__m512d);
#define GEARNVH_VECTOR_SINCOS 1
#endif

namespace gearnvh::internal {

// cos(omega_k t) and sin(omega_k t) for k < 8; entries from `live` on (when < 8) are padding.
// Vector calls cost about as much as two scalar ones, so a chunk of 1-3 live terms (tier 1) stays
// scalar, through the small-angle polynomials (no rounding-mode round trip) where they apply.
inline void VectorSinCos(const double* omega, double t, int live, double* c, double* s) {
  live = std::min(live, 8);
#ifdef GEARNVH_VECTOR_SINCOS
  if (live > 3) {
    const __m512d phase = _mm512_mul_pd(_mm512_loadu_pd(omega), _mm512_set1_pd(t));
    _mm512_storeu_pd(c, _ZGVeN8v_cos(phase));
    _mm512_storeu_pd(s, _ZGVeN8v_sin(phase));
    return;
  }
#endif
  for (int k = 0; k < live; ++k) SmallAngleSinCos(omega[k] * t, &s[k], &c[k]);
  for (int k = live; k < 8; ++k) c[k] = 1.0, s[k] = 0.0;
}

// grow_k = e^{sigma_k t}, c_k = cos(omega_k t), s_k = sin(omega_k t) for k < 8 (entries from
// `live` on are padding: 1, 1, 0). Up to 3 live terms (tier 1 has one) are cheaper one by one:
// glibc's scalar exp and the small-angle sin and cos; more go through Eigen's vector exp and the
// vector sincos above.
inline void VectorGrowSinCos(const double* sigma, const double* omega, double t, int live,
                             double* grow, double* c, double* s) {
  live = std::min(live, 8);
  if (live > 3) {
    using Eight = Eigen::Array<double, 8, 1>;
    Eigen::Map<Eight> grown(grow);
    grown = (Eigen::Map<const Eight>(sigma) * t).exp();
    VectorSinCos(omega, t, live, c, s);
    return;
  }
  for (int k = 0; k < live; ++k) {
    grow[k] = std::exp(sigma[k] * t);
    SmallAngleSinCos(omega[k] * t, &s[k], &c[k]);
  }
  for (int k = live; k < 8; ++k) grow[k] = 1.0, c[k] = 1.0, s[k] = 0.0;
}

}  // namespace gearnvh::internal
