// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/hungarian.h"

#include <cmath>
#include <cstdint>
#include <sstream>

namespace dualgraph {
namespace {

/// A cost with two exactly separated criteria: `penalty` (forbidden cells used) dominates `value`
/// (sum of allowed costs). Pairs under lexicographic order form an ordered group, which is all the
/// potentials of the shortest-augmenting-path method need, so "assign as many rows as possible, then
/// cheapest" is solved exactly without a big-M that would swamp the real costs' precision.
struct LexCost {
  std::int64_t penalty = 0;
  double value = 0.0;
};
LexCost operator+(LexCost a, LexCost b) { return {a.penalty + b.penalty, a.value + b.value}; }
LexCost operator-(LexCost a, LexCost b) { return {a.penalty - b.penalty, a.value - b.value}; }
LexCost& operator+=(LexCost& a, LexCost b) { return a = a + b; }
LexCost& operator-=(LexCost& a, LexCost b) { return a = a - b; }
bool operator<(LexCost a, LexCost b) { return a.penalty != b.penalty ? a.penalty < b.penalty : a.value < b.value; }

/// Larger than any reduced cost: at most n forbidden cells on a path, each with penalty 1.
constexpr LexCost kUnreached{std::int64_t{1} << 40, 0.0};

/// Solves the square-or-wide problem (rows ≤ cols) where every row gets a column; `at(r, c)` gives the
/// lexicographic cost. Returns per row its column.
template <typename CostAt>
std::vector<int> assignAllRows(int rows, int cols, const CostAt& at) {
  // Columns 0..cols-1 are real; column `cols` is a virtual start column owned by the row being added.
  const int root = cols;
  std::vector<LexCost> row_potential(static_cast<size_t>(rows));
  std::vector<LexCost> col_potential(static_cast<size_t>(cols) + 1);
  std::vector<int> owner(static_cast<size_t>(cols) + 1, -1);  // row holding each column, -1 = free
  std::vector<LexCost> slack(static_cast<size_t>(cols) + 1);  // shortest reduced distance found so far
  std::vector<int> came_from(static_cast<size_t>(cols) + 1);  // previous column on that path
  std::vector<char> settled(static_cast<size_t>(cols) + 1);

  for (int new_row = 0; new_row < rows; ++new_row) {
    owner[root] = new_row;
    std::fill(slack.begin(), slack.end(), kUnreached);
    std::fill(came_from.begin(), came_from.end(), root);
    std::fill(settled.begin(), settled.end(), 0);
    int frontier = root;
    // Dijkstra over columns in reduced costs until a free column is reached; the potentials are moved
    // by each step's distance so settled columns keep zero reduced cost along the tree.
    while (owner[static_cast<size_t>(frontier)] != -1) {
      settled[static_cast<size_t>(frontier)] = 1;
      const int row = owner[static_cast<size_t>(frontier)];
      LexCost step = kUnreached;
      int next = -1;
      for (int c = 0; c < cols; ++c) {
        if (settled[static_cast<size_t>(c)]) continue;
        const LexCost reduced = at(row, c) - row_potential[static_cast<size_t>(row)] - col_potential[static_cast<size_t>(c)];
        if (reduced < slack[static_cast<size_t>(c)]) {
          slack[static_cast<size_t>(c)] = reduced;
          came_from[static_cast<size_t>(c)] = frontier;
        }
        if (next < 0 || slack[static_cast<size_t>(c)] < step) {
          step = slack[static_cast<size_t>(c)];
          next = c;
        }
      }
      for (int c = 0; c <= cols; ++c) {
        if (settled[static_cast<size_t>(c)]) {
          row_potential[static_cast<size_t>(owner[static_cast<size_t>(c)])] += step;
          col_potential[static_cast<size_t>(c)] -= step;
        } else {
          slack[static_cast<size_t>(c)] -= step;
        }
      }
      frontier = next;
    }
    // Flip the path: every column on it passes to the row of the column before it.
    while (frontier != root) {
      const int previous = came_from[static_cast<size_t>(frontier)];
      owner[static_cast<size_t>(frontier)] = owner[static_cast<size_t>(previous)];
      frontier = previous;
    }
  }
  std::vector<int> row_to_col(static_cast<size_t>(rows), -1);
  for (int c = 0; c < cols; ++c) {
    if (owner[static_cast<size_t>(c)] >= 0) row_to_col[static_cast<size_t>(owner[static_cast<size_t>(c)])] = c;
  }
  return row_to_col;
}

}  // namespace

Result<Assignment> solveAssignment(const Eigen::MatrixXd& cost, double forbidden) {
  if (std::isnan(forbidden)) return Status(StatusCode::kInvalidArgument, "assignment: the forbidden threshold is NaN");
  for (Eigen::Index r = 0; r < cost.rows(); ++r) {
    for (Eigen::Index c = 0; c < cost.cols(); ++c) {
      const double entry = cost(r, c);
      if (std::isnan(entry) || entry == -std::numeric_limits<double>::infinity()) {
        std::ostringstream message;
        message << "assignment: cost(" << r << ", " << c << ") is " << entry;
        return Status(StatusCode::kInvalidArgument, message.str());
      }
    }
  }
  // The potentials add and subtract costs; a sum that overflows would turn into NaN comparisons.
  double magnitude = 0.0;
  for (Eigen::Index i = 0; i < cost.size(); ++i) {
    if (isAllowedCost(cost.data()[i], forbidden)) magnitude += std::abs(cost.data()[i]);
  }
  if (!std::isfinite(magnitude)) {
    return Status(StatusCode::kInvalidArgument, "assignment: the allowed costs are too large to add up in double");
  }
  const int rows = static_cast<int>(cost.rows());
  const int cols = static_cast<int>(cost.cols());
  Assignment assignment;
  assignment.row_to_col.assign(static_cast<size_t>(rows), -1);
  if (rows == 0 || cols == 0) return assignment;

  // Every row of the smaller side gets some cell; a forbidden cell costs one penalty unit and stands
  // for "unassigned". Any partial assignment extends to a full one over forbidden cells (there are
  // enough columns), so minimising (penalties, sum) maximises the assigned count, then minimises cost.
  const bool transposed = rows > cols;
  const auto lex = [&](int r, int c) {
    const double entry = cost(r, c);
    return isAllowedCost(entry, forbidden) ? LexCost{0, entry} : LexCost{1, 0.0};
  };
  std::vector<int> side;
  if (!transposed) {
    side = assignAllRows(rows, cols, lex);
    for (int r = 0; r < rows; ++r) assignment.row_to_col[static_cast<size_t>(r)] = side[static_cast<size_t>(r)];
  } else {
    side = assignAllRows(cols, rows, [&](int c, int r) { return lex(r, c); });
    for (int c = 0; c < cols; ++c) assignment.row_to_col[static_cast<size_t>(side[static_cast<size_t>(c)])] = c;
  }
  for (int r = 0; r < rows; ++r) {
    int& col = assignment.row_to_col[static_cast<size_t>(r)];
    if (col < 0) continue;
    if (!isAllowedCost(cost(r, col), forbidden)) {
      col = -1;
      continue;
    }
    ++assignment.assigned_rows;
    assignment.total_cost += cost(r, col);
  }
  return assignment;
}

}  // namespace dualgraph
