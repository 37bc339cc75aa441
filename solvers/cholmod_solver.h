// SPDX-License-Identifier: MIT
#pragma once

#include <memory>
#include <string>

#include "core/linear_solver.h"

namespace dualgraph {

/// Options of `CholmodSolver`.
struct CholmodOptions {
  /// Supernodal (BLAS-3, the fast choice for pose graphs) or simplicial factorisation.
  bool supernodal = true;
  /// Let CHOLMOD pick the ordering (AMD, and METIS/NESDIS when AMD fills badly) or force AMD.
  bool amd_only = false;
};

/// Sparse Cholesky H = L Lᵀ with SuiteSparse CHOLMOD. `analyze` runs the ordering and symbolic
/// factorisation once per pattern; `factorize` is numeric only and reads the caller's CSC arrays
/// in place (no copy); `solve` reuses its workspaces, so an iteration allocates nothing.
/// A matrix that is not positive definite is reported as `kNotPositiveDefinite`.
class CholmodSolver final : public LinearSolver {
 public:
  explicit CholmodSolver(const CholmodOptions& options = {});
  ~CholmodSolver() override;
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  Status analyze(const SparseMatrixView& matrix) override;
  Status factorize(const SparseMatrixView& matrix) override;
  Status solve(const double* b, double* x) override;
  std::string name() const override;

  /// Entries of the last factor L (0 before the first factorisation).
  double factorNonzeros() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dualgraph
