// SPDX-License-Identifier: MIT
// Cholesky and inverse of one 6×6 block; include-free, internal linkage, for baseline and AVX2 builds.
#pragma once

// The factorisation of one diagonal 6×6 block of BlockCholesky, written once for both of its numeric
// loops: block_cholesky.cpp (baseline flags) and block_kernels_avx2.cpp (-mavx2 -mfma); also the covariance
// check's fast path (dual_graph/measurements.cpp). Internal linkage on purpose: each translation unit keeps
// its own copy, so the AVX2 build of this function can never be the one the linker picks for baseline code. No includes (compiler builtins only), as the AVX2
// file requires.

namespace dualgraph::block_factor {
namespace {

/// In-place Cholesky of the symmetric 6×6 block `a` (column-major, 36 doubles; lower triangle read, strict
/// upper zeroed) and L⁻¹ into `inverse` (from the six reciprocals of the diagonal the factorisation
/// computed, so no division sits on the inverse's dependency chain). Returns -1, or the row 0…5 of the
/// first pivot that is not positive and finite, with its value in `pivot` (the block is then unusable).
inline int choleskyAndInverse(double* a, double* inverse, double& pivot) {
  // Every loop fully unrolled (constant indices, no loop control; the zeroing without `rep stos`, whose
  // start-up cost a 36-entry block does not amortise): the block is on the factorisation's critical path.
  double reciprocal[6];  // 1 / L_kk
#pragma GCC unroll 6
  for (int k = 0; k < 6; ++k) {
    double d = a[7 * k];
#pragma GCC unroll 6
    for (int m = 0; m < k; ++m) d -= a[6 * m + k] * a[6 * m + k];
    if (!__builtin_isfinite(d) || !(d > 0.0)) {
      pivot = d;
      return k;
    }
    // 1/√d as √d · (1/d): the square root and the division run side by side instead of one after the
    // other on the column's dependency chain (each pivot waits for the previous column).
    const double l = __builtin_sqrt(d);
    const double r = d > 1e-290 ? l * (1.0 / d) : 1.0 / l;  // (1/d would overflow for subnormal d)
    a[7 * k] = l;
    reciprocal[k] = r;
#pragma GCC unroll 6
    for (int i = k + 1; i < 6; ++i) {
      double s = a[6 * k + i];
#pragma GCC unroll 6
      for (int m = 0; m < k; ++m) s -= a[6 * m + i] * a[6 * m + k];
      a[6 * k + i] = s * r;
    }
  }
#pragma GCC unroll 6
  for (int col = 1; col < 6; ++col) {
#pragma GCC unroll 6
    for (int row = 0; row < col; ++row) a[6 * col + row] = 0.0;
  }
#pragma GCC unroll 6
  for (int c = 0; c < 6; ++c) {
#pragma GCC unroll 6
    for (int row = 0; row < c; ++row) inverse[6 * c + row] = 0.0;
    inverse[7 * c] = reciprocal[c];
#pragma GCC unroll 6
    for (int i = c + 1; i < 6; ++i) {
      double s = 0.0;
#pragma GCC unroll 6
      for (int k = c; k < i; ++k) s += a[6 * k + i] * inverse[6 * c + k];
      inverse[6 * c + i] = -s * reciprocal[i];
    }
  }
  return -1;
}

}  // namespace
}  // namespace dualgraph::block_factor
