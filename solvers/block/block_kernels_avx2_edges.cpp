// SPDX-License-Identifier: MIT
// The AVX2 + FMA kernels of the temporary graph's SE(3) edges (solvers/block/block_kernels_avx2.h): the assembly
// products and eᵀΩe. Compiled with -mavx2 -mfma (solvers/CMakeLists.txt), like block_kernels_avx2.cpp and
// under the same rule: nothing included but block_product_avx2.h. Called only after the baseline code has
// checked the CPU (`enabled`).
#include "dualgraph/solvers/block/block_kernels_avx2.h"

#if defined(__AVX2__) && defined(__FMA__)
#include "dualgraph/solvers/block/block_product_avx2.h"

namespace dualgraph::block_kernels_avx2 {

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

double quadraticForm(const double*, const double*) { return 0.0; }
unsigned nonzeroQuadrants(const double*) { return 15; }
void weightedJacobianTransposed(double*, double*, const double*, double, const double*, unsigned, const double*) {}
void addProduct(double*, const double*, const double*, unsigned, bool) {}

}  // namespace dualgraph::block_kernels_avx2

#endif
