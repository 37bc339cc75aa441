// SPDX-License-Identifier: MIT
// Free-gauge detection for marginal covariances: unanchored components of a system, confirmed numerically.
#pragma once

#include <string>
#include <vector>

#include "dualgraph/core/linear_solver.h"
#include "dualgraph/core/sparse_system.h"
#include "dualgraph/core/status.h"

namespace dualgraph {

/// A connected component of a system's active vertices (joined by edges between free vertices) on which
/// no edge is anchored: none has a fixed vertex, none is unary (a prior).
struct UnanchoredComponent {
  int lowest_id = 0;      ///< its vertex of lowest id (for messages)
  int vertices = 0;
  std::vector<int> rows;  ///< its scalar rows in the system
};

/// The unanchored components of `system` (built), in order of lowest id. O(vertices + edges).
std::vector<UnanchoredComponent> unanchoredComponents(const SparseSystem& system);

/// Whether the factorised H is numerically singular on `rows` (the union of unanchored components): two
/// steps of inverse iteration with `solver` from a fixed start on those rows, then the Rayleigh quotient
/// vᵀHv / vᵀv against the largest diagonal entry of H on the rows. A free gauge leaves round-off
/// (≈ 1e-16 relative); any real constraint leaves far more. Singular when below `kGaugeRelativeEigenvalue`.
Result<bool> singularOnRows(const SparseSystem& system, LinearSolver& solver, const std::vector<int>& rows);

/// The threshold of `singularOnRows`: the smallest eigenvalue of H on the rows relative to its largest
/// diagonal entry. Physical conditioning of real graphs stays far above (a chain of 10⁴ poses held at one
/// end: ≈ 1e-8); a free gauge's round-off stays far below.
inline constexpr double kGaugeRelativeEigenvalue = 1e-11;

/// The kFailedPrecondition of a free gauge: names the components and says how to anchor them.
Status freeGaugeError(const std::vector<UnanchoredComponent>& components);

}  // namespace dualgraph
