// SPDX-License-Identifier: MIT
// EigenSolver: sparse LDLᵀ on Eigen's SimplicialLDLT (AMD or natural order), allocation-free.
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "dualgraph/core/linear_solver.h"

namespace dualgraph {

/// Fill-reducing ordering of `EigenSolver`.
enum class EigenOrdering {
  kAmd,      ///< approximate minimum degree (Eigen's AMD), the default
  /// none: the system's own order (vertices by increasing id). For graphs built so that this order is
  /// already good and the vertices whose marginals are wanted come last (the temporary graph: a pose
  /// chain in time order, then the gates), so `solveColumnsAtRows` only touches the factor's tail.
  kNatural,
};

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
  explicit EigenSolver(EigenOrdering ordering = EigenOrdering::kAmd) : ordering_(ordering) {}
  Status analyze(const SparseMatrixView& matrix) override;
  /// Requires the exact pattern of the last `analyze` (checked, O(nnz)); kFailedPrecondition otherwise.
  Status factorize(const SparseMatrixView& matrix) override;
  Status solve(const double* b, double* x) override;
  Status solveColumns(const double* B, double* X, int n, int columns) override;
  /// Forward substitution from each column's first nonzero (in the ordering), backward substitution
  /// down to the first needed row only.
  Status solveColumnsAtRows(const double* B, double* X, int n, int columns, const int* rows, int row_count) override;
  std::string name() const override {
    return ordering_ == EigenOrdering::kNatural ? "eigen-simplicial-ldlt-natural" : "eigen-simplicial-ldlt";
  }

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
    /// L's strictly lower part, column-major (unit diagonal implied).
    const Matrix& lower() const { return m_matrix; }
  };
  /// y ← L D Lᵀ \ y, in the permuted order, in place.
  void solvePermutedInPlace(Eigen::Ref<Eigen::VectorXd> y) const;
  /// new_position_ from AMD on the analysed pattern.
  Status computeAmdOrdering();
  /// permuted_ and source_entry_ from the analysed pattern and new_position_.
  void buildPermutedPattern();

  EigenOrdering ordering_;
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
