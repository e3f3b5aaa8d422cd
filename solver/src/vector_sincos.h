// cos and sin of 8 phases omega_k t at a time, shared by the decomposition's propagator and the
// closed-form gaps (spectral_decomposition.cc, spectral_gap.cc).
#pragma once

#include <algorithm>
#include <cmath>

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
// scalar.
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
  for (int k = 0; k < live; ++k) sincos(omega[k] * t, &s[k], &c[k]);
  for (int k = live; k < 8; ++k) c[k] = 1.0, s[k] = 0.0;
}

}  // namespace gearnvh::internal
