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
/// The six columns of a 6×6 result in registers: rows 0–3 of column j in top[j], rows 4–5 in bottom[j].
struct Columns {
  __m256d top[6];
  __m128d bottom[6];
};

/// acc ∘= A · S (∘: kAdd or kSubtract, kAssign as kAdd) on 6×6 columns kept in registers; see accumulate.
template <Mode kMode, bool kLowerOnly, bool kTransposedA, typename S, typename Zero>
inline __attribute__((always_inline)) void accumulateInto(Columns& r, const double* a, S s, Zero zero) {
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
        if (!skip_top) r.top[j] = _mm256_fnmadd_pd(a_top, b, r.top[j]);
        r.bottom[j] = _mm_fnmadd_pd(a_bottom, b2, r.bottom[j]);
      } else {
        if (!skip_top) r.top[j] = _mm256_fmadd_pd(a_top, b, r.top[j]);
        r.bottom[j] = _mm_fmadd_pd(a_bottom, b2, r.bottom[j]);
      }
    }
  }
}

inline __attribute__((always_inline)) Columns zeroColumns() {
  Columns r;
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j) {
    r.top[j] = _mm256_setzero_pd();
    r.bottom[j] = _mm_setzero_pd();
  }
  return r;
}

/// C (6×6) =, += or −= A · S for a coefficient map S(k, j) (the right-hand factor's entry (k, j)), skipping
/// the terms `Zero(k, j)` declares exactly zero (triangular factors, an SE(3) Jacobian's zero quadrants;
/// resolved at compile time), left in registers. Every load of A and C happens here, before any store:
/// C may be A in kAssign mode. `kLowerOnly` skips rows 0–3 of columns 4 and 5 (for updates of a diagonal
/// block of which only the lower triangle is read). `kTransposedA`: the left factor is Aᵀ, its column k
/// (A's row k) gathered into registers from A's strided entries (no transposed copy: scalar stores read
/// back by vector loads would stall store forwarding).
template <Mode kMode, bool kLowerOnly, bool kTransposedA, typename S, typename Zero>
inline __attribute__((always_inline)) Columns accumulate(const double* c, const double* a, S s, Zero zero) {
  Columns r = zeroColumns();
  if (kMode != kAssign) {
#pragma GCC unroll 6
    for (int j = 0; j < 6; ++j) {
      r.top[j] = _mm256_loadu_pd(c + 6 * j);
      r.bottom[j] = _mm_loadu_pd(c + 6 * j + 4);
    }
  }
  accumulateInto<kMode, kLowerOnly, kTransposedA>(r, a, s, zero);
  return r;
}

template <bool kLowerOnly>
inline __attribute__((always_inline)) void store(double* c, const Columns& r) {
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j) {
    if (!(kLowerOnly && j >= 4)) _mm256_storeu_pd(c + 6 * j, r.top[j]);
    _mm_storeu_pd(c + 6 * j + 4, r.bottom[j]);
  }
}

/// Stores the transpose P of the 6×6 matrix in `g` at p, with register shuffles, and subtracts P · e from
/// the 6-vector r (from P's columns while they are in registers).
inline __attribute__((always_inline)) void storeTransposedAndSubtractTimesVector(double* p, const Columns& g, const double* e,
                                                                                double* r) {
  __m256d top[6];
  __m128d bottom[6];
  // Rows 0–3 of columns 0–3 → columns 0–3, rows 0–3 (a 4×4 transpose).
  const __m256d u0 = _mm256_unpacklo_pd(g.top[0], g.top[1]);  // (0,0) (0,1) (2,0) (2,1)
  const __m256d u1 = _mm256_unpackhi_pd(g.top[0], g.top[1]);  // (1,0) (1,1) (3,0) (3,1)
  const __m256d u2 = _mm256_unpacklo_pd(g.top[2], g.top[3]);
  const __m256d u3 = _mm256_unpackhi_pd(g.top[2], g.top[3]);
  top[0] = _mm256_permute2f128_pd(u0, u2, 0x20);
  top[1] = _mm256_permute2f128_pd(u1, u3, 0x20);
  top[2] = _mm256_permute2f128_pd(u0, u2, 0x31);
  top[3] = _mm256_permute2f128_pd(u1, u3, 0x31);
  // Rows 0–3 of columns 4, 5 → rows 4, 5 of columns 0–3.
  const __m256d v0 = _mm256_unpacklo_pd(g.top[4], g.top[5]);  // (0,4) (0,5) (2,4) (2,5)
  const __m256d v1 = _mm256_unpackhi_pd(g.top[4], g.top[5]);  // (1,4) (1,5) (3,4) (3,5)
  bottom[0] = _mm256_castpd256_pd128(v0);
  bottom[1] = _mm256_castpd256_pd128(v1);
  bottom[2] = _mm256_extractf128_pd(v0, 1);
  bottom[3] = _mm256_extractf128_pd(v1, 1);
  // Rows 4, 5 of every column → columns 4, 5.
  const __m128d w01 = _mm_unpacklo_pd(g.bottom[0], g.bottom[1]), x01 = _mm_unpackhi_pd(g.bottom[0], g.bottom[1]);
  const __m128d w23 = _mm_unpacklo_pd(g.bottom[2], g.bottom[3]), x23 = _mm_unpackhi_pd(g.bottom[2], g.bottom[3]);
  top[4] = _mm256_insertf128_pd(_mm256_castpd128_pd256(w01), w23, 1);
  top[5] = _mm256_insertf128_pd(_mm256_castpd128_pd256(x01), x23, 1);
  bottom[4] = _mm_unpacklo_pd(g.bottom[4], g.bottom[5]);
  bottom[5] = _mm_unpackhi_pd(g.bottom[4], g.bottom[5]);
  // r −= P e with two accumulators (even and odd k), then the stores.
  __m256d r_top[2] = {_mm256_loadu_pd(r), _mm256_setzero_pd()};
  __m128d r_bottom[2] = {_mm_loadu_pd(r + 4), _mm_setzero_pd()};
#pragma GCC unroll 6
  for (int k = 0; k < 6; ++k) {
    const __m256d b = _mm256_broadcast_sd(e + k);
    r_top[k & 1] = _mm256_fnmadd_pd(top[k], b, r_top[k & 1]);
    r_bottom[k & 1] = _mm_fnmadd_pd(bottom[k], _mm256_castpd256_pd128(b), r_bottom[k & 1]);
  }
#pragma GCC unroll 6
  for (int k = 0; k < 6; ++k) {
    _mm256_storeu_pd(p + 6 * k, top[k]);
    _mm_storeu_pd(p + 6 * k + 4, bottom[k]);
  }
  _mm256_storeu_pd(r, _mm256_add_pd(r_top[0], r_top[1]));
  _mm_storeu_pd(r + 4, _mm_add_pd(r_bottom[0], r_bottom[1]));
}

template <Mode kMode, bool kLowerOnly, bool kTransposedA = false, typename S, typename Zero>
inline __attribute__((always_inline)) void product(double* c, const double* a, S s, Zero zero) {
  store<kLowerOnly>(c, accumulate<kMode, kLowerOnly, kTransposedA>(c, a, s, zero));
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

/// y = A x (kAssign) or y −= A x (kSubtract) for a 6×6 A and 6-vectors (y may be x in kAssign mode).
template <Mode kMode>
inline __attribute__((always_inline)) void matrixVector(double* y, const double* a, const double* x) {
  __m256d top[2] = {kMode == kAssign ? _mm256_setzero_pd() : _mm256_loadu_pd(y), _mm256_setzero_pd()};
  __m128d bottom[2] = {kMode == kAssign ? _mm_setzero_pd() : _mm_loadu_pd(y + 4), _mm_setzero_pd()};
#pragma GCC unroll 6
  for (int k = 0; k < 6; ++k) {
    const __m256d b = _mm256_broadcast_sd(x + k);
    if (kMode == kAssign) {
      top[k & 1] = _mm256_fmadd_pd(_mm256_loadu_pd(a + 6 * k), b, top[k & 1]);
      bottom[k & 1] = _mm_fmadd_pd(_mm_loadu_pd(a + 6 * k + 4), _mm256_castpd256_pd128(b), bottom[k & 1]);
    } else {
      top[k & 1] = _mm256_fnmadd_pd(_mm256_loadu_pd(a + 6 * k), b, top[k & 1]);
      bottom[k & 1] = _mm_fnmadd_pd(_mm_loadu_pd(a + 6 * k + 4), _mm256_castpd256_pd128(b), bottom[k & 1]);
    }
  }
  _mm256_storeu_pd(y, _mm256_add_pd(top[0], top[1]));
  _mm_storeu_pd(y + 4, _mm_add_pd(bottom[0], bottom[1]));
}

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
                            const int* col_begin, const int* target, const int* target_begin, int num_blocks) {
  for (int j = num_blocks - 1; j >= 0; --j) {
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

namespace {

/// Zero(k, j) of a right-hand factor (a Jacobian) whose 3×3 quadrant (r, c) is exactly zero when bit 2r + c
/// of kMask is clear.
template <unsigned kMask>
struct QuadrantZero {
  constexpr bool operator()(int k, int j) const { return ((kMask >> (2 * (k / 3) + j / 3)) & 1u) == 0; }
};

template <unsigned kMask>
void weightedJacobianTransposed(double* p, double* r, const double* information, double weight, const double* j,
                                const double* e) {
  Columns g = accumulate<kAssign, false, false>(p, information, [j](int k, int c) { return j + 6 * c + k; },
                                                QuadrantZero<kMask>{});
  const __m256d w = _mm256_set1_pd(weight);
#pragma GCC unroll 6
  for (int c = 0; c < 6; ++c) {
    g.top[c] = _mm256_mul_pd(g.top[c], w);
    g.bottom[c] = _mm_mul_pd(g.bottom[c], _mm256_castpd256_pd128(w));
  }
  storeTransposedAndSubtractTimesVector(p, g, e, r);
}

template <unsigned kMask, Mode kMode>
void productWithJacobian(double* h, const double* p, const double* j) {
  product<kMode, false>(h, p, [j](int k, int c) { return j + 6 * c + k; }, QuadrantZero<kMask>{});
}

/// The masks of the SE(3) edges' Jacobians get their own code; any other mask is treated as dense (15),
/// which is exact too.
template <unsigned kMask>
void addProductFor(double* h, const double* p, const double* j, bool assign) {
  if (assign) {
    productWithJacobian<kMask, kAssign>(h, p, j);
  } else {
    productWithJacobian<kMask, kAdd>(h, p, j);
  }
}

}  // namespace

double quadraticForm(const double* information, const double* e) {
  double product[6];
  matrixVector<kAssign>(product, information, e);
  const __m256d top = _mm256_mul_pd(_mm256_loadu_pd(product), _mm256_loadu_pd(e));
  const __m128d bottom = _mm_fmadd_pd(_mm_loadu_pd(product + 4), _mm_loadu_pd(e + 4),
                                      _mm_add_pd(_mm256_castpd256_pd128(top), _mm256_extractf128_pd(top, 1)));
  return _mm_cvtsd_f64(_mm_add_sd(bottom, _mm_unpackhi_pd(bottom, bottom)));
}

unsigned nonzeroQuadrants(const double* j) {
  const __m256d left_top = _mm256_or_pd(_mm256_or_pd(_mm256_loadu_pd(j), _mm256_loadu_pd(j + 6)), _mm256_loadu_pd(j + 12));
  const __m128d left_bottom = _mm_or_pd(_mm_or_pd(_mm_loadu_pd(j + 4), _mm_loadu_pd(j + 10)), _mm_loadu_pd(j + 16));
  const __m256d right_top = _mm256_or_pd(_mm256_or_pd(_mm256_loadu_pd(j + 18), _mm256_loadu_pd(j + 24)), _mm256_loadu_pd(j + 30));
  const __m128d right_bottom = _mm_or_pd(_mm_or_pd(_mm_loadu_pd(j + 22), _mm_loadu_pd(j + 28)), _mm_loadu_pd(j + 34));
  // The OR of the bit patterns is ±0 only when every entry is ±0 (NaN compares unequal: nonzero).
  const int lt = _mm256_movemask_pd(_mm256_cmp_pd(left_top, _mm256_setzero_pd(), _CMP_NEQ_UQ));
  const int lb = _mm_movemask_pd(_mm_cmp_pd(left_bottom, _mm_setzero_pd(), _CMP_NEQ_UQ));
  const int rt = _mm256_movemask_pd(_mm256_cmp_pd(right_top, _mm256_setzero_pd(), _CMP_NEQ_UQ));
  const int rb = _mm_movemask_pd(_mm_cmp_pd(right_bottom, _mm_setzero_pd(), _CMP_NEQ_UQ));
  unsigned mask = 0;
  if ((lt & 7) != 0) mask |= 1u;
  if ((rt & 7) != 0) mask |= 2u;
  if ((lt & 8) != 0 || lb != 0) mask |= 4u;
  if ((rt & 8) != 0 || rb != 0) mask |= 8u;
  return mask;
}

void weightedJacobianTransposed(double* p, double* r, const double* information, double weight, const double* j,
                                unsigned j_mask, const double* e) {
  switch (j_mask) {
    case 9: return weightedJacobianTransposed<9>(p, r, information, weight, j, e);
    case 11: return weightedJacobianTransposed<11>(p, r, information, weight, j, e);
    case 13: return weightedJacobianTransposed<13>(p, r, information, weight, j, e);
    default: return weightedJacobianTransposed<15>(p, r, information, weight, j, e);
  }
}

void addProduct(double* h, const double* p, const double* j, unsigned j_mask, bool assign) {
  switch (j_mask) {
    case 9: return addProductFor<9>(h, p, j, assign);
    case 11: return addProductFor<11>(h, p, j, assign);
    case 13: return addProductFor<13>(h, p, j, assign);
    default: return addProductFor<15>(h, p, j, assign);
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
void solveColumns(const double*, const double*, const int*, const int*, int, double*) {}
double quadraticForm(const double*, const double*) { return 0.0; }
unsigned nonzeroQuadrants(const double*) { return 15; }
void weightedJacobianTransposed(double*, double*, const double*, double, const double*, unsigned, const double*) {}
void addProduct(double*, const double*, const double*, unsigned, bool) {}

}  // namespace dualgraph::block_kernels_avx2

#endif
