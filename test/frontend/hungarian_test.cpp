// SPDX-License-Identifier: MIT
// solveAssignment against exhaustive enumeration of every injective partial assignment under the same
// rule (most assigned rows first, then least cost), on random rectangular matrices with forbidden
// entries and ties; hand cases; bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "dualgraph/frontend/gates/hungarian.h"

namespace dualgraph {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct BruteForceBest {
  int assigned_rows = 0;
  double total_cost = 0.0;
};

/// Tries, row by row, "unassigned" and every free allowed column; keeps the lexicographic best.
void enumerate(const Eigen::MatrixXd& cost, double forbidden, int row, std::vector<char>& used, int count,
               double sum, BruteForceBest& best) {
  if (row == cost.rows()) {
    if (count > best.assigned_rows || (count == best.assigned_rows && sum < best.total_cost)) best = {count, sum};
    return;
  }
  enumerate(cost, forbidden, row + 1, used, count, sum, best);
  for (int c = 0; c < cost.cols(); ++c) {
    if (used[static_cast<size_t>(c)] || !isAllowedCost(cost(row, c), forbidden)) continue;
    used[static_cast<size_t>(c)] = 1;
    enumerate(cost, forbidden, row + 1, used, count + 1, sum + cost(row, c), best);
    used[static_cast<size_t>(c)] = 0;
  }
}

BruteForceBest bruteForce(const Eigen::MatrixXd& cost, double forbidden) {
  BruteForceBest best{0, 0.0};
  std::vector<char> used(static_cast<size_t>(cost.cols()), 0);
  enumerate(cost, forbidden, 0, used, 0, 0.0, best);
  return best;
}

/// The solution is a valid partial assignment: right size, injective, allowed entries only, and its
/// reported count and cost are those of its entries.
void expectConsistent(const Eigen::MatrixXd& cost, double forbidden, const Assignment& a) {
  ASSERT_EQ(a.row_to_col.size(), static_cast<size_t>(cost.rows()));
  std::vector<char> used(static_cast<size_t>(cost.cols()), 0);
  int count = 0;
  double sum = 0.0;
  for (int r = 0; r < cost.rows(); ++r) {
    const int c = a.row_to_col[static_cast<size_t>(r)];
    if (c < 0) continue;
    ASSERT_LT(c, cost.cols());
    EXPECT_FALSE(used[static_cast<size_t>(c)]) << "column " << c << " used twice";
    used[static_cast<size_t>(c)] = 1;
    EXPECT_TRUE(isAllowedCost(cost(r, c), forbidden)) << "forbidden cell (" << r << ", " << c << ")";
    ++count;
    sum += cost(r, c);
  }
  EXPECT_EQ(a.assigned_rows, count);
  EXPECT_NEAR(a.total_cost, sum, 1e-12 * (1.0 + std::abs(sum)));
}

TEST(Hungarian, EqualsBruteForceOnRandomRectangularMatricesWithForbiddenEntries) {
  std::mt19937 rng(20240611);
  std::uniform_int_distribution<int> size(1, 7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int partial_cases = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const int rows = size(rng);
    const int cols = size(rng);
    const double forbidden_probability = (trial % 5) * 0.2;    // 0 .. 0.8
    const bool integer_costs = trial % 3 == 0;                  // many ties
    const bool use_threshold = trial % 4 == 1;                  // forbidden by threshold, not by +inf
    const double threshold = use_threshold ? 7.0 : kInf;
    Eigen::MatrixXd cost(rows, cols);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        double value = integer_costs ? std::floor(unit(rng) * 4.0) : unit(rng) * 10.0 - 3.0;  // negatives too
        if (unit(rng) < forbidden_probability) value = use_threshold ? threshold + unit(rng) * 5.0 : kInf;
        cost(r, c) = value;
      }
    }
    const Result<Assignment> result = solveAssignment(cost, threshold);
    ASSERT_TRUE(result.ok()) << result.status().toString();
    const BruteForceBest best = bruteForce(cost, threshold);
    expectConsistent(cost, threshold, *result);
    ASSERT_EQ(result->assigned_rows, best.assigned_rows) << "trial " << trial << "\n" << cost;
    ASSERT_NEAR(result->total_cost, best.total_cost, 1e-9 * (1.0 + std::abs(best.total_cost)))
        << "trial " << trial << "\n" << cost;
    if (best.assigned_rows < std::min(rows, cols)) ++partial_cases;
  }
  EXPECT_GT(partial_cases, 500);  // the "not every row can be assigned" rule was really exercised
}

TEST(Hungarian, PrefersMoreAssignedRowsOverLowerCost) {
  // Row 0 alone would take column 0 for 0; but then row 1 (only column 0 allowed) is left out.
  Eigen::MatrixXd cost(2, 2);
  cost << 0.0, 100.0,
          1.0, kInf;
  const Result<Assignment> result = solveAssignment(cost);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->row_to_col, (std::vector<int>{1, 0}));
  EXPECT_EQ(result->assigned_rows, 2);
  EXPECT_DOUBLE_EQ(result->total_cost, 101.0);
}

TEST(Hungarian, AllForbiddenLeavesEveryRowUnassigned) {
  const Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(3, 4, kInf);
  const Result<Assignment> result = solveAssignment(cost);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->row_to_col, (std::vector<int>{-1, -1, -1}));
  EXPECT_EQ(result->assigned_rows, 0);
  EXPECT_EQ(result->total_cost, 0.0);
}

TEST(Hungarian, ThresholdForbidsEntriesAtOrAboveIt) {
  Eigen::MatrixXd cost(1, 3);
  cost << 2.0, 2.5, 3.0;
  const Result<Assignment> result = solveAssignment(cost, 2.0);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->row_to_col, (std::vector<int>{-1}));
}

TEST(Hungarian, SingleRowTakesItsCheapestAllowedColumn) {
  Eigen::MatrixXd cost(1, 5);
  cost << 4.0, kInf, 1.5, 3.0, -0.5;
  const Result<Assignment> result = solveAssignment(cost);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->row_to_col, (std::vector<int>{4}));
  EXPECT_DOUBLE_EQ(result->total_cost, -0.5);
}

TEST(Hungarian, TallMatrixLeavesTheCostliestRowsOut) {
  Eigen::MatrixXd cost(4, 2);
  cost << 5.0, 5.0,
          1.0, 9.0,
          9.0, 1.0,
          2.0, 2.0;
  const Result<Assignment> result = solveAssignment(cost);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->row_to_col, (std::vector<int>{-1, 0, 1, -1}));
  EXPECT_DOUBLE_EQ(result->total_cost, 2.0);
}

TEST(Hungarian, TiesGiveAnOptimalValidAssignment) {
  const Eigen::MatrixXd cost = Eigen::MatrixXd::Ones(3, 3);
  const Result<Assignment> result = solveAssignment(cost);
  ASSERT_TRUE(result.ok());
  expectConsistent(cost, kInf, *result);
  EXPECT_EQ(result->assigned_rows, 3);
  EXPECT_DOUBLE_EQ(result->total_cost, 3.0);
}

TEST(Hungarian, EmptyMatricesAssignNothing) {
  const Result<Assignment> no_cols = solveAssignment(Eigen::MatrixXd(2, 0));
  ASSERT_TRUE(no_cols.ok());
  EXPECT_EQ(no_cols->row_to_col, (std::vector<int>{-1, -1}));
  const Result<Assignment> no_rows = solveAssignment(Eigen::MatrixXd(0, 3));
  ASSERT_TRUE(no_rows.ok());
  EXPECT_TRUE(no_rows->row_to_col.empty());
}

TEST(Hungarian, NaNCostIsInvalidArgumentNamingTheCell) {
  Eigen::MatrixXd cost = Eigen::MatrixXd::Ones(2, 3);
  cost(1, 2) = std::numeric_limits<double>::quiet_NaN();
  const Result<Assignment> result = solveAssignment(cost);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(result.status().message().find("(1, 2)"), std::string::npos) << result.status().message();
}

TEST(Hungarian, NegativeInfinityAndNaNThresholdAreInvalidArgument) {
  Eigen::MatrixXd cost = Eigen::MatrixXd::Ones(2, 2);
  EXPECT_EQ(solveAssignment(cost, std::nan("")).status().code(), StatusCode::kInvalidArgument);
  cost(0, 0) = -kInf;
  EXPECT_EQ(solveAssignment(cost).status().code(), StatusCode::kInvalidArgument);
}

TEST(Hungarian, CostsTooLargeToAddUpAreInvalidArgument) {
  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(2, 2, 1e308);
  EXPECT_EQ(solveAssignment(cost).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace dualgraph
