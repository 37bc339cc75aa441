// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/eigen_solver.h"

#include <Eigen/OrderingMethods>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "dualgraph/solvers/sparse_pattern.h"

namespace dualgraph {

Status EigenSolver::analyze(const SparseMatrixView& view) {
  analyzed_ = factorized_ = false;
  DG_RETURN_IF_ERROR(validateUpperCsc(view, "Eigen analyze"));
  const int n = view.n;
  col_ptr_.assign(view.col_ptr, view.col_ptr + n + 1);
  row_index_.assign(view.row_index, view.row_index + view.nnz());
  work_.resize(n);
  if (n == 0) {
    analyzed_ = true;
    return Status();
  }
  new_position_.resize(n);
  if (ordering_ == EigenOrdering::kNatural) {
    std::iota(new_position_.begin(), new_position_.end(), 0);
  } else {
    DG_RETURN_IF_ERROR(computeAmdOrdering());
  }
  buildPermutedPattern();
  ldlt_.analyzePreordered(permuted_);
  if (ldlt_.info() != Eigen::Success) {
    return Status(StatusCode::kFailedPrecondition, "Eigen analyze: symbolic analysis failed");
  }
  analyzed_ = true;
  return Status();
}

Status EigenSolver::computeAmdOrdering() {
  const int n = static_cast<int>(col_ptr_.size()) - 1;
  // AMD on the full symmetric pattern (Eigen's orderings return the inverse permutation).
  Matrix upper(n, n);
  upper.resizeNonZeros(static_cast<Eigen::Index>(row_index_.size()));
  std::copy(col_ptr_.begin(), col_ptr_.end(), upper.outerIndexPtr());
  std::copy(row_index_.begin(), row_index_.end(), upper.innerIndexPtr());
  std::fill(upper.valuePtr(), upper.valuePtr() + row_index_.size(), 1.0);
  Matrix full;
  full = upper.selfadjointView<Eigen::Upper>();
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
  Eigen::AMDOrdering<int>()(full, inverse);
  for (int k = 0; k < n; ++k) new_position_[inverse.indices()[k]] = k;
  return Status();
}

void EigenSolver::buildPermutedPattern() {
  const int n = static_cast<int>(col_ptr_.size()) - 1;
  const int nnz = static_cast<int>(row_index_.size());
  // The permuted upper triangle, and which input entry fills each of its entries: each input entry lands at
  // (row, column) = (min, max) of its two new positions. Two counting passes (by row, then stably by column)
  // give the columns with their rows sorted in O(nnz + n), as a comparison sort would in O(nnz log nnz).
  std::vector<int> low(nnz), high(nnz);
  for (int j = 0; j < n; ++j) {
    for (int e = col_ptr_[j]; e < col_ptr_[j + 1]; ++e) {
      const int a = new_position_[row_index_[e]], b = new_position_[j];
      low[e] = std::min(a, b);
      high[e] = std::max(a, b);
    }
  }
  std::vector<int> start(n + 1, 0), by_row(nnz);
  for (int e = 0; e < nnz; ++e) ++start[low[e] + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  for (int e = 0; e < nnz; ++e) by_row[start[low[e]]++] = e;
  permuted_.resize(n, n);
  permuted_.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = permuted_.outerIndexPtr();
  std::fill(outer, outer + n + 1, 0);
  for (int e = 0; e < nnz; ++e) ++outer[high[e] + 1];
  std::partial_sum(outer, outer + n + 1, outer);
  std::vector<int> next(outer, outer + n);
  source_entry_.assign(nnz, 0);
  for (const int e : by_row) {
    const int k = next[high[e]]++;
    permuted_.innerIndexPtr()[k] = low[e];
    permuted_.valuePtr()[k] = 0.0;
    source_entry_[k] = e;
  }
}

Status EigenSolver::factorize(const SparseMatrixView& view) {
  factorized_ = false;
  if (!analyzed_) return Status(StatusCode::kFailedPrecondition, "Eigen factorize before a successful analyze");
  const int n = static_cast<int>(col_ptr_.size()) - 1;
  if (!samePattern(view, n, col_ptr_.data(), row_index_.data())) {
    return Status(StatusCode::kFailedPrecondition,
                  "Eigen factorize: the pattern differs from the analysed one (call analyze first)");
  }
  DG_RETURN_IF_ERROR(checkFiniteValues(view, "Eigen factorize"));
  if (n == 0) {
    factorized_ = true;
    return Status();
  }
  double* values = permuted_.valuePtr();
  for (size_t k = 0; k < source_entry_.size(); ++k) values[k] = view.values[source_entry_[k]];
  ldlt_.factorizePreordered(permuted_);
  if (ldlt_.info() != Eigen::Success) {
    return Status(StatusCode::kNotPositiveDefinite, "Eigen: matrix is not positive definite (zero pivot)");
  }
  // D is in the permuted order; report the original row/column like CHOLMOD does.
  const Eigen::VectorXd& d = ldlt_.diagonal();
  for (int k = 0; k < d.size(); ++k) {
    if (!(d[k] > 0.0) || !std::isfinite(d[k])) {
      const int original = static_cast<int>(std::find(new_position_.begin(), new_position_.end(), k) - new_position_.begin());
      return Status(StatusCode::kNotPositiveDefinite, "Eigen: matrix is not positive definite (pivot " +
                                                          std::to_string(d[k]) + " at row/column " +
                                                          std::to_string(original) + " of " + std::to_string(n) + ")");
    }
  }
  factorized_ = true;
  return Status();
}

void EigenSolver::solvePermutedInPlace(Eigen::Ref<Eigen::VectorXd> y) const {
  ldlt_.matrixL().solveInPlace(y);
  y.array() /= ldlt_.diagonal().array();
  ldlt_.matrixU().solveInPlace(y);
}

Status EigenSolver::solve(const double* b, double* x) {
  if (!factorized_) return Status(StatusCode::kFailedPrecondition, "Eigen solve before a successful factorize");
  const int n = static_cast<int>(work_.size());
  if (n == 0) return Status();
  if (b == nullptr || x == nullptr) return Status(StatusCode::kInvalidArgument, "Eigen solve: b or x is null");
  // Through the work vector: b and x may alias.
  for (int i = 0; i < n; ++i) work_[new_position_[i]] = b[i];
  solvePermutedInPlace(work_);
  for (int i = 0; i < n; ++i) x[i] = work_[new_position_[i]];
  return Status();
}

Status EigenSolver::solveColumns(const double* B, double* X, int n, int columns) {
  if (!factorized_) return Status(StatusCode::kFailedPrecondition, "Eigen solve before a successful factorize");
  if (n != static_cast<int>(work_.size()) || columns < 0) {
    return Status(StatusCode::kInvalidArgument, "Eigen solveColumns: wrong row count or a negative column count");
  }
  if (n == 0 || columns == 0) return Status();
  if (B == nullptr || X == nullptr) return Status(StatusCode::kInvalidArgument, "Eigen solveColumns: B or X is null");
  for (int c = 0; c < columns; ++c) {
    const size_t offset = static_cast<size_t>(c) * static_cast<size_t>(n);
    DG_RETURN_IF_ERROR(solve(B + offset, X + offset));
  }
  return Status();
}

Status EigenSolver::solveColumnsAtRows(const double* B, double* X, int n, int columns, const int* rows, int row_count) {
  if (!factorized_) return Status(StatusCode::kFailedPrecondition, "Eigen solve before a successful factorize");
  if (n != static_cast<int>(work_.size()) || columns < 0 || row_count < 0) {
    return Status(StatusCode::kInvalidArgument, "Eigen solveColumnsAtRows: wrong row count or a negative count");
  }
  if (n == 0 || columns == 0 || row_count == 0) return Status();
  if (B == nullptr || X == nullptr || rows == nullptr) {
    return Status(StatusCode::kInvalidArgument, "Eigen solveColumnsAtRows: B, X or rows is null");
  }
  int first_needed = n;  // in the ordering
  for (int k = 0; k < row_count; ++k) {
    if (rows[k] < 0 || rows[k] >= n) {
      return Status(StatusCode::kInvalidArgument, "Eigen solveColumnsAtRows: row " + std::to_string(rows[k]) +
                                                      " outside [0, " + std::to_string(n) + ")");
    }
    first_needed = std::min(first_needed, new_position_[rows[k]]);
  }
  const Matrix& l = ldlt_.lower();
  const int* outer = l.outerIndexPtr();
  const int* inner = l.innerIndexPtr();
  const double* value = l.valuePtr();
  const Eigen::VectorXd& d = ldlt_.diagonal();
  for (int c = 0; c < columns; ++c) {
    const size_t offset = static_cast<size_t>(c) * static_cast<size_t>(n);
    for (int i = 0; i < n; ++i) work_[new_position_[i]] = B[offset + i];
    int first = 0;  // y is zero above the right-hand side's first nonzero: L y = b starts there
    while (first < n && work_[first] == 0.0) ++first;
    const int start = std::min(first, first_needed);
    for (int j = first; j < n; ++j) {  // L y = b (unit lower, column-major)
      const double yj = work_[j];
      if (yj == 0.0) continue;
      for (int k = outer[j]; k < outer[j + 1]; ++k) work_[inner[k]] -= value[k] * yj;
    }
    for (int j = start; j < n; ++j) work_[j] /= d[j];
    for (int j = n - 1; j >= first_needed; --j) {  // Lᵀ x = y, down to the first needed row only
      double sum = work_[j];
      for (int k = outer[j]; k < outer[j + 1]; ++k) sum -= value[k] * work_[inner[k]];
      work_[j] = sum;
    }
    for (int k = 0; k < row_count; ++k) X[offset + rows[k]] = work_[new_position_[rows[k]]];
  }
  return Status();
}

}  // namespace dualgraph
