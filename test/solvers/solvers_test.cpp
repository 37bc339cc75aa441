// SPDX-License-Identifier: MIT
// CHOLMOD and Eigen against a dense solve on block-sparse SPD matrices in the optimiser's layout.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <vector>

#include "solvers/cholmod_solver.h"
#include "solvers/eigen_solver.h"
#include "solvers/linear_solver_factory.h"

namespace dualgraph {
namespace {

/// Upper-triangular CSC of a dense symmetric matrix (entries with |value| > 0 or on the diagonal).
struct Csc {
  int n = 0;
  std::vector<int> col_ptr{0};
  std::vector<int> row_index;
  std::vector<double> values;
  SparseMatrixView view() const { return SparseMatrixView{n, col_ptr.data(), row_index.data(), values.data()}; }
};

Csc toUpperCsc(const Eigen::MatrixXd& dense, const Eigen::MatrixXi& pattern) {
  Csc csc;
  csc.n = static_cast<int>(dense.rows());
  csc.col_ptr.assign(1, 0);
  for (int c = 0; c < csc.n; ++c) {
    for (int r = 0; r <= c; ++r) {
      if (pattern(r, c) != 0 || r == c) {
        csc.row_index.push_back(r);
        csc.values.push_back(dense(r, c));
      }
    }
    csc.col_ptr.push_back(static_cast<int>(csc.row_index.size()));
  }
  return csc;
}

/// A seeded random SPD matrix with a block-sparse pattern (a chain plus random "loop closures").
struct BlockProblem {
  Eigen::MatrixXd dense;
  Eigen::MatrixXi pattern;
};

BlockProblem randomBlockSpd(int blocks, int block_dim, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, blocks - 1);
  const int n = blocks * block_dim;
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(0, n);
  auto add_factor = [&](int i, int j) {
    Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(block_dim, n);
    for (int r = 0; r < block_dim; ++r) {
      for (int c = 0; c < block_dim; ++c) {
        rows(r, i * block_dim + c) = uniform(rng);
        if (j != i) rows(r, j * block_dim + c) = uniform(rng);
      }
    }
    Eigen::MatrixXd stacked(jacobian.rows() + block_dim, n);
    stacked << jacobian, rows;
    jacobian = stacked;
  };
  for (int k = 0; k < blocks; ++k) add_factor(k, k);
  for (int k = 0; k + 1 < blocks; ++k) add_factor(k, k + 1);
  for (int k = 0; k < blocks / 3; ++k) add_factor(pick(rng), pick(rng));
  BlockProblem problem;
  problem.dense = jacobian.transpose() * jacobian + 1e-3 * Eigen::MatrixXd::Identity(n, n);
  problem.pattern = (problem.dense.array().abs() > 0.0).cast<int>();
  return problem;
}

Eigen::VectorXd solveWith(LinearSolver& solver, const Csc& csc, const Eigen::VectorXd& b) {
  EXPECT_TRUE(solver.analyze(csc.view()).ok());
  const Status factorized = solver.factorize(csc.view());
  EXPECT_TRUE(factorized.ok()) << factorized.toString();
  Eigen::VectorXd x(b.size());
  EXPECT_TRUE(solver.solve(b.data(), x.data()).ok());
  return x;
}

class SolverAgreement : public ::testing::TestWithParam<int> {};

TEST_P(SolverAgreement, CholmodEigenAndDenseAgreeOnRandomBlockSparseSpd) {
  const int block_dim = GetParam();
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const BlockProblem problem = randomBlockSpd(60, block_dim, seed);
    const Csc csc = toUpperCsc(problem.dense, problem.pattern);
    std::mt19937 rng(seed);
    std::normal_distribution<double> normal;
    Eigen::VectorXd b(problem.dense.rows());
    for (int k = 0; k < b.size(); ++k) b[k] = normal(rng);
    const Eigen::VectorXd dense = problem.dense.llt().solve(b);
    CholmodSolver supernodal;
    CholmodOptions simplicial_options;
    simplicial_options.supernodal = false;
    simplicial_options.amd_only = true;
    CholmodSolver simplicial(simplicial_options);
    EigenSolver eigen;
    const double scale = dense.norm();
    EXPECT_LT((solveWith(supernodal, csc, b) - dense).norm(), 1e-9 * scale);
    EXPECT_LT((solveWith(simplicial, csc, b) - dense).norm(), 1e-9 * scale);
    EXPECT_LT((solveWith(eigen, csc, b) - dense).norm(), 1e-9 * scale);
  }
}

INSTANTIATE_TEST_SUITE_P(BlockSizes, SolverAgreement, ::testing::Values(3, 6));

TEST(CholmodSolver, ReusesTheSymbolicAnalysisForNewValuesAndAcceptsANewPattern) {
  const BlockProblem first = randomBlockSpd(40, 6, 7);
  Csc csc = toUpperCsc(first.dense, first.pattern);
  CholmodSolver solver;
  ASSERT_TRUE(solver.analyze(csc.view()).ok());
  Eigen::VectorXd b = Eigen::VectorXd::Ones(csc.n);
  Eigen::VectorXd x(csc.n);
  for (double shift : {0.0, 1.0, 10.0}) {
    // Same pattern, new values (what LM does when it changes the damping).
    const Eigen::MatrixXd shifted = first.dense + shift * Eigen::MatrixXd::Identity(csc.n, csc.n);
    csc = toUpperCsc(shifted, first.pattern);
    ASSERT_TRUE(solver.factorize(csc.view()).ok());
    ASSERT_TRUE(solver.solve(b.data(), x.data()).ok());
    EXPECT_LT((shifted * x - b).norm(), 1e-9 * b.norm());
  }
  const BlockProblem second = randomBlockSpd(25, 3, 8);
  const Csc other = toUpperCsc(second.dense, second.pattern);
  EXPECT_FALSE(solver.factorize(other.view()).ok()) << "a different pattern needs analyze first";
  const Eigen::VectorXd b2 = Eigen::VectorXd::Ones(other.n);
  EXPECT_LT((second.dense * solveWith(solver, other, b2) - b2).norm(), 1e-9 * b2.norm());
}

TEST(LinearSolvers, IndefiniteMatrixIsReportedAndTheSolverRecovers) {
  Eigen::MatrixXd indefinite(3, 3);
  indefinite << 1, 2, 0, 2, 1, 0, 0, 0, 1;  // eigenvalues 3, -1, 1
  const Eigen::MatrixXi pattern = Eigen::MatrixXi::Ones(3, 3);
  for (auto kind : {LinearSolverKind::kCholmod, LinearSolverKind::kEigen}) {
    SCOPED_TRACE(linearSolverKindName(kind));
    auto solver = makeLinearSolver(kind);
    Csc csc = toUpperCsc(indefinite, pattern);
    ASSERT_TRUE(solver->analyze(csc.view()).ok());
    const Status failed = solver->factorize(csc.view());
    EXPECT_EQ(failed.code(), StatusCode::kNotPositiveDefinite) << failed.toString();
    Eigen::Vector3d x;
    const Eigen::Vector3d b(1, 2, 3);
    EXPECT_FALSE(solver->solve(b.data(), x.data()).ok()) << "no solve after a failed factorisation";
    // Damping as LM would add it makes the matrix SPD again: same pattern, new values.
    const Eigen::MatrixXd damped = indefinite + 2.0 * Eigen::MatrixXd::Identity(3, 3);
    csc = toUpperCsc(damped, pattern);
    ASSERT_TRUE(solver->factorize(csc.view()).ok());
    ASSERT_TRUE(solver->solve(b.data(), x.data()).ok());
    EXPECT_LT((damped * x - b).norm(), 1e-12);
  }
}

TEST(LinearSolvers, SolveBeforeFactorizeIsAnErrorNotACrash) {
  for (auto kind : {LinearSolverKind::kCholmod, LinearSolverKind::kEigen}) {
    auto solver = makeLinearSolver(kind);
    double b = 1.0;
    double x = 0.0;
    EXPECT_EQ(solver->solve(&b, &x).code(), StatusCode::kFailedPrecondition);
  }
}

TEST(LinearSolvers, EmptyAndOneByOneSystems) {
  for (auto kind : {LinearSolverKind::kCholmod, LinearSolverKind::kEigen}) {
    SCOPED_TRACE(linearSolverKindName(kind));
    auto solver = makeLinearSolver(kind);
    Csc empty;
    EXPECT_TRUE(solver->analyze(empty.view()).ok());
    EXPECT_TRUE(solver->factorize(empty.view()).ok());
    EXPECT_TRUE(solver->solve(nullptr, nullptr).ok());
    Csc one = toUpperCsc(Eigen::MatrixXd::Constant(1, 1, 4.0), Eigen::MatrixXi::Ones(1, 1));
    EXPECT_EQ(solveWith(*solver, one, Eigen::VectorXd::Constant(1, 2.0))[0], 0.5);
  }
}

TEST(LinearSolverFactory, ParsesNamesAndRejectsUnknownOnes) {
  EXPECT_EQ(*parseLinearSolverKind("cholmod"), LinearSolverKind::kCholmod);
  EXPECT_EQ(*parseLinearSolverKind("eigen"), LinearSolverKind::kEigen);
  const auto bad = parseLinearSolverKind("cholesky");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("cholesky"), std::string::npos);
  EXPECT_EQ(makeLinearSolver(LinearSolverKind::kCholmod)->name(), "cholmod-supernodal");
  EXPECT_EQ(makeLinearSolver(LinearSolverKind::kEigen)->name(), "eigen-simplicial-ldlt");
}

}  // namespace
}  // namespace dualgraph
