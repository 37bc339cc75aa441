// SPDX-License-Identifier: MIT
// solveColumns: a block of right-hand sides in one pass equals the dense solve, for every solver and
// for the column-by-column default of LinearSolver; size mismatches are statuses.
#include <gtest/gtest.h>

#include "test/solvers/spd_test_matrices.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

/// Keeps the base class's column-by-column default (does not override solveColumns).
class ColumnByColumn final : public LinearSolver {
 public:
  explicit ColumnByColumn(std::unique_ptr<LinearSolver> inner) : inner_(std::move(inner)) {}
  Status analyze(const SparseMatrixView& m) override { return inner_->analyze(m); }
  Status factorize(const SparseMatrixView& m) override { return inner_->factorize(m); }
  Status solve(const double* b, double* x) override { return inner_->solve(b, x); }
  std::string name() const override { return "column-by-column"; }

 private:
  std::unique_ptr<LinearSolver> inner_;
};

class SolveColumns : public ::testing::TestWithParam<SolverCase> {};

TEST_P(SolveColumns, ABlockOfRightHandSidesEqualsTheDenseSolve) {
  const BlockProblem problem = randomBlockSpd(40, 6, 11);
  const Csc csc = problem.csc();
  for (const bool wrap_default : {false, true}) {
    std::unique_ptr<LinearSolver> solver = GetParam().make();
    if (wrap_default) solver = std::make_unique<ColumnByColumn>(std::move(solver));
    ASSERT_TRUE(solver->analyze(csc.view()).ok());
    ASSERT_TRUE(solver->factorize(csc.view()).ok());
    for (const int columns : {1, 3, 12, 30}) {
      Eigen::MatrixXd B(problem.n(), columns);
      for (int c = 0; c < columns; ++c) B.col(c) = randomVector(problem.n(), 100 + c);
      Eigen::MatrixXd X(problem.n(), columns);
      ASSERT_TRUE(solver->solveColumns(B.data(), X.data(), problem.n(), columns).ok());
      const Eigen::MatrixXd expected = problem.dense.llt().solve(B);
      EXPECT_LT((X - expected).norm() / expected.norm(), 1e-10) << columns << " columns, default " << wrap_default;
    }
    Eigen::MatrixXd B = Eigen::MatrixXd::Ones(problem.n(), 2), X(problem.n(), 2);
    EXPECT_FALSE(solver->solveColumns(B.data(), X.data(), problem.n(), -1).ok());
    EXPECT_TRUE(solver->solveColumns(B.data(), X.data(), problem.n(), 0).ok());
  }
}

TEST_P(SolveColumns, AWrongRowCountIsAnError) {
  const BlockProblem problem = randomBlockSpd(5, 3, 4);
  const Csc csc = problem.csc();
  std::unique_ptr<LinearSolver> solver = GetParam().make();
  Eigen::MatrixXd B = Eigen::MatrixXd::Ones(problem.n() + 1, 2), X(problem.n() + 1, 2);
  EXPECT_EQ(solver->solveColumns(B.data(), X.data(), problem.n(), 2).code(), StatusCode::kFailedPrecondition);
  ASSERT_TRUE(solver->analyze(csc.view()).ok());
  ASSERT_TRUE(solver->factorize(csc.view()).ok());
  EXPECT_EQ(solver->solveColumns(B.data(), X.data(), problem.n() + 1, 2).code(), StatusCode::kInvalidArgument);
}

// Only the requested rows are compared (the others are unspecified): unit columns as the marginals use
// them, dense columns, rows at the start, the middle and the end of the system, for every solver
// (EigenSolver restricts its substitutions; the others solve in full through the base class).
TEST_P(SolveColumns, AtRowsEqualsTheDenseSolveOnTheRequestedRows) {
  const BlockProblem problem = randomBlockSpd(30, 6, 5);
  const Csc csc = problem.csc();
  const int n = problem.n();
  std::unique_ptr<LinearSolver> solver = GetParam().make();
  ASSERT_TRUE(solver->analyze(csc.view()).ok());
  ASSERT_TRUE(solver->factorize(csc.view()).ok());
  const Eigen::MatrixXd inverse = problem.dense.inverse();
  const std::vector<std::vector<int>> row_sets = {
      {n - 6, n - 5, n - 4, n - 3, n - 2, n - 1}, {0, 1, 2}, {97, 40, 150, n - 1}, {n / 2}};
  for (const std::vector<int>& rows : row_sets) {
    SCOPED_TRACE("first row " + std::to_string(rows.front()));
    // Unit columns at the requested rows: the rows' block of H⁻¹.
    Eigen::MatrixXd units = Eigen::MatrixXd::Zero(n, static_cast<int>(rows.size()));
    for (size_t k = 0; k < rows.size(); ++k) units(rows[k], static_cast<int>(k)) = 1.0;
    Eigen::MatrixXd X = Eigen::MatrixXd::Constant(n, units.cols(), 123.0);
    ASSERT_TRUE(solver->solveColumnsAtRows(units.data(), X.data(), n, static_cast<int>(units.cols()), rows.data(),
                                           static_cast<int>(rows.size())).ok());
    for (size_t r = 0; r < rows.size(); ++r) {
      for (size_t c = 0; c < rows.size(); ++c) {
        EXPECT_NEAR(X(rows[r], static_cast<int>(c)), inverse(rows[r], rows[c]), 1e-10 * inverse.norm());
      }
    }
    // Dense right-hand sides.
    Eigen::MatrixXd B(n, 3);
    for (int c = 0; c < 3; ++c) B.col(c) = randomVector(n, 200 + c);
    const Eigen::MatrixXd expected = problem.dense.llt().solve(B);
    Eigen::MatrixXd Y(n, 3);
    ASSERT_TRUE(solver->solveColumnsAtRows(B.data(), Y.data(), n, 3, rows.data(), static_cast<int>(rows.size())).ok());
    for (int row : rows) EXPECT_LT((Y.row(row) - expected.row(row)).norm(), 1e-10 * expected.norm()) << "row " << row;
  }
}

TEST(SolveColumnsAtRows, EigenRejectsRowsOutsideTheSystemAndSolvesBeforeFactorize) {
  const BlockProblem problem = randomBlockSpd(4, 3, 6);
  const Csc csc = problem.csc();
  for (const EigenOrdering ordering : {EigenOrdering::kAmd, EigenOrdering::kNatural}) {
    EigenSolver solver(ordering);
    Eigen::MatrixXd B = Eigen::MatrixXd::Ones(problem.n(), 1), X(problem.n(), 1);
    const int good[] = {0}, bad[] = {problem.n()}, negative[] = {-1};
    EXPECT_EQ(solver.solveColumnsAtRows(B.data(), X.data(), problem.n(), 1, good, 1).code(),
              StatusCode::kFailedPrecondition);
    ASSERT_TRUE(solver.analyze(csc.view()).ok());
    ASSERT_TRUE(solver.factorize(csc.view()).ok());
    EXPECT_EQ(solver.solveColumnsAtRows(B.data(), X.data(), problem.n(), 1, bad, 1).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(solver.solveColumnsAtRows(B.data(), X.data(), problem.n(), 1, negative, 1).code(),
              StatusCode::kInvalidArgument);
    EXPECT_EQ(solver.solveColumnsAtRows(B.data(), X.data(), problem.n(), 1, nullptr, 1).code(),
              StatusCode::kInvalidArgument);
    EXPECT_TRUE(solver.solveColumnsAtRows(B.data(), X.data(), problem.n(), 1, good, 0).ok());
  }
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, SolveColumns, ::testing::ValuesIn(allSolverCases()),
                         [](const auto& info) { return info.param.label; });

}  // namespace
}  // namespace dualgraph
