// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <string>

#include "core/linear_solver.h"

namespace dualgraph {

/// Sparse LDLᵀ with Eigen's `SimplicialLDLT` (AMD ordering, upper triangle): the dependency-free
/// fallback and the oracle CHOLMOD is tested against. `analyze` copies and validates the pattern
/// and runs the symbolic analysis once; `factorize` copies the values (same pattern, checked).
/// LDLᵀ also succeeds on indefinite matrices, so a factor whose D has a non-positive or non-finite
/// entry is reported as `kNotPositiveDefinite`; non-finite input values as `kNumericalError`.
class EigenSolver final : public LinearSolver {
 public:
  Status analyze(const SparseMatrixView& matrix) override;
  /// Requires the exact pattern of the last `analyze` (checked, O(nnz)); kFailedPrecondition otherwise.
  Status factorize(const SparseMatrixView& matrix) override;
  Status solve(const double* b, double* x) override;
  Status solveColumns(const double* B, double* X, int n, int columns) override;
  std::string name() const override { return "eigen-simplicial-ldlt"; }

 private:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  Matrix matrix_;  // upper triangle, the analysed pattern, the values of the last factorize
  Eigen::SimplicialLDLT<Matrix, Eigen::Upper> ldlt_;
  bool analyzed_ = false;
  bool factorized_ = false;
};

}  // namespace dualgraph
