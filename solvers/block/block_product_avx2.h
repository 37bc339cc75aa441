// SPDX-License-Identifier: MIT
// The 6×6 block products shared by the -mavx2 -mfma files; internal linkage, intrinsics only.
#pragma once

// The 6×6 block products of the AVX2 + FMA kernels, shared by the files compiled with -mavx2 -mfma
// (block_kernels_avx2.cpp: factorisation, solve, selected inverse; block_kernels_avx2_edges.cpp: the
// temporary graph's edge assembly). Internal linkage on purpose, and nothing included but the intrinsics:
// no function compiled for AVX2 can be shared with (and picked by the linker for) baseline code. Not
// installed; include it only from a file compiled with -mavx2 -mfma.
#include <immintrin.h>

namespace dualgraph::block_kernels_avx2 {
namespace {

enum Mode { kAssign, kAdd, kSubtract };

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

/// C ∘= A · S as accumulate, then stored.
template <Mode kMode, bool kLowerOnly, bool kTransposedA = false, typename S, typename Zero>
inline __attribute__((always_inline)) void product(double* c, const double* a, S s, Zero zero) {
  store<kLowerOnly>(c, accumulate<kMode, kLowerOnly, kTransposedA>(c, a, s, zero));
}

struct Never {
  constexpr bool operator()(int, int) const { return false; }
};

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

}  // namespace
}  // namespace dualgraph::block_kernels_avx2
