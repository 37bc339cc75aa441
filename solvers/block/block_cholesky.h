// SPDX-License-Identifier: MIT
// BlockCholesky: sparse Cholesky on 6×6 blocks, with the selected inverse (marginals).
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// Block-sparse Cholesky H = L Lᵀ of a symmetric positive definite matrix made of 6×6 blocks, in the
/// natural (given) block order, with the selected inverse of its diagonal blocks (marginal covariances).
///
/// H has `numBlocks()` block rows and columns, every block `Eigen::Matrix<double, 6, 6>` (unitless: the
/// caller's units; a vertex of smaller dimension is padded by the caller with an identity diagonal and
/// zero coupling, which leaves the factor and the inverse of the real part exact). Blocks are stored
/// column by column, lower triangle only: column j holds its diagonal block (full, symmetric) and then
/// the blocks (i, j), i > j, of the filled pattern of L in increasing i. `analyse` computes that
/// pattern once (fill from the elimination tree) together with the position of every update, so the
/// numeric phases do 6×6 block products only (solvers/block/block_kernels.h): per column j with off-diagonal rows S_j,
///   L_jj = chol(H_jj − …),  L_ij = H_ij L_jj⁻ᵀ,  H_ik −= L_ij L_kjᵀ for i ≥ k in S_j;
/// and the selected inverse Σ = H⁻¹ on the same pattern (Takahashi's recursion, last column first),
///   W_i = L_ij L_jj⁻¹,  Σ_kj = −Σ_{i∈S_j} Σ_ki W_i,  Σ_jj = L_jj⁻ᵀ L_jj⁻¹ − Σ_{i∈S_j} W_iᵀ Σ_ij.
/// Never prints or aborts; failures are statuses (kNotPositiveDefinite for a pivot ≤ 0, kNumericalError
/// for a NaN/Inf pivot, kFailedPrecondition for calls out of order, kInvalidArgument for a bad pattern).
class BlockCholesky {
 public:
  using Block = Eigen::Matrix<double, 6, 6>;
  using BlockVector = std::vector<Block, Eigen::aligned_allocator<Block>>;
  static constexpr int kBlockDim = 6;

  /// The pattern of H: `num_blocks` block columns and the off-diagonal block pairs {i, j} (either order,
  /// duplicates allowed) that may be nonzero; the diagonal is always in. kInvalidArgument for an index
  /// out of range or i == j. Invalidates any earlier factor.
  Status analyse(int num_blocks, const std::vector<std::pair<int, int>>& pairs);

  int numBlocks() const { return num_blocks_; }
  /// Stored blocks of H (and of L and Σ): the diagonal, the blocks of H and the fill.
  int numStoredBlocks() const { return static_cast<int>(row_.size()); }
  /// Position of block (row, col) of the lower triangle (row ≥ col) in the storage, or -1 when it is
  /// not in the pattern. For assembling H into a `BlockVector` of `numStoredBlocks()` blocks.
  int blockIndex(int row, int col) const;
  /// Position of the diagonal block j.
  int diagonalIndex(int j) const { return col_begin_[j]; }

  /// Factorises H + diag(`diagonal_add`) (`h`: numStoredBlocks() blocks in the storage layout, fill blocks
  /// zero; of the diagonal blocks only the lower triangle is read; `diagonal_add`: 6·numBlocks() scalars or
  /// null for none). H is not modified. On failure the factor is unusable until the next successful call.
  Status factorize(const Block* h, const double* diagonal_add = nullptr);
  /// x = H⁻¹ b (6·numBlocks() scalars each; may alias).
  Status solve(const double* b, double* x) const;
  /// Σ = H⁻¹ on the pattern of L from the last factorisation; then `inverseDiagonal(j)` = Σ_jj for every j.
  Status selectedInverse();
  /// Σ on the columns of `blocks` and of their elimination-tree ancestors only: column j's recursion reads
  /// Σ on its rows S_j, which are ancestors of j, so nothing else is needed (the Bayes-tree marginal's
  /// path to the root). Then `inverseDiagonal(j)` = Σ_jj for j in `blocks`; `inverseComputed` tells which
  /// columns were done. The columns done get the same values, bit for bit, as from `selectedInverse()`.
  /// kInvalidArgument for a block out of range (nothing computed then).
  Status selectedInverse(const std::vector<int>& blocks);
  /// Whether column j of Σ (Σ_jj and the column's off-diagonal blocks) has been computed from the current
  /// factor (false for every column after `analyse` or `factorize`, until a selected inverse).
  bool inverseComputed(int j) const {
    return j >= 0 && j < static_cast<int>(sigma_column_.size()) && sigma_column_[j] != 0;
  }
  const Block& inverseDiagonal(int j) const { return sigma_[col_begin_[j]]; }
  bool factorized() const { return factorized_; }

 private:
  int num_blocks_ = 0;
  std::vector<int> col_begin_;   ///< per column: its first stored block (the diagonal); size numBlocks()+1
  std::vector<int> row_;         ///< per stored block: its block row
  /// Per column j, for every pair (a ≥ b) of its off-diagonal blocks in storage order (a major): the
  /// stored position of block (row_a, row_b), the target of L_a L_bᵀ. Flattened; begins in target_begin_.
  std::vector<int> target_;
  std::vector<int> target_begin_;
  BlockVector factor_;           ///< L (diagonal blocks lower triangular)
  BlockVector diagonal_inverse_; ///< per column: L_jj⁻¹
  BlockVector sigma_;            ///< the selected inverse
  BlockVector work_;             ///< per off-diagonal block of a column: W_i
  std::vector<unsigned char> sigma_column_;      ///< per column: whether the last selected inverse computed it
  std::vector<std::vector<int>> rows_work_;      ///< analyse: per column, its rows (reused)
  std::vector<std::vector<int>> children_work_;  ///< analyse: per column, its elimination-tree children
  bool factorized_ = false;

  /// Takahashi's recursion over the columns marked in sigma_column_ (their ancestors must be marked).
  void selectedInverseOfMarkedColumns();
};

}  // namespace dualgraph
