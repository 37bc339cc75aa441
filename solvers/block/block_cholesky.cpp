// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/block/block_cholesky.h"

#include "dualgraph/core/small_cholesky.h"
#include "dualgraph/solvers/block/block_kernels.h"
#include "dualgraph/solvers/block/block_kernels_avx2.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

namespace dualgraph {

// The run-time choice of the AVX2 kernels lives here, in baseline code: nothing compiled with -mavx2
// may run before the CPU has been checked.
namespace block_kernels_avx2 {
extern const bool kCompiledWithAvx2;  // block_kernels_avx2.cpp
namespace {
bool available() {
#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
  // libgcc / compiler-rt report AVX2 only when the OS saves the YMM registers (XGETBV).
  static const bool supported = kCompiledWithAvx2 && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return supported;
#else
  return false;
#endif
}
std::atomic<bool>& switchedOn() {
  static std::atomic<bool> on{true};
  return on;
}
}  // namespace

bool enabled() { return available() && switchedOn().load(std::memory_order_relaxed); }
bool setEnabled(bool on) {
  switchedOn().store(on, std::memory_order_relaxed);
  return enabled();
}
}  // namespace block_kernels_avx2

namespace {

using Block = BlockCholesky::Block;
using Vector6 = Eigen::Matrix<double, 6, 1>;
static_assert(sizeof(Block) == 36 * sizeof(double), "6x6 blocks are stored back to back, 36 doubles each");

/// The status of a factorisation that met pivot `d` (not finite, or ≤ 0) at scalar row `row`.
Status pivotFailure(int row, double d) {
  if (!std::isfinite(d)) {
    return Status(StatusCode::kNumericalError,
                  "block Cholesky: non-finite pivot at row " + std::to_string(row) + " (NaN/Inf in the matrix)");
  }
  return Status(StatusCode::kNotPositiveDefinite, "block Cholesky: matrix is not positive definite (pivot " +
                                                       std::to_string(d) + " at row " + std::to_string(row) + ")");
}

}  // namespace

Status BlockCholesky::analyse(int num_blocks, const std::vector<std::pair<int, int>>& pairs) {
  factorized_ = false;
  sigma_column_.clear();
  num_blocks_ = 0;
  col_begin_.assign(1, 0);
  row_.clear();
  if (num_blocks < 0) return Status(StatusCode::kInvalidArgument, "block Cholesky: negative block count");
  // Lower pattern of H per column, then fill: a column's rows (but its parent) join its parent's.
  // Per-column work lists, kept between calls (their capacity is reused: no allocation once warm).
  std::vector<std::vector<int>>& rows = rows_work_;
  std::vector<std::vector<int>>& children = children_work_;
  if (rows.size() < static_cast<size_t>(num_blocks)) {
    rows.resize(num_blocks);
    children.resize(num_blocks);
  }
  for (int j = 0; j < num_blocks; ++j) {
    rows[j].clear();
    children[j].clear();
  }
  for (const auto& [a, b] : pairs) {
    if (a < 0 || b < 0 || a >= num_blocks || b >= num_blocks || a == b) {
      return Status(StatusCode::kInvalidArgument, "block Cholesky: bad block pair (" + std::to_string(a) + ", " +
                                                      std::to_string(b) + ") for " + std::to_string(num_blocks) +
                                                      " blocks");
    }
    rows[std::min(a, b)].push_back(std::max(a, b));
  }
  for (int j = 0; j < num_blocks; ++j) {
    std::vector<int>& column = rows[j];
    for (int child : children[j]) {
      for (int r : rows[child]) {
        if (r != j) column.push_back(r);
      }
    }
    std::sort(column.begin(), column.end());
    column.erase(std::unique(column.begin(), column.end()), column.end());
    if (!column.empty()) children[column.front()].push_back(j);
  }
  col_begin_.assign(num_blocks + 1, 0);
  for (int j = 0; j < num_blocks; ++j) {
    row_.push_back(j);
    row_.insert(row_.end(), rows[j].begin(), rows[j].end());
    col_begin_[j + 1] = static_cast<int>(row_.size());
  }
  num_blocks_ = num_blocks;
  // Update targets: block (row_a, row_b) for a ≥ b among each column's off-diagonal blocks, stored a-major
  // (target[a(a+1)/2 + b] within the column). For a fixed b, the rows row_a (a ≥ b, increasing) are found
  // in column row_b's sorted rows by one merge instead of a search each.
  target_begin_.assign(num_blocks + 1, 0);
  size_t max_column = 0;
  for (int j = 0; j < num_blocks; ++j) {
    const size_t m = static_cast<size_t>(col_begin_[j + 1] - col_begin_[j] - 1);
    max_column = std::max(max_column, m);
    target_begin_[j + 1] = target_begin_[j] + static_cast<int>(m * (m + 1) / 2);
  }
  target_.resize(static_cast<size_t>(target_begin_[num_blocks]));
  for (int j = 0; j < num_blocks; ++j) {
    const int first = col_begin_[j] + 1;
    const int end = col_begin_[j + 1];
    int* column_targets = target_.data() + target_begin_[j];
    for (int b = first; b < end; ++b) {
      const int col = row_[b];
      int p = col_begin_[col];
      const int col_end = col_begin_[col + 1];
      for (int a = b; a < end; ++a) {
        while (p < col_end && row_[p] < row_[a]) ++p;
        if (p == col_end || row_[p] != row_[a]) {
          return Status(StatusCode::kInvalidArgument, "block Cholesky: fill pattern is not closed");
        }
        column_targets[(a - first) * (a - first + 1) / 2 + (b - first)] = p;
      }
    }
  }
  // Every entry is written before it is read (factorize copies H; the inverse is filled column by column).
  factor_.resize(row_.size());
  sigma_.resize(row_.size());
  sigma_column_.assign(static_cast<size_t>(num_blocks), 0);
  diagonal_inverse_.resize(num_blocks);
  work_.resize(max_column);
  return Status();
}

int BlockCholesky::blockIndex(int row, int col) const {
  if (col < 0 || col >= num_blocks_ || row < col || row >= num_blocks_) return -1;
  const auto begin = row_.begin() + col_begin_[col];
  const auto end = row_.begin() + col_begin_[col + 1];
  if (end - begin <= 16) {  // the usual column: a short scan beats the binary search's branches
    for (auto it = begin; it != end && *it <= row; ++it) {
      if (*it == row) return static_cast<int>(it - row_.begin());
    }
    return -1;
  }
  const auto it = std::lower_bound(begin, end, row);
  return it != end && *it == row ? static_cast<int>(it - row_.begin()) : -1;
}

Status BlockCholesky::factorize(const Block* h, const double* diagonal_add) {
  factorized_ = false;
  std::fill(sigma_column_.begin(), sigma_column_.end(), 0);  // no Σ of this factor yet
  std::copy(h, h + row_.size(), factor_.begin());
  if (diagonal_add != nullptr) {
    for (int j = 0; j < num_blocks_; ++j) {
      factor_[col_begin_[j]].diagonal() += Eigen::Map<const Vector6>(diagonal_add + 6 * j);
    }
  }
  if (num_blocks_ > 0 && block_kernels_avx2::enabled()) {  // (no storage to point into without blocks)
    block_kernels_avx2::PivotFailure failure;
    if (!block_kernels_avx2::factorizeColumns(factor_.data()->data(), diagonal_inverse_.data()->data(), col_begin_.data(),
                                              target_.data(), target_begin_.data(), num_blocks_, failure)) {
      return pivotFailure(failure.row, failure.pivot);
    }
    factorized_ = true;
    return Status();
  }
  for (int j = 0; j < num_blocks_; ++j) {
    Block& inverse = diagonal_inverse_[j];
    double pivot = 0.0;
    const int failed = block_factor::choleskyAndInverse(factor_[col_begin_[j]].data(), inverse.data(), pivot);
    if (failed >= 0) return pivotFailure(6 * j + failed, pivot);
    const int first = col_begin_[j] + 1;
    const int end = col_begin_[j + 1];
    for (int p = first; p < end; ++p) block_kernels::multiplyTransposedLowerInPlace(factor_[p], inverse);
    const int* target = target_.data() + target_begin_[j];
    for (int a = first; a < end; ++a) {
      for (int b = first; b < a; ++b) block_kernels::subtractProductTransposed(factor_[*target++], factor_[a], factor_[b]);
      // A diagonal block of a later column: its factorisation reads the lower triangle only.
      block_kernels::subtractGramLower(factor_[*target++], factor_[a]);
    }
  }
  factorized_ = true;
  return Status();
}

Status BlockCholesky::solve(const double* b, double* x) const {
  if (!factorized_) return Status(StatusCode::kFailedPrecondition, "block Cholesky: solve before a successful factorize");
  const int n = 6 * num_blocks_;
  if (x != b) std::copy(b, b + n, x);
  if (num_blocks_ > 0 && block_kernels_avx2::enabled()) {
    block_kernels_avx2::solveColumns(factor_.data()->data(), diagonal_inverse_.data()->data(), col_begin_.data(),
                                     row_.data(), num_blocks_, x);
    return Status();
  }
  for (int j = 0; j < num_blocks_; ++j) {
    Eigen::Map<Vector6> x_j(x + 6 * j);
    const Vector6 y = diagonal_inverse_[j] * x_j;
    x_j = y;
    for (int p = col_begin_[j] + 1; p < col_begin_[j + 1]; ++p) Eigen::Map<Vector6>(x + 6 * row_[p]).noalias() -= factor_[p] * y;
  }
  for (int j = num_blocks_ - 1; j >= 0; --j) {
    Vector6 r = Eigen::Map<const Vector6>(x + 6 * j);
    for (int p = col_begin_[j] + 1; p < col_begin_[j + 1]; ++p) {
      r.noalias() -= factor_[p].transpose() * Eigen::Map<const Vector6>(x + 6 * row_[p]);
    }
    Eigen::Map<Vector6>(x + 6 * j).noalias() = diagonal_inverse_[j].transpose() * r;
  }
  return Status();
}

Status BlockCholesky::selectedInverse() {
  sigma_column_.assign(static_cast<size_t>(num_blocks_), factorized_ ? 1 : 0);
  if (!factorized_) {
    return Status(StatusCode::kFailedPrecondition, "block Cholesky: selected inverse before a successful factorize");
  }
  selectedInverseOfMarkedColumns();
  return Status();
}

Status BlockCholesky::selectedInverse(const std::vector<int>& blocks) {
  sigma_column_.assign(static_cast<size_t>(num_blocks_), 0);
  if (!factorized_) {
    return Status(StatusCode::kFailedPrecondition, "block Cholesky: selected inverse before a successful factorize");
  }
  for (int j : blocks) {
    if (j < 0 || j >= num_blocks_) {
      sigma_column_.assign(sigma_column_.size(), 0);
      return Status(StatusCode::kInvalidArgument, "block Cholesky: selected inverse of block " + std::to_string(j) +
                                                      " of " + std::to_string(num_blocks_));
    }
    sigma_column_[j] = 1;
  }
  // Ancestor closure, in increasing column order: column j's parent is its first off-diagonal row.
  for (int j = 0; j < num_blocks_; ++j) {
    if (sigma_column_[j] != 0 && col_begin_[j + 1] > col_begin_[j] + 1) sigma_column_[row_[col_begin_[j] + 1]] = 1;
  }
  selectedInverseOfMarkedColumns();
  return Status();
}

void BlockCholesky::selectedInverseOfMarkedColumns() {
  if (num_blocks_ > 0 && block_kernels_avx2::enabled()) {
    block_kernels_avx2::selectedInverseColumns(factor_.data()->data(), diagonal_inverse_.data()->data(),
                                               sigma_.data()->data(), work_.empty() ? nullptr : work_.data()->data(),
                                               col_begin_.data(), target_.data(), target_begin_.data(),
                                               sigma_column_.data(), num_blocks_);
    return;
  }
  for (int j = num_blocks_ - 1; j >= 0; --j) {
    if (sigma_column_[j] == 0) continue;
    const int first = col_begin_[j] + 1;
    const int m = col_begin_[j + 1] - first;
    const Block& inverse = diagonal_inverse_[j];
    for (int i = 0; i < m; ++i) block_kernels::multiplyLower(work_[i], factor_[first + i], inverse);
    const int* target = target_.data() + target_begin_[j];  // (a, b), a ≥ b: target[a(a+1)/2 + b]
    for (int a = 0; a < m; ++a) {
      Block& sigma_aj = sigma_[first + a];
      sigma_aj.setZero();
      for (int i = 0; i < m; ++i) {
        if (i <= a) {
          block_kernels::subtractProduct(sigma_aj, sigma_[target[a * (a + 1) / 2 + i]], work_[i]);
        } else {
          // Σ(row a, row i) = Σ(row i, row a)ᵀ, the stored block.
          block_kernels::subtractTransposedProduct(sigma_aj, sigma_[target[i * (i + 1) / 2 + a]], work_[i]);
        }
      }
    }
    Block diagonal;
    diagonal.noalias() = inverse.transpose() * inverse;
    for (int a = 0; a < m; ++a) block_kernels::subtractTransposedProduct(diagonal, work_[a], sigma_[first + a]);
    sigma_[col_begin_[j]] = 0.5 * (diagonal + diagonal.transpose());
  }
}

}  // namespace dualgraph
