// SPDX-License-Identifier: MIT
// CholmodSelectedInverse: the entries of H⁻¹ on the pattern of CHOLMOD's factor (internal to solvers/).
#pragma once

#include <vector>

#include "dualgraph/core/status.h"

struct cholmod_factor_struct;  // cholmod.h stays out of the headers (CHOLMOD is a private dependency)

namespace dualgraph {

/// The selected inverse of a numeric CHOLMOD factor P H Pᵀ = L Lᵀ (or L D Lᵀ): the entries of
/// Σ = (P H Pᵀ)⁻¹ = L⁻ᵀ L⁻¹ at every position of L's pattern, by Takahashi's recursion in one pass from the
/// last column to the first. For a column block J with rows R below it (R × R lies in L's filled pattern,
/// so Σ_RR is known from the later columns):
///   Y = L_RJ L_JJ⁻¹,   Σ_RJ = −Σ_RR Y,   Σ_JJ = (L_JJ L_JJᵀ)⁻¹ − Yᵀ Σ_RJ.
/// Supernodal factors run it per supernode with dense BLAS/LAPACK (dtrsm, dsymm, dgemm, dpotri): about
/// twice the factorisation's flops. Simplicial factors (LLᵀ or LDLᵀ) run it column by column (J = {j}).
/// Σ is stored in L's own layout; reads map H's indices through CHOLMOD's permutation (L->Perm).
/// Internal to solvers/: CholmodSolver owns one and recomputes it after each factorisation.
class CholmodSelectedInverse {
 public:
  /// Computes Σ on the pattern of `factor` (numeric, int indices, real double). The factor must stay
  /// unchanged while blocks are read. kFailedPrecondition for a symbolic factor or another kind.
  Status compute(const cholmod_factor_struct& factor);
  /// Forgets Σ (the factor changed).
  void clear();
  bool valid() const { return factor_ != nullptr; }

  /// Σ_H's diagonal blocks (H⁻¹ in H's own indices): for k < count, the dims[k]² block at rows and columns
  /// [offsets[k], offsets[k] + dims[k]), column-major, one after another in `out`. Every pair of scalars of
  /// a block must lie in L's pattern (true when H's own diagonal block is dense, as a vertex's block is);
  /// otherwise kFailedPrecondition naming the block.
  Status diagonalBlocks(const int* offsets, const int* dims, int count, double* out) const;

 private:
  Status computeSupernodal(const cholmod_factor_struct& factor);
  Status computeSimplicial(const cholmod_factor_struct& factor);
  /// Σ(row, column) in L's (permuted) indices, row ≥ column; false when outside the pattern.
  bool entry(int row, int column, double& value) const;

  const cholmod_factor_struct* factor_ = nullptr;  ///< null until a successful compute
  int n_ = 0;
  std::vector<double> sigma_;        ///< Σ in the layout of L->x
  std::vector<int> inverse_perm_;    ///< H's index → L's
  std::vector<int> super_of_;        ///< supernodal: column → its supernode
  // Workspaces, kept between calls.
  std::vector<int> map_;             ///< row → position in a supernode's pattern / in R (simplicial)
  std::vector<double> y_;
  std::vector<double> sigma_rr_;
};

}  // namespace dualgraph
