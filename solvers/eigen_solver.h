// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <string>

#include "core/linear_solver.h"

namespace dualgraph {

/// Sparse LDLᵀ with Eigen's `SimplicialLDLT` (AMD ordering): the dependency-free fallback and the
/// oracle CHOLMOD is tested against. Pattern analysis once per `analyze`; a factor whose D has a
/// non-positive or non-finite entry is reported as `kNotPositiveDefinite`.
class EigenSolver final : public LinearSolver {
 public:
  Status analyze(const SparseMatrixView& matrix) override;
  Status factorize(const SparseMatrixView& matrix) override;
  Status solve(const double* b, double* x) override;
  std::string name() const override { return "eigen-simplicial-ldlt"; }

 private:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  Status copyValues(const SparseMatrixView& matrix);

  Matrix matrix_;
  Eigen::SimplicialLDLT<Matrix, Eigen::Upper> ldlt_;
  bool analyzed_ = false;
  bool factorized_ = false;
};

}  // namespace dualgraph
