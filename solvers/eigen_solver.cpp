// SPDX-License-Identifier: MIT
#include "solvers/eigen_solver.h"

#include <algorithm>
#include <cmath>

namespace dualgraph {

Status EigenSolver::copyValues(const SparseMatrixView& view) {
  if (view.n != matrix_.rows() || view.nnz() != matrix_.nonZeros()) {
    return Status(StatusCode::kFailedPrecondition, "Eigen solver: pattern differs from the analysed one");
  }
  std::copy(view.values, view.values + view.nnz(), matrix_.valuePtr());
  return Status();
}

Status EigenSolver::analyze(const SparseMatrixView& view) {
  analyzed_ = factorized_ = false;
  matrix_.resize(view.n, view.n);
  matrix_.resizeNonZeros(view.nnz());
  std::copy(view.col_ptr, view.col_ptr + view.n + 1, matrix_.outerIndexPtr());
  std::copy(view.row_index, view.row_index + view.nnz(), matrix_.innerIndexPtr());
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + view.nnz(), 0.0);
  if (view.n > 0) ldlt_.analyzePattern(matrix_);
  analyzed_ = true;
  return Status();
}

Status EigenSolver::factorize(const SparseMatrixView& view) {
  factorized_ = false;
  if (!analyzed_) return Status(StatusCode::kFailedPrecondition, "Eigen solver: factorize before analyze");
  DG_RETURN_IF_ERROR(copyValues(view));
  if (view.n == 0) {
    factorized_ = true;
    return Status();
  }
  ldlt_.factorize(matrix_);
  if (ldlt_.info() != Eigen::Success) {
    return Status(StatusCode::kNotPositiveDefinite, "matrix is not positive definite (Eigen LDLT failed)");
  }
  const auto d = ldlt_.vectorD();
  for (int k = 0; k < d.size(); ++k) {
    if (!(d[k] > 0.0) || !std::isfinite(d[k])) {
      return Status(StatusCode::kNotPositiveDefinite,
                    "matrix is not positive definite (pivot " + std::to_string(k) + " is not positive)");
    }
  }
  factorized_ = true;
  return Status();
}

Status EigenSolver::solve(const double* b, double* x) {
  if (!factorized_) return Status(StatusCode::kFailedPrecondition, "Eigen solver: solve before a successful factorize");
  const int n = static_cast<int>(matrix_.rows());
  if (n == 0) return Status();
  const Eigen::VectorXd solution = ldlt_.solve(Eigen::Map<const Eigen::VectorXd>(b, n));
  Eigen::Map<Eigen::VectorXd>(x, n) = solution;
  return Status();
}

}  // namespace dualgraph
