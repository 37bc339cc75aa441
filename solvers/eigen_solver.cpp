// SPDX-License-Identifier: MIT
#include "solvers/eigen_solver.h"

#include <algorithm>
#include <cmath>

#include "solvers/sparse_pattern.h"

namespace dualgraph {

Status EigenSolver::analyze(const SparseMatrixView& view) {
  analyzed_ = factorized_ = false;
  DG_RETURN_IF_ERROR(validateUpperCsc(view, "Eigen analyze"));
  matrix_.resize(view.n, view.n);
  matrix_.resizeNonZeros(view.nnz());
  if (view.n > 0) {
    std::copy(view.col_ptr, view.col_ptr + view.n + 1, matrix_.outerIndexPtr());
    std::copy(view.row_index, view.row_index + view.nnz(), matrix_.innerIndexPtr());
  }
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + view.nnz(), 0.0);
  if (view.n > 0) {
    ldlt_.analyzePattern(matrix_);
    if (ldlt_.info() != Eigen::Success) {
      return Status(StatusCode::kFailedPrecondition, "Eigen analyze: symbolic analysis failed");
    }
  }
  analyzed_ = true;
  return Status();
}

Status EigenSolver::factorize(const SparseMatrixView& view) {
  factorized_ = false;
  if (!analyzed_) return Status(StatusCode::kFailedPrecondition, "Eigen factorize before a successful analyze");
  const int n = static_cast<int>(matrix_.rows());
  if (!samePattern(view, n, matrix_.outerIndexPtr(), matrix_.innerIndexPtr())) {
    return Status(StatusCode::kFailedPrecondition,
                  "Eigen factorize: the pattern differs from the analysed one (call analyze first)");
  }
  DG_RETURN_IF_ERROR(checkFiniteValues(view, "Eigen factorize"));
  if (n == 0) {
    factorized_ = true;
    return Status();
  }
  std::copy(view.values, view.values + view.nnz(), matrix_.valuePtr());
  ldlt_.factorize(matrix_);
  if (ldlt_.info() != Eigen::Success) {
    return Status(StatusCode::kNotPositiveDefinite, "Eigen: matrix is not positive definite (zero pivot)");
  }
  // D is in the permuted order; report the original row/column like CHOLMOD does.
  const auto d = ldlt_.vectorD();
  for (int k = 0; k < d.size(); ++k) {
    if (!(d[k] > 0.0) || !std::isfinite(d[k])) {
      return Status(StatusCode::kNotPositiveDefinite,
                    "Eigen: matrix is not positive definite (pivot " + std::to_string(d[k]) + " at row/column " +
                        std::to_string(ldlt_.permutationPinv().indices()[k]) + " of " + std::to_string(n) + ")");
    }
  }
  factorized_ = true;
  return Status();
}

Status EigenSolver::solve(const double* b, double* x) {
  if (!factorized_) return Status(StatusCode::kFailedPrecondition, "Eigen solve before a successful factorize");
  const int n = static_cast<int>(matrix_.rows());
  if (n == 0) return Status();
  if (b == nullptr || x == nullptr) return Status(StatusCode::kInvalidArgument, "Eigen solve: b or x is null");
  // Solve into a temporary: b and x may alias.
  const Eigen::VectorXd solution = ldlt_.solve(Eigen::Map<const Eigen::VectorXd>(b, n));
  Eigen::Map<Eigen::VectorXd>(x, n) = solution;
  return Status();
}

Status EigenSolver::solveColumns(const double* B, double* X, int n, int columns) {
  if (!factorized_) return Status(StatusCode::kFailedPrecondition, "Eigen solve before a successful factorize");
  if (n != matrix_.rows() || columns < 0) {
    return Status(StatusCode::kInvalidArgument, "Eigen solveColumns: wrong row count or a negative column count");
  }
  if (n == 0 || columns == 0) return Status();
  if (B == nullptr || X == nullptr) return Status(StatusCode::kInvalidArgument, "Eigen solveColumns: B or X is null");
  Eigen::Map<Eigen::MatrixXd>(X, n, columns) = ldlt_.solve(Eigen::Map<const Eigen::MatrixXd>(B, n, columns));
  return Status();
}

}  // namespace dualgraph
