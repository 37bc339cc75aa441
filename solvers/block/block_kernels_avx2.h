// SPDX-License-Identifier: MIT
// The AVX2 + FMA versions of the block loops (factorise, solve, inverse, edge assembly), chosen at run time.
#pragma once

namespace dualgraph::block_kernels_avx2 {

/// The 6×6 block loops of BlockCholesky and the SE(3) edge assembly of the temporary graph's solver in
/// AVX2 + FMA (four doubles per instruction, fused multiply-add), chosen at run time: the library keeps
/// the baseline x86-64 flags (SSE2, solvers/block/block_kernels.h) so that it runs on any x86-64 CPU, and two
/// translation units (block_kernels_avx2.cpp, block_kernels_avx2_edges.cpp, sharing the internal-linkage
/// products of block_product_avx2.h) are compiled with -mavx2 -mfma and only called when the CPU and the
/// OS support both (`enabled()`). They include no Eigen and no standard-library header, so no inline
/// function compiled for AVX2 can be shared with (and picked by the linker for) the baseline code.
///
/// Blocks are 6×6 column-major arrays of 36 doubles (`Eigen::Matrix<double, 6, 6>`'s storage; any 8-byte
/// alignment), stored one after another. The arithmetic is that of the baseline kernels; the order of
/// the terms differs, so results agree to round-off, not bit for bit.

/// True when these kernels are compiled in (x86-64 with GCC or Clang) and the CPU and OS run AVX2 + FMA,
/// and they have not been switched off by `setEnabled(false)`.
bool enabled();
/// For tests and benchmarks: use (true, when available) or bypass (false) these kernels process-wide.
/// Returns `enabled()` afterwards. Not to be called while a factorisation runs in another thread.
bool setEnabled(bool on);

/// A pivot that ended a factorisation: block row 6·column + k, its value (≤ 0 or not finite).
struct PivotFailure {
  int row = -1;
  double pivot = 0.0;
};

/// BlockCholesky::factorize's column loop on `factor` (H + damping already copied in): per column the
/// diagonal block's Cholesky and L_jj⁻¹ (`diagonal_inverse`, one block per column), L_ij = H_ij L_jj⁻ᵀ
/// and the updates H_ab −= L_a L_bᵀ at `target` (BlockCholesky's analyse arrays). Returns false with
/// `failure` set at the first pivot that is not positive and finite.
bool factorizeColumns(double* factor, double* diagonal_inverse, const int* col_begin, const int* target,
                      const int* target_begin, int num_blocks, PivotFailure& failure);

/// BlockCholesky::selectedInverse's recursion (Takahashi), last column first, into `sigma` (same layout
/// as `factor`), for the columns j with `wanted[j]` ≠ 0 (whose ancestors must be wanted too); `work` holds at
/// least the largest column's off-diagonal block count.
void selectedInverseColumns(const double* factor, const double* diagonal_inverse, double* sigma, double* work,
                            const int* col_begin, const int* target, const int* target_begin,
                            const unsigned char* wanted, int num_blocks);

/// BlockCholesky::solve's substitutions on x in place (b in, H⁻¹ b out): L y = b column by column, then
/// Lᵀ x = y (`row`: BlockCholesky's block row of every stored block).
void solveColumns(const double* factor, const double* diagonal_inverse, const int* col_begin, const int* row,
                  int num_blocks, double* x);

// The SE(3) edge assembly H_rc += J_rᵀ W J_c, b_r −= J_rᵀ W e (BlockLmSolver), with P_r = (W J_r)ᵀ
// computed once per vertex of the edge and each Jacobian's exactly-zero 3×3 quadrants skipped.

/// Bit 2r + c set when the 3×3 quadrant (r, c) (rows 3r…3r+2, columns 3c…3c+2) of the 6×6 block `j` has
/// an entry other than ±0 (NaN counts as nonzero).
unsigned nonzeroQuadrants(const double* j);
/// p = weight · (Ω · j)ᵀ, which is weight · jᵀ Ω for the symmetric information Ω, skipping the quadrants
/// of j that `j_mask` (from nonzeroQuadrants, or any superset of it) declares zero; then r −= p · e (the
/// 6-vectors e, the edge's error, and r, its vertex's block of b). p must not alias anything.
void weightedJacobianTransposed(double* p, double* r, const double* information, double weight, const double* j,
                                unsigned j_mask, const double* e);
/// eᵀ Ω e for a 6×6 Ω (the edge's χ² without robust kernel).
double quadraticForm(const double* information, const double* e);
/// h = p · j (`assign`) or h += p · j, skipping j's zero quadrants as above. h must not alias p or j.
void addProduct(double* h, const double* p, const double* j, unsigned j_mask, bool assign);

}  // namespace dualgraph::block_kernels_avx2
