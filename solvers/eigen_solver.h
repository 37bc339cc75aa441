// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "core/linear_solver.h"

namespace dualgraph {

/// Sparse LDLᵀ with Eigen's simplicial factorisation: the dependency-free fallback, the oracle CHOLMOD
/// is tested against, and the small-system half of AutoSolver. `analyze` validates and copies the pattern,
/// computes an AMD ordering, builds the permuted upper triangle with a scatter map from the input's
/// entries, and runs the symbolic analysis once; `factorize` scatters the values and factorises the
/// pre-ordered matrix; `solve` permutes into a work vector and solves in place — so neither allocates
/// (Eigen's own `factorize` builds a permuted copy at every call; its stack work arrays go to the heap only
/// above 128 KiB, ≈ 8000 unknowns). LDLᵀ also succeeds on indefinite matrices, so a factor whose D has a
/// non-positive or non-finite entry is reported as `kNotPositiveDefinite`; non-finite input values as
/// `kNumericalError`.
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
  /// Eigen's SimplicialLDLT with its pre-ordered analysis and factorisation made callable: the ordering
  /// is applied here, once, instead of at every factorisation.
  class PreorderedLdlt : public Eigen::SimplicialLDLT<Matrix, Eigen::Upper, Eigen::NaturalOrdering<int>> {
   public:
    void analyzePreordered(const Matrix& a) { analyzePattern_preordered(a, true); }
    void factorizePreordered(const Matrix& a) { factorize_preordered<true>(a); }
    /// D by reference (Eigen's vectorD() returns a copy).
    const Eigen::VectorXd& diagonal() const { return m_diag; }
  };
  /// y ← L D Lᵀ \ y, in the permuted order, in place.
  void solvePermutedInPlace(Eigen::Ref<Eigen::VectorXd> y) const;

  std::vector<int> col_ptr_, row_index_;  ///< the analysed input pattern (upper CSC)
  std::vector<int> new_position_;         ///< original index → position in the ordering
  std::vector<int> source_entry_;         ///< permuted_ entry k ← input entry source_entry_[k]
  Matrix permuted_;                       ///< P H Pᵀ, upper triangle
  Eigen::VectorXd work_;
  PreorderedLdlt ldlt_;
  bool analyzed_ = false;
  bool factorized_ = false;
};

}  // namespace dualgraph
