// SPDX-License-Identifier: MIT
// The AVX2 + FMA kernels of BlockCholesky (solvers/block/block_kernels_avx2.h); the edge kernels are in
// block_kernels_avx2_edges.cpp. Compiled with -mavx2 -mfma (solvers/CMakeLists.txt), so it must include
// nothing but the include-free core/small_cholesky.h and block_product_avx2.h (internal linkage): see
// the header. Its functions are only called after the baseline code has checked the CPU
// (block_cholesky.cpp, `enabled`).
#include "dualgraph/solvers/block/block_kernels_avx2.h"

#if defined(__AVX2__) && defined(__FMA__)
#include "dualgraph/core/small_cholesky.h"
#include "dualgraph/solvers/block/block_product_avx2.h"

namespace dualgraph::block_kernels_avx2 {

extern const bool kCompiledWithAvx2 = true;

namespace {

/// C −= A · Bᵀ.
inline void subtractProductTransposed(double* c, const double* a, const double* b) {
  product<kSubtract, false>(c, a, [b](int k, int j) { return b + 6 * k + j; }, Never{});
}
/// Lower triangle (and part of the upper) of C −= A · Aᵀ.
inline void subtractGramLower(double* c, const double* a) {
  product<kSubtract, true>(c, a, [a](int k, int j) { return a + 6 * k + j; }, Never{});
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

namespace {

/// The six dot products of A's columns with x, in registers: rows 0–3 of Aᵀ x in `top`, rows 4–5 in
/// `bottom` (products per column, then a horizontal-add network).
inline __attribute__((always_inline)) void transposedTimesVector(const double* a, const double* x, __m256d& top,
                                                                 __m128d& bottom) {
  const __m256d x_top = _mm256_loadu_pd(x);
  const __m128d x_bottom = _mm_loadu_pd(x + 4);
  __m256d p[6];
#pragma GCC unroll 6
  for (int c = 0; c < 6; ++c) {
    // Column c's four upper products with its two lower ones added into lanes 0 and 1.
    const __m256d upper = _mm256_mul_pd(_mm256_loadu_pd(a + 6 * c), x_top);
    const __m128d lower = _mm_mul_pd(_mm_loadu_pd(a + 6 * c + 4), x_bottom);
    p[c] = _mm256_add_pd(upper, _mm256_castpd128_pd256(lower));  // upper lanes of the cast are undefined…
    p[c] = _mm256_blend_pd(upper, p[c], 0x3);                     // …so only lanes 0, 1 take the sum
  }
  const __m256d h01 = _mm256_hadd_pd(p[0], p[1]);  // c0: 0+1, c1: 0+1, c0: 2+3, c1: 2+3
  const __m256d h23 = _mm256_hadd_pd(p[2], p[3]);
  const __m256d h45 = _mm256_hadd_pd(p[4], p[5]);
  top = _mm256_add_pd(_mm256_permute2f128_pd(h01, h23, 0x20), _mm256_permute2f128_pd(h01, h23, 0x31));
  bottom = _mm_add_pd(_mm256_castpd256_pd128(h45), _mm256_extractf128_pd(h45, 1));
}

}  // namespace

void solveColumns(const double* factor, const double* diagonal_inverse, const int* col_begin, const int* row,
                  int num_blocks, double* x) {
  for (int j = 0; j < num_blocks; ++j) {  // L y = b, column by column
    double* x_j = x + 6 * j;
    matrixVector<kAssign>(x_j, diagonal_inverse + 36 * j, x_j);
    for (int p = col_begin[j] + 1; p < col_begin[j + 1]; ++p) matrixVector<kSubtract>(x + 6 * row[p], factor + 36 * p, x_j);
  }
  for (int j = num_blocks - 1; j >= 0; --j) {  // Lᵀ x = y, row by row
    double* x_j = x + 6 * j;
    __m256d r_top = _mm256_loadu_pd(x_j);
    __m128d r_bottom = _mm_loadu_pd(x_j + 4);
    for (int p = col_begin[j] + 1; p < col_begin[j + 1]; ++p) {
      __m256d top;
      __m128d bottom;
      transposedTimesVector(factor + 36 * p, x + 6 * row[p], top, bottom);
      r_top = _mm256_sub_pd(r_top, top);
      r_bottom = _mm_sub_pd(r_bottom, bottom);
    }
    alignas(32) double r[6];
    _mm256_store_pd(r, r_top);
    _mm_store_pd(r + 4, r_bottom);
    __m256d top;
    __m128d bottom;
    transposedTimesVector(diagonal_inverse + 36 * j, r, top, bottom);
    _mm256_storeu_pd(x_j, top);
    _mm_storeu_pd(x_j + 4, bottom);
  }
}

void selectedInverseColumns(const double* factor, const double* diagonal_inverse, double* sigma, double* work,
                            const int* col_begin, const int* target, const int* target_begin,
                            const unsigned char* wanted, int num_blocks) {
  for (int j = num_blocks - 1; j >= 0; --j) {
    if (wanted[j] == 0) continue;
    const int first = col_begin[j] + 1;
    const int m = col_begin[j + 1] - first;
    const double* inverse = diagonal_inverse + 36 * j;
    for (int i = 0; i < m; ++i) multiplyLower(work + 36 * i, factor + 36 * (first + i), inverse);
    const int* t = target + target_begin[j];  // (a, b), a ≥ b: t[a(a+1)/2 + b]
    // Each Σ_aj = −Σ_i Σ(a, i) W_i summed in registers, stored once.
    for (int a = 0; a < m; ++a) {
      Columns sum = zeroColumns();
      for (int i = 0; i < m; ++i) {
        const double* w = work + 36 * i;
        const auto s = [w](int k, int c) { return w + 6 * c + k; };
        if (i <= a) {
          accumulateInto<kSubtract, false, false>(sum, sigma + 36 * t[a * (a + 1) / 2 + i], s, Never{});
        } else {  // Σ(row a, row i) = Σ(row i, row a)ᵀ, the stored block
          accumulateInto<kSubtract, false, true>(sum, sigma + 36 * t[i * (i + 1) / 2 + a], s, Never{});
        }
      }
      store<false>(sigma + 36 * (first + a), sum);
    }
    // L_jj⁻ᵀ L_jj⁻¹ (L_jj⁻¹ is lower triangular: its transpose's column k is zero above row k) − Σ_a W_aᵀ Σ_aj.
    Columns diagonal_sum = zeroColumns();
    accumulateInto<kAdd, false, true>(diagonal_sum, inverse, [inverse](int k, int c) { return inverse + 6 * c + k; },
                                      [](int k, int c) { return k < c; });
    for (int a = 0; a < m; ++a) {
      const double* sigma_aj = sigma + 36 * (first + a);
      accumulateInto<kSubtract, false, true>(diagonal_sum, work + 36 * a, [sigma_aj](int k, int c) { return sigma_aj + 6 * c + k; },
                                             Never{});
    }
    double diagonal[36];
    store<false>(diagonal, diagonal_sum);
    double* sigma_jj = sigma + 36 * col_begin[j];
    for (int c = 0; c < 6; ++c) {
      for (int r = 0; r < 6; ++r) sigma_jj[6 * c + r] = 0.5 * (diagonal[6 * c + r] + diagonal[6 * r + c]);
    }
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
void selectedInverseColumns(const double*, const double*, double*, double*, const int*, const int*, const int*,
                            const unsigned char*, int) {}
void solveColumns(const double*, const double*, const int*, const int*, int, double*) {}

}  // namespace dualgraph::block_kernels_avx2

#endif
