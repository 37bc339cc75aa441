// SPDX-License-Identifier: MIT
// The 6×6 block products of BlockCholesky for the baseline build (SSE2, no FMA).
#pragma once

#include <Eigen/Core>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace dualgraph::block_kernels {

/// Dense 6×6 block products for the block Cholesky (solvers/block/block_cholesky.h), written for the default
/// build flags (SSE2: two doubles per instruction, no FMA). Eigen's fixed-size products of this size
/// reload operands and broadcast every right-hand coefficient separately; these kernels keep two result
/// columns (six packets) in registers, skip the exact zeros of triangular factors, and compute only the
/// lower half of the symmetric update of a diagonal block. Timed on the temporary graph's pattern by
/// BM_BlockCholesky_TemporaryPattern (avx2:0; bench/README.md, "Distillation (temporary graph)").
///
/// Blocks are column-major `Eigen::Matrix<double, 6, 6>` (16-byte aligned, as Eigen stores them). The
/// A·B and A·Bᵀ kernels add or subtract their k-terms one by one into C's packets, in increasing k (Eigen
/// sums the terms first and then adds the sum: the last bits may differ); Aᵀ·B sums each dot product's even
/// and odd terms separately. No kernel reads entries of C it does not write. Outputs must not alias inputs
/// unless stated.
using Block = Eigen::Matrix<double, 6, 6>;

namespace detail {

#if defined(__SSE2__)
using Packet = __m128d;
inline Packet load(const double* p) { return _mm_load_pd(p); }
inline void store(double* p, Packet x) { _mm_store_pd(p, x); }
inline Packet broadcast(double x) { return _mm_set1_pd(x); }
inline Packet add(Packet a, Packet b) { return _mm_add_pd(a, b); }
inline Packet sub(Packet a, Packet b) { return _mm_sub_pd(a, b); }
inline Packet mul(Packet a, Packet b) { return _mm_mul_pd(a, b); }
inline Packet unpackLow(Packet a, Packet b) { return _mm_unpacklo_pd(a, b); }
inline Packet unpackHigh(Packet a, Packet b) { return _mm_unpackhi_pd(a, b); }
#else
struct Packet {
  double v[2];
};
inline Packet load(const double* p) { return {{p[0], p[1]}}; }
inline void store(double* p, Packet x) { p[0] = x.v[0], p[1] = x.v[1]; }
inline Packet broadcast(double x) { return {{x, x}}; }
inline Packet add(Packet a, Packet b) { return {{a.v[0] + b.v[0], a.v[1] + b.v[1]}}; }
inline Packet sub(Packet a, Packet b) { return {{a.v[0] - b.v[0], a.v[1] - b.v[1]}}; }
inline Packet mul(Packet a, Packet b) { return {{a.v[0] * b.v[0], a.v[1] * b.v[1]}}; }
inline Packet unpackLow(Packet a, Packet b) { return {{a.v[0], b.v[0]}}; }
inline Packet unpackHigh(Packet a, Packet b) { return {{a.v[1], b.v[1]}}; }
#endif

enum Op { kAssign, kAdd, kSubtract };

/// Rows [2·P0, 6) of columns j and j + 1 of C =, += or −= Σ_{k ∈ [K0, K1)} A(:, k) · [s(k, j), s(k, j + 1)],
/// where `S` maps (k, column) to the right-hand coefficient. The six packets stay in registers (started
/// from C, or from the first term for =) and each term is added or subtracted in increasing k; one store.
/// Every load of A happens before the first store to C, so C may be A when the pair's columns are not read
/// by a later call.
template <int P0, int K0, int K1, Op kOp, typename S>
inline void columnPair(double* c, const double* a, int j, S s) {
  static_assert(0 <= P0 && P0 < 3 && 0 <= K0 && K0 < K1 && K1 <= 6, "6x6 block");
  Packet sum0[3], sum1[3];
  for (int p = P0; p < 3; ++p) {
    if (kOp == kAssign) {
      const Packet x = load(a + 6 * K0 + 2 * p);
      sum0[p] = mul(x, broadcast(s(K0, j)));
      sum1[p] = mul(x, broadcast(s(K0, j + 1)));
    } else {
      sum0[p] = load(c + 6 * j + 2 * p);
      sum1[p] = load(c + 6 * j + 6 + 2 * p);
    }
  }
  for (int k = kOp == kAssign ? K0 + 1 : K0; k < K1; ++k) {
    const Packet b0 = broadcast(s(k, j)), b1 = broadcast(s(k, j + 1));
    for (int p = P0; p < 3; ++p) {
      const Packet x = load(a + 6 * k + 2 * p);
      sum0[p] = kOp == kSubtract ? sub(sum0[p], mul(x, b0)) : add(sum0[p], mul(x, b0));
      sum1[p] = kOp == kSubtract ? sub(sum1[p], mul(x, b1)) : add(sum1[p], mul(x, b1));
    }
  }
  for (int p = P0; p < 3; ++p) {
    store(c + 6 * j + 2 * p, sum0[p]);
    store(c + 6 * j + 6 + 2 * p, sum1[p]);
  }
}

/// C op A · S for a full coefficient map S (6×6, all k).
template <Op kOp, typename S>
inline void full(double* c, const double* a, S s) {
  columnPair<0, 0, 6, kOp>(c, a, 0, s);
  columnPair<0, 0, 6, kOp>(c, a, 2, s);
  columnPair<0, 0, 6, kOp>(c, a, 4, s);
}

}  // namespace detail

/// C −= A · Bᵀ.
inline void subtractProductTransposed(Block& c, const Block& a, const Block& b) {
  const double* bd = b.data();
  detail::full<detail::kSubtract>(c.data(), a.data(), [bd](int k, int j) { return bd[6 * k + j]; });
}

/// C −= A · B.
inline void subtractProduct(Block& c, const Block& a, const Block& b) {
  const double* bd = b.data();
  detail::full<detail::kSubtract>(c.data(), a.data(), [bd](int k, int j) { return bd[6 * j + k]; });
}

namespace detail {

/// C op Aᵀ · B as dot products of A's and B's columns (no transposed copy): rows r, r + 1 of column c are
/// the two lanes of one packet after a pairwise horizontal sum.
template <Op kOp>
inline void transposedProduct(double* cd, const double* ad, const double* bd) {
  for (int r = 0; r < 6; r += 2) {
    const double* a0 = ad + 6 * r;
    const double* a1 = a0 + 6;
    const Packet x00 = load(a0), x01 = load(a0 + 2), x02 = load(a0 + 4);
    const Packet x10 = load(a1), x11 = load(a1 + 2), x12 = load(a1 + 4);
    for (int col = 0; col < 6; ++col) {
      const double* bc = bd + 6 * col;
      const Packet y0 = load(bc), y1 = load(bc + 2), y2 = load(bc + 4);
      const Packet d0 = add(add(mul(x00, y0), mul(x01, y1)), mul(x02, y2));  // lanes: even, odd k of row r
      const Packet d1 = add(add(mul(x10, y0), mul(x11, y1)), mul(x12, y2));
      const Packet dot = add(unpackLow(d0, d1), unpackHigh(d0, d1));
      double* out = cd + 6 * col + r;
      store(out, kOp == kAssign ? dot : kOp == kAdd ? add(load(out), dot) : sub(load(out), dot));
    }
  }
}

}  // namespace detail

/// C −= Aᵀ · B. Each entry is a dot product summed as (even k) + (odd k): it differs from Eigen's order in
/// the last bits.
inline void subtractTransposedProduct(Block& c, const Block& a, const Block& b) {
  detail::transposedProduct<detail::kSubtract>(c.data(), a.data(), b.data());
}

/// The lower triangle of C −= A · Aᵀ (a symmetric update). Entries of the strict upper triangle in the
/// same aligned packets as lower ones ((0, 1), (2, 3), (4, 5)) are updated too; the rest of the strict
/// upper triangle is left as it was.
inline void subtractGramLower(Block& c, const Block& a) {
  const double* ad = a.data();
  const auto s = [ad](int k, int j) { return ad[6 * k + j]; };
  detail::columnPair<0, 0, 6, detail::kSubtract>(c.data(), ad, 0, s);
  detail::columnPair<1, 0, 6, detail::kSubtract>(c.data(), ad, 2, s);
  detail::columnPair<2, 0, 6, detail::kSubtract>(c.data(), ad, 4, s);
}

/// X ← X · Lᵀ in place, L lower triangular (its strict upper triangle must be exactly zero).
inline void multiplyTransposedLowerInPlace(Block& x, const Block& l) {
  const double* ld = l.data();
  const auto s = [ld](int k, int j) { return ld[6 * k + j]; };  // Lᵀ(k, j) = L(j, k), zero for k > j
  // Column pair (j, j + 1) of the result reads columns 0 … j + 1 of X: written last pair first, no pair
  // reads a column that an earlier call has overwritten.
  double* xd = x.data();
  detail::columnPair<0, 0, 6, detail::kAssign>(xd, xd, 4, s);
  detail::columnPair<0, 0, 4, detail::kAssign>(xd, xd, 2, s);
  detail::columnPair<0, 0, 2, detail::kAssign>(xd, xd, 0, s);
}

/// W = X · L, L lower triangular (its strict upper triangle must be exactly zero).
inline void multiplyLower(Block& w, const Block& x, const Block& l) {
  const double* ld = l.data();
  const auto s = [ld](int k, int j) { return ld[6 * j + k]; };  // L(k, j), zero for k < j
  detail::columnPair<0, 0, 6, detail::kAssign>(w.data(), x.data(), 0, s);
  detail::columnPair<0, 2, 6, detail::kAssign>(w.data(), x.data(), 2, s);
  detail::columnPair<0, 4, 6, detail::kAssign>(w.data(), x.data(), 4, s);
}

}  // namespace dualgraph::block_kernels
