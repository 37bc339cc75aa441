// SPDX-License-Identifier: MIT
// CHOLMOD and Eigen against a dense LLᵀ solve on block-sparse SPD matrices in the optimiser's
// layout, symbolic-analysis reuse across value changes, and re-analysis for a new pattern.
#include <gtest/gtest.h>

#include <random>

#include "dualgraph/solvers/cholmod_solver.h"
#include "dualgraph/solvers/eigen_solver.h"
#include "test/solvers/spd_test_matrices.h"

namespace dualgraph {
namespace {

using testing::BlockProblem;
using testing::Csc;
using testing::SolverCase;

/// analyze + factorize + solve, failing the test (not crashing) on any error status.
Eigen::VectorXd analyzeFactorizeSolve(LinearSolver& solver, const Csc& csc, const Eigen::VectorXd& b) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
  const Status analyzed = solver.analyze(csc.view());
  EXPECT_TRUE(analyzed.ok()) << analyzed.toString();
  const Status factorized = solver.factorize(csc.view());
  EXPECT_TRUE(factorized.ok()) << factorized.toString();
  const Status solved = solver.solve(b.data(), x.data());
  EXPECT_TRUE(solved.ok()) << solved.toString();
  return x;
}

double relativeError(const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
  return (x - reference).norm() / reference.norm();
}

class SolverAgreement : public ::testing::TestWithParam<int> {};

TEST_P(SolverAgreement, CholmodEigenAndDenseLltAgreeOnRandomBlockSparseSpd) {
  const int block_dim = GetParam();
  for (unsigned seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const BlockProblem problem = testing::randomBlockSpd(60, block_dim, seed);  // 180 or 360 rows
    const Csc csc = problem.csc();
    const Eigen::VectorXd b = testing::randomVector(problem.n(), 100 + seed);
    const Eigen::LLT<Eigen::MatrixXd> dense_llt(problem.dense);
    ASSERT_EQ(dense_llt.info(), Eigen::Success);
    const Eigen::VectorXd x_dense = dense_llt.solve(b);

    Eigen::VectorXd x_eigen;
    for (const SolverCase& c : testing::allSolverCases()) {
      SCOPED_TRACE(c.label);
      auto solver = c.make();
      const Eigen::VectorXd x = analyzeFactorizeSolve(*solver, csc, b);
      EXPECT_LT(relativeError(x, x_dense), 1e-10);
      EXPECT_LT((problem.dense * x - b).norm() / b.norm(), 1e-12);
      if (c.label == "Eigen") x_eigen = x;
    }
    CholmodSolver cholmod;
    EXPECT_LT(relativeError(analyzeFactorizeSolve(cholmod, csc, b), x_eigen), 1e-10);
  }
}

INSTANTIATE_TEST_SUITE_P(BlockSizes, SolverAgreement, ::testing::Values(3, 6),
                         [](const auto& info) { return "Block" + std::to_string(info.param); });

class EverySolver : public ::testing::TestWithParam<SolverCase> {};

TEST_P(EverySolver, RefactorizesNewValuesOnTheAnalysedPatternLikeLevenbergMarquardt) {
  const BlockProblem problem = testing::randomBlockSpd(40, 6, 7);
  auto solver = GetParam().make();
  ASSERT_TRUE(solver->analyze(problem.csc().view()).ok());  // once; every factorize below reuses it
  const Eigen::VectorXd b = testing::randomVector(problem.n(), 8);
  Eigen::VectorXd x(problem.n());
  for (double lambda : {1e-4, 1e-2, 1.0, 100.0, 1e-3}) {
    SCOPED_TRACE("lambda " + std::to_string(lambda));
    const Csc damped = problem.shifted(lambda);
    ASSERT_TRUE(solver->factorize(damped.view()).ok());
    ASSERT_TRUE(solver->solve(b.data(), x.data()).ok());
    const Eigen::MatrixXd h = problem.dense + lambda * Eigen::MatrixXd::Identity(problem.n(), problem.n());
    EXPECT_LT(relativeError(x, h.llt().solve(b)), 1e-10);
    // Solving twice with one factorisation (the workspaces are reused) gives the same answer.
    Eigen::VectorXd again(problem.n());
    ASSERT_TRUE(solver->solve(b.data(), again.data()).ok());
    EXPECT_EQ(again, x);
  }
}

TEST_P(EverySolver, AnalyzeAgainAcceptsANewPatternOfAnySize) {
  auto solver = GetParam().make();
  int shape = 0;
  for (const auto& [blocks, block_dim, seed] : {std::tuple{40, 6, 11u}, std::tuple{25, 3, 12u},
                                                 std::tuple{25, 3, 13u}, std::tuple{70, 6, 14u}}) {
    SCOPED_TRACE("shape " + std::to_string(shape++));
    const BlockProblem problem = testing::randomBlockSpd(blocks, block_dim, seed);
    const Eigen::VectorXd b = testing::randomVector(problem.n(), seed);
    const Eigen::VectorXd x = analyzeFactorizeSolve(*solver, problem.csc(), b);
    EXPECT_LT(relativeError(x, problem.dense.llt().solve(b)), 1e-10);
  }
}

TEST_P(EverySolver, SolvesInPlaceWhenRightHandSideAndSolutionAlias) {
  const BlockProblem problem = testing::randomBlockSpd(20, 3, 21);
  auto solver = GetParam().make();
  const Csc csc = problem.csc();
  ASSERT_TRUE(solver->analyze(csc.view()).ok());
  ASSERT_TRUE(solver->factorize(csc.view()).ok());
  const Eigen::VectorXd b = testing::randomVector(problem.n(), 22);
  Eigen::VectorXd in_place = b;
  ASSERT_TRUE(solver->solve(in_place.data(), in_place.data()).ok());
  EXPECT_LT(relativeError(in_place, problem.dense.llt().solve(b)), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Solvers, EverySolver, ::testing::ValuesIn(testing::allSolverCases()),
                         [](const auto& info) { return info.param.label; });

TEST(CholmodSolver, ReportsFactorStatisticsAndTheOrderingItUsed) {
  const BlockProblem problem = testing::randomBlockSpd(60, 6, 31);
  const Csc csc = problem.csc();
  CholmodOptions amd_only;
  amd_only.ordering = CholmodOrdering::kAmd;
  CholmodSolver automatic;
  CholmodSolver amd(amd_only);
  EXPECT_EQ(automatic.lastFactorNnz(), 0.0);
  EXPECT_EQ(automatic.orderingUsed(), "");
  for (CholmodSolver* solver : {&automatic, &amd}) {
    ASSERT_TRUE(solver->analyze(csc.view()).ok());
    // L holds at least the lower triangle of A's pattern, at most a dense triangle.
    EXPECT_GE(solver->lastFactorNnz(), static_cast<double>(csc.view().nnz()));
    EXPECT_LE(solver->lastFactorNnz(), 0.5 * problem.n() * (problem.n() + 1.0));
    EXPECT_GT(solver->factorFlops(), solver->lastFactorNnz());
    EXPECT_FALSE(solver->orderingUsed().empty());
  }
  EXPECT_EQ(amd.orderingUsed(), "amd");
  const double analysed_nnz = automatic.lastFactorNnz();
  ASSERT_TRUE(automatic.factorize(problem.shifted(1.0).view()).ok());
  EXPECT_EQ(automatic.lastFactorNnz(), analysed_nnz) << "a factorize must not redo the analysis";
  EXPECT_TRUE(automatic.name() == "cholmod-supernodal" || automatic.name() == "cholmod-simplicial") << automatic.name();
  CholmodOptions simplicial;
  simplicial.factorization = CholmodFactorization::kSimplicial;
  EXPECT_EQ(CholmodSolver(simplicial).name(), "cholmod-simplicial");
  CholmodOptions supernodal;
  supernodal.factorization = CholmodFactorization::kSupernodal;
  EXPECT_EQ(CholmodSolver(supernodal).name(), "cholmod-supernodal");
  EXPECT_EQ(CholmodSolver().name(), "cholmod-auto");  // not analysed yet
}

TEST(CholmodSolver, AutoPicksSimplicialForAVerySparseFactorAndSupernodalForADenseOne) {
  // A chain of 6×6 blocks (each block coupled to the next only): L has the pattern of A (no fill), few flops
  // per nonzero, below CHOLMOD's supernodal switch (40).
  const BlockProblem chain = testing::randomBlockSpd(150, 6, 5, 1e-2, /*loop_closures=*/false);
  // A dense SPD matrix of order 300: ≈ n/3 = 100 flops per nonzero of L.
  BlockProblem dense;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd a(300, 300);
  for (int i = 0; i < a.size(); ++i) a.data()[i] = normal(rng);
  dense.dense = a.transpose() * a + Eigen::MatrixXd::Identity(300, 300);
  dense.pattern = Eigen::MatrixXi::Ones(300, 300);
  CholmodSolver automatic;
  ASSERT_TRUE(automatic.analyze(chain.csc().view()).ok());
  EXPECT_EQ(automatic.name(), "cholmod-simplicial") << automatic.factorFlops() / automatic.lastFactorNnz() << " flops per nonzero";
  ASSERT_TRUE(automatic.factorize(chain.csc().view()).ok());
  ASSERT_TRUE(automatic.analyze(dense.csc().view()).ok());
  EXPECT_EQ(automatic.name(), "cholmod-supernodal") << automatic.factorFlops() / automatic.lastFactorNnz() << " flops per nonzero";
  // The switch moved above the dense matrix's ≈ 100 flops per nonzero: simplicial there too.
  CholmodOptions high_switch;
  high_switch.supernodal_switch = 1000.0;
  CholmodSolver tuned(high_switch);
  ASSERT_TRUE(tuned.analyze(dense.csc().view()).ok());
  EXPECT_EQ(tuned.name(), "cholmod-simplicial");
}

}  // namespace
}  // namespace dualgraph
