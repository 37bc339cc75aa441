// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/auto_solver.h"

#include "dualgraph/solvers/cholmod_solver.h"
#include "dualgraph/solvers/eigen_solver.h"

namespace dualgraph {

Status AutoSolver::analyze(const SparseMatrixView& matrix) {
  if (matrix.n <= kMaxSimplicialDimension) {
    if (!simplicial_) simplicial_ = std::make_unique<EigenSolver>();
    active_ = simplicial_.get();
  } else {
    if (!supernodal_) supernodal_ = std::make_unique<CholmodSolver>();
    active_ = supernodal_.get();
  }
  return active_->analyze(matrix);
}

Status AutoSolver::factorize(const SparseMatrixView& matrix) {
  if (active_ == nullptr) return Status(StatusCode::kFailedPrecondition, "auto solver: factorize before analyze");
  return active_->factorize(matrix);
}

Status AutoSolver::solve(const double* b, double* x) {
  if (active_ == nullptr) return Status(StatusCode::kFailedPrecondition, "auto solver: solve before analyze");
  return active_->solve(b, x);
}

Status AutoSolver::solveColumns(const double* B, double* X, int n, int columns) {
  if (active_ == nullptr) return Status(StatusCode::kFailedPrecondition, "auto solver: solve before analyze");
  return active_->solveColumns(B, X, n, columns);
}

Status AutoSolver::solveColumnsAtRows(const double* B, double* X, int n, int columns, const int* rows, int row_count) {
  if (active_ == nullptr) return Status(StatusCode::kFailedPrecondition, "auto solver: solve before analyze");
  return active_->solveColumnsAtRows(B, X, n, columns, rows, row_count);
}

Status AutoSolver::inverseDiagonalBlocks(const int* offsets, const int* dims, int count, double* out) {
  if (active_ == nullptr) return Status(StatusCode::kFailedPrecondition, "auto solver: selected inverse before analyze");
  return active_->inverseDiagonalBlocks(offsets, dims, count, out);
}

std::string AutoSolver::name() const { return active_ == nullptr ? "auto" : "auto(" + active_->name() + ")"; }

}  // namespace dualgraph
