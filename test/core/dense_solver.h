// SPDX-License-Identifier: MIT
// A dense reference solver (tests only) and one that always fails, to test the optimiser without
// solvers/.
#pragma once

#include <Eigen/Dense>

#include "dualgraph/core/linear_solver.h"

namespace dualgraph::testing {

/// Expands the upper-triangular CSC to a dense symmetric matrix.
inline Eigen::MatrixXd denseFromUpper(const SparseMatrixView& m) {
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(m.n, m.n);
  for (int c = 0; c < m.n; ++c) {
    for (int k = m.col_ptr[c]; k < m.col_ptr[c + 1]; ++k) {
      dense(m.row_index[k], c) = m.values[k];
      dense(c, m.row_index[k]) = m.values[k];
    }
  }
  return dense;
}

/// Dense LLᵀ; kNotPositiveDefinite when it fails.
class DenseTestSolver : public LinearSolver {
 public:
  Status analyze(const SparseMatrixView&) override { return Status(); }
  Status factorize(const SparseMatrixView& m) override {
    llt_.compute(denseFromUpper(m));
    if (llt_.info() != Eigen::Success) return Status(StatusCode::kNotPositiveDefinite, "dense LLT failed");
    return Status();
  }
  Status solve(const double* b, double* x) override {
    const int n = static_cast<int>(llt_.rows());
    Eigen::Map<Eigen::VectorXd>(x, n) = llt_.solve(Eigen::Map<const Eigen::VectorXd>(b, n));
    return Status();
  }
  std::string name() const override { return "dense-test"; }

 private:
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

/// Every factorisation fails as not positive definite.
class FailingSolver : public LinearSolver {
 public:
  Status analyze(const SparseMatrixView&) override { return Status(); }
  Status factorize(const SparseMatrixView&) override {
    return Status(StatusCode::kNotPositiveDefinite, "always fails");
  }
  Status solve(const double*, double*) override { return Status(StatusCode::kFailedPrecondition, "no factor"); }
  std::string name() const override { return "failing"; }
};

}  // namespace dualgraph::testing
