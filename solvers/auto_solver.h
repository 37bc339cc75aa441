// SPDX-License-Identifier: MIT
// AutoSolver: Eigen's simplicial LDLᵀ up to 3000 unknowns, CHOLMOD supernodal above.
#pragma once

#include <memory>
#include <string>

#include "dualgraph/core/linear_solver.h"

namespace dualgraph {

/// Picks the sparse Cholesky by size at every `analyze`: Eigen's SimplicialLDLT up to
/// `kMaxSimplicialDimension` unknowns, CHOLMOD supernodal above. Small systems (the dual graph's
/// temporary graphs and fixed-lag main graph, a few hundred unknowns) spend most of a supernodal
/// factorisation in per-supernode and BLAS-call overhead; large ones with fill need the supernodal
/// BLAS kernels. The threshold is where the faster of the two changed on this project's main graphs
/// (measured in bench/README.md, "Main-graph update per keyframe", the main graph's linear solver).
class AutoSolver final : public LinearSolver {
 public:
  static constexpr int kMaxSimplicialDimension = 3000;

  Status analyze(const SparseMatrixView& matrix) override;
  Status factorize(const SparseMatrixView& matrix) override;
  Status solve(const double* b, double* x) override;
  Status solveColumns(const double* B, double* X, int n, int columns) override;
  Status solveColumnsAtRows(const double* B, double* X, int n, int columns, const int* rows, int row_count) override;
  bool hasSelectedInverse() const override { return active_ != nullptr && active_->hasSelectedInverse(); }
  Status inverseDiagonalBlocks(const int* offsets, const int* dims, int count, double* out) override;
  /// "auto(<the active solver's name>)", "auto" before the first analyze.
  std::string name() const override;

 private:
  std::unique_ptr<LinearSolver> simplicial_;
  std::unique_ptr<LinearSolver> supernodal_;
  LinearSolver* active_ = nullptr;
};

}  // namespace dualgraph
