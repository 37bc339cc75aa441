// SPDX-License-Identifier: MIT
// The AVX2 + FMA kernels (solvers/block_kernels_avx2.h). This file alone is compiled with -mavx2 -mfma
// (solvers/CMakeLists.txt) and must include nothing but intrinsics and the include-free
// block_diagonal_factor.h (internal linkage): see the header. Its functions are
// only called after the baseline code has checked the CPU (block_cholesky.cpp, `enabled`).
#include "solvers/block_kernels_avx2.h"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>

#include "solvers/block_diagonal_factor.h"

namespace dualgraph::block_kernels_avx2 {

extern const bool kCompiledWithAvx2 = true;

namespace {

enum Mode { kAssign, kAdd, kSubtract };

/// C (6×6) =, += or −= A · S for a coefficient map S(k, j) (the right-hand factor's entry (k, j)), skipping
/// the terms `Zero(k, j)` declares exactly zero (triangular factors; resolved at compile time). All six
/// result columns stay in registers (rows 0–3 in one ymm, rows 4–5 in one xmm) until the stores, and every
/// load of A comes before them: C may be A in kAssign mode. `kLowerOnly` skips rows 0–3 of columns 4 and 5
/// (for updates of a diagonal block of which only the lower triangle is read). `kTransposedA`: the left
/// factor is Aᵀ, its column k (A's row k) gathered into registers from A's strided entries (no transposed
/// copy: scalar stores read back by vector loads would stall store forwarding).
template <Mode kMode, bool kLowerOnly, bool kTransposedA = false, typename S, typename Zero>
inline __attribute__((always_inline)) void product(double* c, const double* a, S s, Zero zero) {
  __m256d top[6];
  __m128d bottom[6];
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j) {
    if (kMode == kAssign) {
      top[j] = _mm256_setzero_pd();
      bottom[j] = _mm_setzero_pd();
    } else {
      top[j] = _mm256_loadu_pd(c + 6 * j);
      bottom[j] = _mm_loadu_pd(c + 6 * j + 4);
    }
  }
#pragma GCC unroll 6
  for (int k = 0; k < 6; ++k) {
    const __m256d a_top = kTransposedA ? _mm256_set_pd(a[18 + k], a[12 + k], a[6 + k], a[k]) : _mm256_loadu_pd(a + 6 * k);
    const __m128d a_bottom = kTransposedA ? _mm_set_pd(a[30 + k], a[24 + k]) : _mm_loadu_pd(a + 6 * k + 4);
#pragma GCC unroll 6
    for (int j = 0; j < 6; ++j) {
      if (zero(k, j)) continue;
      const __m256d b = _mm256_broadcast_sd(s(k, j));
      const __m128d b2 = _mm256_castpd256_pd128(b);
      const bool skip_top = kLowerOnly && j >= 4;
      if (kMode == kSubtract) {
        if (!skip_top) top[j] = _mm256_fnmadd_pd(a_top, b, top[j]);
        bottom[j] = _mm_fnmadd_pd(a_bottom, b2, bottom[j]);
      } else {
        if (!skip_top) top[j] = _mm256_fmadd_pd(a_top, b, top[j]);
        bottom[j] = _mm_fmadd_pd(a_bottom, b2, bottom[j]);
      }
    }
  }
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j) {
    if (!(kLowerOnly && j >= 4)) _mm256_storeu_pd(c + 6 * j, top[j]);
    _mm_storeu_pd(c + 6 * j + 4, bottom[j]);
  }
}

struct Never {
  constexpr bool operator()(int, int) const { return false; }
};

/// C −= A · Bᵀ.
inline void subtractProductTransposed(double* c, const double* a, const double* b) {
  product<kSubtract, false>(c, a, [b](int k, int j) { return b + 6 * k + j; }, Never{});
}
/// Lower triangle (and part of the upper) of C −= A · Aᵀ.
inline void subtractGramLower(double* c, const double* a) {
  product<kSubtract, true>(c, a, [a](int k, int j) { return a + 6 * k + j; }, Never{});
}
/// C −= A · B.
inline void subtractProduct(double* c, const double* a, const double* b) {
  product<kSubtract, false>(c, a, [b](int k, int j) { return b + 6 * j + k; }, Never{});
}
/// C −= Aᵀ · B.
inline void subtractTransposedProduct(double* c, const double* a, const double* b) {
  product<kSubtract, false, true>(c, a, [b](int k, int j) { return b + 6 * j + k; }, Never{});
}
/// X ← X · Lᵀ in place (L lower triangular).
inline void multiplyTransposedLowerInPlace(double* x, const double* l) {
  product<kAssign, false>(x, x, [l](int k, int j) { return l + 6 * k + j; }, [](int k, int j) { return k > j; });
}
/// W = X · L (L lower triangular).
inline void multiplyLower(double* w, const double* x, const double* l) {
  product<kAssign, false>(w, x, [l](int k, int j) { return l + 6 * j + k; }, [](int k, int j) { return k < j; });
}

}  // namespace

bool factorizeColumns(double* factor, double* diagonal_inverse, const int* col_begin, const int* target,
                      const int* target_begin, int num_blocks, PivotFailure& failure) {
  for (int j = 0; j < num_blocks; ++j) {
    double* inverse = diagonal_inverse + 36 * j;
    const int failed = block_factor::choleskyAndInverse(factor + 36 * col_begin[j], inverse, failure.pivot);
    if (failed >= 0) {
      failure.row = 6 * j + failed;
      return false;
    }
    const int first = col_begin[j] + 1;
    const int end = col_begin[j + 1];
    for (int p = first; p < end; ++p) multiplyTransposedLowerInPlace(factor + 36 * p, inverse);
    const int* t = target + target_begin[j];
    for (int a = first; a < end; ++a) {
      for (int b = first; b < a; ++b) subtractProductTransposed(factor + 36 * *t++, factor + 36 * a, factor + 36 * b);
      subtractGramLower(factor + 36 * *t++, factor + 36 * a);
    }
  }
  return true;
}

void selectedInverseColumns(const double* factor, const double* diagonal_inverse, double* sigma, double* work,
                            const int* col_begin, const int* target, const int* target_begin, int num_blocks) {
  for (int j = num_blocks - 1; j >= 0; --j) {
    const int first = col_begin[j] + 1;
    const int m = col_begin[j + 1] - first;
    const double* inverse = diagonal_inverse + 36 * j;
    for (int i = 0; i < m; ++i) multiplyLower(work + 36 * i, factor + 36 * (first + i), inverse);
    const int* t = target + target_begin[j];  // (a, b), a ≥ b: t[a(a+1)/2 + b]
    for (int a = 0; a < m; ++a) {
      double* sigma_aj = sigma + 36 * (first + a);
      for (int e = 0; e < 36; ++e) sigma_aj[e] = 0.0;
      for (int i = 0; i < m; ++i) {
        if (i <= a) {
          subtractProduct(sigma_aj, sigma + 36 * t[a * (a + 1) / 2 + i], work + 36 * i);
        } else {
          subtractTransposedProduct(sigma_aj, sigma + 36 * t[i * (i + 1) / 2 + a], work + 36 * i);
        }
      }
    }
    double diagonal[36];  // L_jj⁻ᵀ L_jj⁻¹ (L_jj⁻¹ is lower triangular: its transpose's column k is zero above row k)
    product<kAssign, false, true>(diagonal, inverse, [inverse](int k, int c) { return inverse + 6 * c + k; },
                                  [](int k, int c) { return k < c; });
    for (int a = 0; a < m; ++a) subtractTransposedProduct(diagonal, work + 36 * a, sigma + 36 * (first + a));
    double* sigma_jj = sigma + 36 * col_begin[j];
    for (int c = 0; c < 6; ++c) {
      for (int r = 0; r < 6; ++r) sigma_jj[6 * c + r] = 0.5 * (diagonal[6 * c + r] + diagonal[6 * r + c]);
    }
  }
}

void multiply(double* g, const double* w, const double* j) {
  product<kAssign, false>(g, w, [j](int k, int c) { return j + 6 * c + k; }, Never{});
}

void addTransposedProduct(double* h, const double* j, const double* g) {
  product<kAdd, false, true>(h, j, [g](int k, int c) { return g + 6 * c + k; }, Never{});
}

void subtractTransposedTimesVector(double* r, const double* g, const double* e) {
  const __m256d e_top = _mm256_loadu_pd(e);
  const __m128d e_bottom = _mm_loadu_pd(e + 4);
  for (int c = 0; c < 6; ++c) {
    const __m256d p = _mm256_mul_pd(_mm256_loadu_pd(g + 6 * c), e_top);
    const __m128d q = _mm_fmadd_pd(_mm_loadu_pd(g + 6 * c + 4), e_bottom,
                                   _mm_add_pd(_mm256_castpd256_pd128(p), _mm256_extractf128_pd(p, 1)));
    r[c] -= _mm_cvtsd_f64(_mm_add_sd(q, _mm_unpackhi_pd(q, q)));
  }
}

}  // namespace dualgraph::block_kernels_avx2

#else  // not compiled for AVX2 + FMA: never called (enabled() is false); defined so that the library links.

namespace dualgraph::block_kernels_avx2 {

extern const bool kCompiledWithAvx2 = false;

bool factorizeColumns(double*, double*, const int*, const int*, const int*, int, PivotFailure& failure) {
  failure.row = -1;
  return false;
}
void selectedInverseColumns(const double*, const double*, double*, double*, const int*, const int*, const int*, int) {}
void multiply(double*, const double*, const double*) {}
void addTransposedProduct(double*, const double*, const double*) {}
void subtractTransposedTimesVector(double*, const double*, const double*) {}

}  // namespace dualgraph::block_kernels_avx2

#endif
