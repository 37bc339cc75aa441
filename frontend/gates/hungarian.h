// SPDX-License-Identifier: MIT
// solveAssignment: minimum-cost rectangular assignment (Hungarian) with forbidden entries.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// A solution of `solveAssignment`: per row the column it takes or -1.
struct Assignment {
  std::vector<int> row_to_col;  ///< size = rows of the cost matrix; -1 = unassigned
  int assigned_rows = 0;        ///< rows with a column
  double total_cost = 0.0;      ///< sum of the chosen entries (0 when nothing is assigned)
};

/// Minimum-cost assignment on a rectangular cost matrix (rows = detections, columns = gates).
///
/// An entry is *forbidden* when it is +∞ or ≥ `forbidden`; every other entry (negative ones too) is
/// allowed. A partial assignment maps some rows injectively to allowed columns. What is optimised,
/// lexicographically:
///   1. the number of assigned rows is as large as possible (a maximum matching over allowed entries),
///   2. among those, the sum of the chosen entries is as small as possible.
/// So a row stays unassigned only when no maximum matching can give it a column (none allowed, or
/// all its allowed columns are needed by other rows). Ties are broken deterministically but
/// unspecified.
///
/// Shortest augmenting paths with row/column potentials (Kuhn–Munkres in the Jonker–Volgenant form),
/// O(n²·m) for n = min(rows, cols), m = max(rows, cols); the two criteria are kept exact by a
/// lexicographic cost (count of forbidden cells used, sum of allowed costs), so there is no big-M.
/// Empty matrices give an empty/all-unassigned result. kInvalidArgument when an entry is NaN or −∞
/// (naming row and column), `forbidden` is NaN, or the allowed entries are too large to add up.
Result<Assignment> solveAssignment(const Eigen::MatrixXd& cost,
                                   double forbidden = std::numeric_limits<double>::infinity());

/// True when `cost(row, col)` may be used under the rule above (finite and < `forbidden`).
inline bool isAllowedCost(double cost, double forbidden) {
  return cost < forbidden && cost < std::numeric_limits<double>::infinity();
}

}  // namespace dualgraph
