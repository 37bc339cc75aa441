// SPDX-License-Identifier: MIT
// CholmodSolver: sparse Cholesky with SuiteSparse CHOLMOD, and its ordering and factorisation options.
#pragma once

#include <memory>
#include <string>

#include "dualgraph/core/linear_solver.h"

namespace dualgraph {

/// Fill-reducing ordering used by `CholmodSolver::analyze`.
enum class CholmodOrdering {
  kDefault,  ///< CHOLMOD's own choice: AMD, then METIS too when AMD fills badly (if CHOLMOD has METIS)
  kAmd,      ///< AMD only (deterministic and cheap to compute; usually as good on pose graphs)
};

/// Which numeric factorisation CHOLMOD runs (always LLᵀ).
enum class CholmodFactorization {
  /// CHOLMOD's own choice per analysed pattern (CHOLMOD_AUTO, what Ceres gets): supernodal when the
  /// factorisation's flops per nonzero of L reach 40 (dense supernodes, BLAS-3: sphere2500), simplicial on
  /// sparser factors (2-D graphs, long chains: intel), where it is faster (bench/README.md, "CHOLMOD's choice").
  kAuto,
  kSupernodal,  ///< always supernodal (BLAS-3 on dense supernodes)
  kSimplicial,  ///< always simplicial (column by column)
};

/// Options of `CholmodSolver`.
struct CholmodOptions {
  CholmodFactorization factorization = CholmodFactorization::kAuto;
  /// kAuto: supernodal when the factorisation's flops per nonzero of L reach this (CHOLMOD's
  /// `supernodal_switch`, its default 40). The crossover depends on the machine and its BLAS (measured on the
  /// public pose graphs in bench/README.md, "Engine phases, edge linearisation, CHOLMOD's choice, BLAS").
  double supernodal_switch = 40.0;
  CholmodOrdering ordering = CholmodOrdering::kDefault;
};

/// Sparse Cholesky H = L Lᵀ with SuiteSparse CHOLMOD (int API, real double).
/// `analyze` validates the pattern, runs the ordering and the symbolic factorisation and keeps
/// both until the next `analyze`; `factorize` is numeric only and reads the caller's CSC arrays
/// in place (no copy); `solve` keeps its CHOLMOD workspaces between calls, so it allocates nothing
/// after the first call. A matrix that is not positive definite is reported as
/// `kNotPositiveDefinite` (a normal outcome: the optimiser raises damping); non-finite values
/// as `kNumericalError`. CHOLMOD never prints: its messages end up in the returned Status.
/// Not thread-safe; one instance per optimiser.
class CholmodSolver final : public LinearSolver {
 public:
  explicit CholmodSolver(const CholmodOptions& options = {});
  ~CholmodSolver() override;
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  Status analyze(const SparseMatrixView& matrix) override;
  /// Requires the exact pattern of the last `analyze` (checked, O(nnz)); kFailedPrecondition otherwise.
  Status factorize(const SparseMatrixView& matrix) override;
  Status solve(const double* b, double* x) override;
  /// One cholmod_solve2 on the n × columns block (its own workspaces, kept between calls).
  Status solveColumns(const double* B, double* X, int n, int columns) override;
  bool hasSelectedInverse() const override { return true; }
  /// Diagonal blocks of H⁻¹ from the selected inverse of the last factor (solvers/cholmod_selected_inverse.h:
  /// Takahashi's recursion, BLAS-3 per supernode), computed at the first call after each factorisation and
  /// kept until the next: all blocks of a graph for about twice the flops of the factorisation.
  Status inverseDiagonalBlocks(const int* offsets, const int* dims, int count, double* out) override;
  /// "cholmod-supernodal" or "cholmod-simplicial" (the kind of the analysed factor; with kAuto before any
  /// `analyze`: "cholmod-auto").
  std::string name() const override;

  /// Nonzeros of the factor L for the analysed pattern (0 before `analyze`).
  double lastFactorNnz() const;
  /// Floating-point operations of one numeric factorisation of the analysed pattern (0 before).
  double factorFlops() const;
  /// Ordering CHOLMOD chose at the last `analyze`: "amd", "metis", "nesdis", "natural", …; "" before.
  std::string orderingUsed() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dualgraph
