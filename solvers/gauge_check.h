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
/// steps of inverse iteration with `solver` from a fixed start on those rows give v, the direction H is
/// softest along; singular when vᵀHv ≤ kGaugeCancellation · vᵀ|H|v, i.e. when the quadratic form is nothing
/// but the round-off of its own terms' cancellation (|H|: entrywise magnitudes). Unlike a threshold on
/// H's eigenvalues this does not depend on the information matrices' scales (MIT.g2o's spread over 16 orders).
Result<bool> singularOnRows(const SparseSystem& system, LinearSolver& solver, const std::vector<int>& rows);

/// The threshold of `singularOnRows`. Measured on the public pose graphs at their initial estimates
/// (CHOLMOD): with nothing fixed vᵀHv / vᵀ|H|v = 1.9e-17 (parking-garage) … 9.8e-15 (sphere2500), round-off;
/// with one vertex fixed (the weakest real anchoring: a whole graph hanging from one vertex) 1.9e-10 (MIT) …
/// 1.3e-5 (smallGrid3D). The threshold sits between, two orders from each.
inline constexpr double kGaugeCancellation = 1e-12;

/// The kFailedPrecondition of a free gauge: names the components and says how to anchor them.
Status freeGaugeError(const std::vector<UnanchoredComponent>& components);

}  // namespace dualgraph
