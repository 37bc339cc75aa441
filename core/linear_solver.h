// SPDX-License-Identifier: MIT
// The LinearSolver interface (analyze, factorize, solve H x = b) and the upper-CSC matrix it takes.
#pragma once

#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// A symmetric matrix in compressed-column form holding only the upper triangle (row ≤ column),
/// row indices sorted within each column: CHOLMOD's `stype = 1` layout. The arrays belong to the
/// caller; a solver must not keep pointers to `values` across calls.
struct SparseMatrixView {
  int n = 0;                        ///< rows = columns
  const int* col_ptr = nullptr;     ///< n + 1 entries
  const int* row_index = nullptr;   ///< col_ptr[n] entries
  const double* values = nullptr;   ///< col_ptr[n] entries
  int nnz() const { return n == 0 ? 0 : col_ptr[n]; }
};

/// Solves H x = b for the symmetric positive-definite normal-equation matrices the optimiser
/// builds. `analyze` runs once per sparsity pattern (ordering, symbolic factorisation);
/// `factorize` once per iteration (numeric values only); `solve` after a successful factorize.
/// Implementations live in solvers/ (CHOLMOD, Eigen SimplicialLDLT).
class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// Symbolic analysis of the pattern of `matrix`; values are ignored.
  virtual Status analyze(const SparseMatrixView& matrix) = 0;
  /// Numeric factorisation with the pattern given to the last `analyze`.
  /// NotPositiveDefinite when the matrix is not SPD (the optimiser then raises damping).
  virtual Status factorize(const SparseMatrixView& matrix) = 0;
  /// x = H⁻¹ b with the last factorisation; `b` and `x` have n entries and may alias.
  virtual Status solve(const double* b, double* x) = 0;
  /// X = H⁻¹ B for `columns` right-hand sides at once (column-major n × columns, n the analysed
  /// size; B and X must not alias). The default solves column by column; CHOLMOD and Eigen solve
  /// the block in one pass (BLAS-3 in CHOLMOD's supernodal solve).
  virtual Status solveColumns(const double* B, double* X, int n, int columns);
  /// The same where only the rows listed in `rows` (`row_count` indices in [0, n)) of X are needed; the
  /// other rows of X are left unspecified. Marginal covariances use it: a solver whose ordering puts those
  /// rows last (EigenSolver with EigenOrdering::kNatural on a graph whose marginal vertices have the
  /// largest ids) stops its substitutions at them. The default solves in full.
  virtual Status solveColumnsAtRows(const double* B, double* X, int n, int columns, const int* rows, int row_count);
  /// Whether `inverseDiagonalBlocks` is implemented (CHOLMOD: yes, from its factor's selected inverse).
  virtual bool hasSelectedInverse() const { return false; }
  /// The diagonal blocks of H⁻¹ of the last factorisation: for k < `count`, the dims[k] × dims[k] block
  /// at rows and columns [offsets[k], offsets[k] + dims[k]) of H, column-major, one after another in `out`
  /// (Σ dims[k]² entries). A solver that implements it computes the entries of H⁻¹ on its factor's
  /// pattern once per factorisation (Takahashi's recursion) and reads every block from them. The default
  /// is kFailedPrecondition: callers solve unit columns instead.
  virtual Status inverseDiagonalBlocks(const int* offsets, const int* dims, int count, double* out);
  /// Short name for summaries, e.g. "cholmod-supernodal".
  virtual std::string name() const = 0;
};

inline Status LinearSolver::solveColumns(const double* B, double* X, int n, int columns) {
  if (columns < 0 || n < 0) return Status(StatusCode::kInvalidArgument, "solveColumns: negative size");
  for (int c = 0; c < columns; ++c) {
    const size_t offset = static_cast<size_t>(c) * static_cast<size_t>(n);
    DG_RETURN_IF_ERROR(solve(B + offset, X + offset));
  }
  return Status();
}

inline Status LinearSolver::solveColumnsAtRows(const double* B, double* X, int n, int columns, const int* /*rows*/,
                                               int /*row_count*/) {
  return solveColumns(B, X, n, columns);
}

inline Status LinearSolver::inverseDiagonalBlocks(const int* /*offsets*/, const int* /*dims*/, int /*count*/,
                                                 double* /*out*/) {
  return Status(StatusCode::kFailedPrecondition, name() + " has no selected inverse (solve unit columns instead)");
}

}  // namespace dualgraph
