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
/// It runs per supernode with dense BLAS/LAPACK (dtrsm, dsymm, dgemm, dpotri): about twice the
/// factorisation's flops. A supernodal factor is used as CHOLMOD laid it out; a simplicial one (LLᵀ or LDLᵀ,
/// scaled to LLᵀ) is first copied into the same layout, its fundamental supernodes (runs of columns whose
/// patterns nest: column j's rows below j+1 are column j+1's) found from the pattern, so both kinds take
/// the same BLAS-3 path (faster than a scalar column recursion; bench/README.md, "Marginals of every vertex").
/// Σ is stored in the supernodal layout; reads map H's indices through CHOLMOD's permutation (L->Perm).
/// Internal to solvers/: CholmodSolver owns one and recomputes it after each factorisation.
class CholmodSelectedInverse {
 public:
  /// Computes Σ on the pattern of `factor` (numeric, int indices, real double); Σ and its layout are kept
  /// here, so the factor may change afterwards. kFailedPrecondition for a symbolic factor or another kind.
  Status compute(const cholmod_factor_struct& factor);
  /// Forgets Σ (the factor changed).
  void clear();
  bool valid() const { return valid_; }

  /// Σ_H's diagonal blocks (H⁻¹ in H's own indices): for k < count, the dims[k]² block at rows and columns
  /// [offsets[k], offsets[k] + dims[k]), column-major, one after another in `out`. Every pair of scalars of
  /// a block must lie in L's pattern (true when H's own diagonal block is dense, as a vertex's block is);
  /// otherwise kFailedPrecondition naming the block.
  Status diagonalBlocks(const int* offsets, const int* dims, int count, double* out) const;

 private:
  /// The layout of a supernodal factor (CHOLMOD's arrays copied, its values referenced).
  Status layOutSupernodal(const cholmod_factor_struct& factor);
  /// The layout of a simplicial factor: its fundamental supernodes, values copied (LDLᵀ scaled to LLᵀ).
  Status layOutSimplicial(const cholmod_factor_struct& factor);
  /// Takahashi's recursion over the layout, last supernode first.
  Status recurse();
  /// Σ(row, column) in L's (permuted) indices, row ≥ column; false when outside the pattern.
  bool entry(int row, int column, double& value) const;

  bool valid_ = false;
  int n_ = 0;
  // The supernodal layout, as CHOLMOD's: supernode s has columns [super_[s], super_[s+1]), row indices
  // s_[pi_[s] .. pi_[s+1]) (its own columns first, then the rows below, increasing), and its values column-major
  // at values_[px_[s]], leading dimension pi_[s+1] − pi_[s].
  std::vector<int> super_;
  std::vector<int> pi_;
  std::vector<size_t> px_;
  std::vector<int> s_;
  const double* values_ = nullptr;   ///< L->x (supernodal) or owned_values_ (simplicial)
  std::vector<double> owned_values_;
  std::vector<double> sigma_;        ///< Σ in the same layout
  std::vector<int> inverse_perm_;    ///< H's index → L's
  std::vector<int> super_of_;        ///< column → its supernode
  // Workspaces, kept between calls.
  std::vector<int> map_;             ///< row → position in an ancestor supernode's rows
  std::vector<double> y_;
  std::vector<double> sigma_rr_;
};

}  // namespace dualgraph
