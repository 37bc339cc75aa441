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

INSTANTIATE_TEST_SUITE_P(AllSolvers, SolveColumns, ::testing::ValuesIn(allSolverCases()),
                         [](const auto& info) { return info.param.label; });

}  // namespace
}  // namespace dualgraph
