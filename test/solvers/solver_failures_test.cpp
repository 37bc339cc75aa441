// SPDX-License-Identifier: MIT
// What every solver does with matrices and call orders the optimiser must survive: indefinite and
// non-finite matrices, calls out of order, a changed pattern, malformed input, n = 0 and 1×1.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test/solvers/spd_test_matrices.h"

namespace dualgraph {
namespace {

using testing::BlockProblem;
using testing::Csc;
using testing::SolverCase;

class SolverFailures : public ::testing::TestWithParam<SolverCase> {};

TEST_P(SolverFailures, IndefiniteMatrixIsNotPositiveDefiniteAndRaisingTheDampingRecovers) {
  const BlockProblem problem = testing::randomBlockSpd(50, 6, 41);
  // H − s·I with s just below H's smallest diagonal entry: every diagonal entry stays positive, but
  // s exceeds λmin(H) (which lies below the smallest diagonal entry of any non-diagonal SPD matrix).
  const double shift = -0.99 * problem.dense.diagonal().minCoeff();
  const Csc indefinite = problem.shifted(shift);
  const Eigen::MatrixXd h_indefinite = problem.dense + shift * Eigen::MatrixXd::Identity(problem.n(), problem.n());
  ASSERT_NE(h_indefinite.llt().info(), Eigen::Success) << "precondition: the shifted matrix is indefinite";
  auto solver = GetParam().make();
  ASSERT_TRUE(solver->analyze(problem.csc().view()).ok());
  const Eigen::VectorXd b = testing::randomVector(problem.n(), 42);
  Eigen::VectorXd x(problem.n());
  // LM reacts to kNotPositiveDefinite by raising λ until the matrix factorises.
  const Status failed = solver->factorize(indefinite.view());
  EXPECT_EQ(failed.code(), StatusCode::kNotPositiveDefinite) << failed.toString();
  EXPECT_EQ(solver->solve(b.data(), x.data()).code(), StatusCode::kFailedPrecondition)
      << "no solve with a failed factorisation";
  ASSERT_TRUE(solver->factorize(problem.shifted(0.5).view()).ok());
  ASSERT_TRUE(solver->solve(b.data(), x.data()).ok());
  const Eigen::MatrixXd h = problem.dense + 0.5 * Eigen::MatrixXd::Identity(problem.n(), problem.n());
  EXPECT_LT((x - h.llt().solve(b)).norm() / x.norm(), 1e-10);
}

TEST_P(SolverFailures, SmallIndefiniteAndSemidefiniteMatricesAreNotPositiveDefinite) {
  Eigen::Matrix3d indefinite;
  indefinite << 1, 2, 0, 2, 1, 0, 0, 0, 1;  // eigenvalues 3, −1, 1; every diagonal entry positive
  Eigen::Matrix3d singular;
  singular << 1, 1, 0, 1, 1, 0, 0, 0, 1;  // eigenvalues 2, 0, 1
  for (const Eigen::Matrix3d& h : {indefinite, singular}) {
    auto solver = GetParam().make();
    const Csc csc = testing::toUpperCsc(h, Eigen::MatrixXi::Ones(3, 3));
    ASSERT_TRUE(solver->analyze(csc.view()).ok());
    const Status failed = solver->factorize(csc.view());
    EXPECT_EQ(failed.code(), StatusCode::kNotPositiveDefinite) << failed.toString();
  }
}

TEST_P(SolverFailures, NamesTheOriginalRowOfADecoupledNegativePivot) {
  // A chain with one variable that couples to nothing and has a negative diagonal.
  const int n = 12;
  const int bad = 7;
  Eigen::MatrixXd h = 4.0 * Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXi pattern = Eigen::MatrixXi::Identity(n, n);
  for (int k = 0; k + 1 < n; ++k) {
    if (k == bad || k + 1 == bad) continue;
    h(k, k + 1) = h(k + 1, k) = 1.0;
    pattern(k, k + 1) = pattern(k + 1, k) = 1;
  }
  h(bad, bad) = -1.0;
  auto solver = GetParam().make();
  const Csc csc = testing::toUpperCsc(h, pattern);
  ASSERT_TRUE(solver->analyze(csc.view()).ok());
  const Status failed = solver->factorize(csc.view());
  ASSERT_EQ(failed.code(), StatusCode::kNotPositiveDefinite);
  EXPECT_NE(failed.message().find("row/column 7 of 12"), std::string::npos) << failed.message();
}

TEST_P(SolverFailures, NonFiniteValuesAreANumericalErrorNamingTheEntry) {
  const BlockProblem problem = testing::randomBlockSpd(10, 3, 51);
  auto solver = GetParam().make();
  Csc csc = problem.csc();
  ASSERT_TRUE(solver->analyze(csc.view()).ok());
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Csc poisoned = csc;
    poisoned.values[poisoned.col_ptr[4] + 1] = bad;  // column 4, its second stored row
    const Status failed = solver->factorize(poisoned.view());
    EXPECT_EQ(failed.code(), StatusCode::kNumericalError) << failed.toString();
    EXPECT_NE(failed.message().find("column 4"), std::string::npos) << failed.message();
  }
  ASSERT_TRUE(solver->factorize(csc.view()).ok()) << "the next finite matrix factorises";
}

TEST_P(SolverFailures, CallsOutOfOrderAreErrorsNotCrashes) {
  auto solver = GetParam().make();
  double b = 1.0;
  double x = 0.0;
  EXPECT_EQ(solver->solve(&b, &x).code(), StatusCode::kFailedPrecondition);
  const Csc csc = testing::randomBlockSpd(5, 3, 61).csc();
  EXPECT_EQ(solver->factorize(csc.view()).code(), StatusCode::kFailedPrecondition);
  ASSERT_TRUE(solver->analyze(csc.view()).ok());
  EXPECT_EQ(solver->solve(&b, &x).code(), StatusCode::kFailedPrecondition) << "analysed, not factorised";
}

TEST_P(SolverFailures, FactorizeRejectsAPatternOtherThanTheAnalysedOne) {
  const Eigen::Matrix3d h = Eigen::Vector3d(4, 5, 6).asDiagonal();
  Eigen::MatrixXi couples_01 = Eigen::MatrixXi::Identity(3, 3);
  couples_01(0, 1) = couples_01(1, 0) = 1;
  Eigen::MatrixXi couples_12 = Eigen::MatrixXi::Identity(3, 3);
  couples_12(1, 2) = couples_12(2, 1) = 1;
  const Csc first = testing::toUpperCsc(h, couples_01);
  const Csc second = testing::toUpperCsc(h, couples_12);  // same n and nnz, other entries
  const Csc larger = testing::randomBlockSpd(4, 3, 71).csc();
  auto solver = GetParam().make();
  ASSERT_TRUE(solver->analyze(first.view()).ok());
  EXPECT_EQ(solver->factorize(second.view()).code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(solver->factorize(larger.view()).code(), StatusCode::kFailedPrecondition);
  ASSERT_TRUE(solver->analyze(second.view()).ok());
  ASSERT_TRUE(solver->factorize(second.view()).ok());
}

TEST_P(SolverFailures, MalformedMatricesAreInvalidArguments) {
  const int col_ptr[] = {0, 1, 3};
  const int lower_entry[] = {0, 0, 2};  // row 2 in a 2×2 matrix's column 1
  const int unsorted[] = {0, 1, 0};
  const int sorted[] = {0, 0, 1};
  const int bad_start[] = {1, 1, 3};
  const double values[] = {2.0, 0.5, 2.0};
  auto solver = GetParam().make();
  for (const SparseMatrixView& view : {SparseMatrixView{2, col_ptr, lower_entry, values},
                                       SparseMatrixView{2, col_ptr, unsorted, values},
                                       SparseMatrixView{2, bad_start, sorted, values},
                                       SparseMatrixView{2, nullptr, sorted, values},
                                       SparseMatrixView{-1, nullptr, nullptr, nullptr}}) {
    const Status rejected = solver->analyze(view);
    EXPECT_EQ(rejected.code(), StatusCode::kInvalidArgument) << rejected.toString();
    EXPECT_EQ(solver->factorize(view).code(), StatusCode::kFailedPrecondition);
  }
  const SparseMatrixView good{2, col_ptr, sorted, values};
  ASSERT_TRUE(solver->analyze(good).ok());
  ASSERT_TRUE(solver->factorize(good).ok());
}

TEST_P(SolverFailures, EmptySystemIsTrivial) {
  auto solver = GetParam().make();
  const Csc empty;
  EXPECT_TRUE(solver->analyze(empty.view()).ok());
  EXPECT_TRUE(solver->factorize(empty.view()).ok());
  EXPECT_TRUE(solver->solve(nullptr, nullptr).ok());
  // And the solver still works on a real matrix afterwards.
  const Csc one = testing::toUpperCsc(Eigen::MatrixXd::Constant(1, 1, 4.0), Eigen::MatrixXi::Ones(1, 1));
  ASSERT_TRUE(solver->analyze(one.view()).ok());
  ASSERT_TRUE(solver->factorize(one.view()).ok());
}

TEST_P(SolverFailures, OneByOneSystems) {
  auto solver = GetParam().make();
  const Eigen::MatrixXi pattern = Eigen::MatrixXi::Ones(1, 1);
  const Csc four = testing::toUpperCsc(Eigen::MatrixXd::Constant(1, 1, 4.0), pattern);
  ASSERT_TRUE(solver->analyze(four.view()).ok());
  ASSERT_TRUE(solver->factorize(four.view()).ok());
  const double b = 2.0;
  double x = 0.0;
  ASSERT_TRUE(solver->solve(&b, &x).ok());
  EXPECT_DOUBLE_EQ(x, 0.5);
  for (double bad : {0.0, -3.0}) {
    const Csc not_spd = testing::toUpperCsc(Eigen::MatrixXd::Constant(1, 1, bad), pattern);
    EXPECT_EQ(solver->factorize(not_spd.view()).code(), StatusCode::kNotPositiveDefinite) << bad;
  }
}

TEST_P(SolverFailures, NeverPrintsEvenWhenTheMatrixIsIndefinite) {
  Eigen::Matrix2d h;
  h << 1, 3, 3, 1;
  const Csc csc = testing::toUpperCsc(h, Eigen::MatrixXi::Ones(2, 2));
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  {
    auto solver = GetParam().make();
    const Status analyzed = solver->analyze(csc.view());
    const Status factorized = solver->factorize(csc.view());
    EXPECT_TRUE(analyzed.ok());
    EXPECT_EQ(factorized.code(), StatusCode::kNotPositiveDefinite);
  }
  const std::string out = ::testing::internal::GetCapturedStdout();
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
}

INSTANTIATE_TEST_SUITE_P(Solvers, SolverFailures, ::testing::ValuesIn(testing::allSolverCases()),
                         [](const auto& info) { return info.param.label; });

}  // namespace
}  // namespace dualgraph
