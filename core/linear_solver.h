// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/status.h"

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
  /// Short name for summaries, e.g. "cholmod-supernodal".
  virtual std::string name() const = 0;
};

}  // namespace dualgraph
