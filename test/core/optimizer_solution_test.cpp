// SPDX-License-Identifier: MIT
// Optimizer (Levenberg–Marquardt and Gauss–Newton) with the dense test solver: solutions against a
// dense least-squares solve and known truths, χ² histories, robust kernels, the summary.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "dualgraph/core/optimizer.h"
#include "test/core/optimizer_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

class OptimizerAlgorithm : public ::testing::TestWithParam<Algorithm> {};

TEST_P(OptimizerAlgorithm, LinearProblemReachesTheDenseLeastSquaresSolution) {
  // Diagonal damping's first step stops 1e-4 short; either damping must end at the optimum to round-off.
  for (const auto& [seed, damping] : {std::pair{1u, LmDamping::kIdentity}, {2u, LmDamping::kIdentity},
                                      {3u, LmDamping::kIdentity}, {1u, LmDamping::kDiagonal},
                                      {2u, LmDamping::kDiagonal}, {3u, LmDamping::kDiagonal}}) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " damping " + lmDampingName(damping));
    Graph graph;
    buildLinearProblem(graph, seed);
    const auto expected = denseLeastSquares(graph);
    const double optimal_chi2 = chi2At(graph, expected);
    const Eigen::Vector2d fixed_before = pointOf(graph, 0);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    OptimizerParams params = paramsFor(GetParam());
    params.damping = damping;
    params.relative_decrease_stop = 1e-14;  // run to χ²'s round-off floor: this test is about the solution
    const SolverSummary summary = optimizer.optimize(params);
    EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
    EXPECT_TRUE(summary.usable());
    expectAtSolution(graph, expected, 1e-9);
    EXPECT_NEAR(summary.final_chi2, optimal_chi2, 1e-13 * optimal_chi2);
    EXPECT_EQ(pointOf(graph, 0), fixed_before) << "a fixed vertex never moves";
    EXPECT_NEAR(summary.final_chi2, graph.chi2(), 1e-12 * (1 + graph.chi2()));
    EXPECT_LE(summary.final_chi2, summary.initial_chi2);
    if (GetParam() == Algorithm::kGaussNewton) {
      EXPECT_LE(summary.iterations, 3) << "one step solves a linear problem";
    }
    expectCleanStacks(graph);
  }
}

TEST_P(OptimizerAlgorithm, LinearProblemsReportConvergedOnceChi2IsAtItsRoundOffFloor) {
  // With almost no damping the first step solves a linear problem; χ² then has nothing left to
  // lose but round-off, so the next trial may well be rejected. That is convergence (as GN
  // reports it), not "no decreasing step", and needs no further damping increases.
  for (unsigned seed = 100; seed < 130; ++seed) {
    Graph graph;
    buildLinearProblem(graph, seed);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    OptimizerParams params = paramsFor(GetParam());
    params.initial_lambda = 1e-12;
    const SolverSummary summary = optimizer.optimize(params);
    EXPECT_EQ(summary.termination, TerminationReason::kConverged)
        << "seed " << seed << ": " << terminationReasonName(summary.termination) << " " << summary.message;
    EXPECT_LE(summary.iterations, 3) << "seed " << seed;
    EXPECT_LE(summary.factorizations, summary.iterations + 1) << "seed " << seed;
  }
}

TEST_P(OptimizerAlgorithm, DisconnectedComponentsAreEachSolved) {
  Graph graph;
  std::mt19937 rng(4);
  std::normal_distribution<double> normal;
  // Component A anchored by a prior, component B by a fixed vertex; no edge between them.
  for (int id : {0, 1, 2, 3}) addPoint(graph, id, {normal(rng), normal(rng)});
  for (int id : {10, 11, 12, 13}) addPoint(graph, id, {normal(rng), normal(rng)}, id == 12);
  addEdge<EdgePoint2Prior>(graph, {1}, {1, 1});
  addEdge<EdgePoint2Relative>(graph, {0, 1}, {1, 0});
  addEdge<EdgePoint2Relative>(graph, {2, 1}, {0, 1});
  addEdge<EdgePoint2Relative>(graph, {3, 2}, {-1, 0.5});
  addEdge<EdgePoint2Relative>(graph, {3, 0}, {0.2, -1}, testing::randomInformation<2>(rng));
  addEdge<EdgePoint2Relative>(graph, {10, 11}, {2, 0});
  addEdge<EdgePoint2Relative>(graph, {12, 11}, {0, 2});
  addEdge<EdgePoint2Relative>(graph, {13, 12}, {1, 1}, testing::randomInformation<2>(rng));
  addEdge<EdgePoint2Relative>(graph, {10, 13}, {1, 1});
  const auto expected = denseLeastSquares(graph);
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(paramsFor(GetParam()));
  EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
  expectAtSolution(graph, expected, 1e-9);
  EXPECT_EQ(summary.vertices, 7);
  EXPECT_EQ(summary.dimension, 14);
}

TEST_P(OptimizerAlgorithm, NonlinearRangeProblemConvergesToTheTruth) {
  Graph graph;
  const RangeProblem problem = buildRangeProblem(graph, 0.4, 5);
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  std::vector<IterationSummary> history;
  OptimizerParams params = paramsFor(GetParam());
  params.callback = [&history](const IterationSummary& it) { history.push_back(it); };
  const SolverSummary summary = optimizer.optimize(params);
  EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
  EXPECT_GT(summary.initial_chi2, 1e-2);
  EXPECT_LT(summary.final_chi2, 1e-20);
  for (int id : {4, 5, 6}) {
    EXPECT_LT((pointOf(graph, id) - problem.truth.at(id)).norm(), 1e-9) << "vertex " << id;
  }
  ASSERT_EQ(history.size(), static_cast<size_t>(summary.iterations));
  for (size_t k = 0; k < history.size(); ++k) EXPECT_EQ(history[k].iteration, static_cast<int>(k + 1));
  EXPECT_EQ(history.back().chi2, summary.final_chi2);
  EXPECT_GE(summary.factorizations, summary.iterations);
  expectCleanStacks(graph);
}

class LmDampingKind : public ::testing::TestWithParam<LmDamping> {};

TEST_P(LmDampingKind, LevenbergMarquardtChi2DecreasesMonotonically) {
  for (unsigned seed : {6u, 7u, 8u, 9u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Graph graph;
    buildRangeProblem(graph, 1.5, seed);  // far from the truth: some steps are rejected
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    std::vector<IterationSummary> history;
    OptimizerParams params;
    params.damping = GetParam();
    params.callback = [&history](const IterationSummary& it) { history.push_back(it); };
    const SolverSummary summary = optimizer.optimize(params);
    EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination);
    ASSERT_FALSE(history.empty());
    double previous = summary.initial_chi2;
    for (const IterationSummary& it : history) {
      EXPECT_LE(it.chi2, previous) << "iteration " << it.iteration;
      EXPECT_GE(it.trials, 1);
      EXPECT_GT(it.lambda, 0.0);
      previous = it.chi2;
    }
    EXPECT_EQ(summary.final_chi2, previous);
    EXPECT_NEAR(summary.final_chi2, graph.chi2(), 1e-12 * (1 + summary.final_chi2));
    expectCleanStacks(graph);
  }
}

// Both dampings reach the same optimum; diagonal damping starts at λ₀ = 1e-4 (Ceres' 1 / 1e4).
TEST_P(LmDampingKind, ReachesTheSameOptimumAsTheOtherDamping) {
  Graph reference;
  buildRangeProblem(reference, 0.8, 11);
  OptimizerParams params;
  params.damping = GetParam() == LmDamping::kIdentity ? LmDamping::kDiagonal : LmDamping::kIdentity;
  ASSERT_EQ(Optimizer(reference, std::make_unique<DenseTestSolver>()).optimize(params).termination,
            TerminationReason::kConverged);
  Graph graph;
  buildRangeProblem(graph, 0.8, 11);
  params.damping = GetParam();
  std::vector<IterationSummary> history;
  params.callback = [&history](const IterationSummary& it) { history.push_back(it); };
  const SolverSummary summary = Optimizer(graph, std::make_unique<DenseTestSolver>()).optimize(params);
  EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
  for (const auto& [id, v] : graph.vertices()) {
    EXPECT_LT((pointOf(graph, id) - pointOf(reference, id)).norm(), 1e-7) << "vertex " << id;
  }
  ASSERT_FALSE(history.empty());
  if (GetParam() == LmDamping::kDiagonal) {
    EXPECT_EQ(history[0].lambda, 1e-4);
  }
}

INSTANTIATE_TEST_SUITE_P(IdentityAndDiagonal, LmDampingKind,
                         ::testing::Values(LmDamping::kIdentity, LmDamping::kDiagonal),
                         [](const ::testing::TestParamInfo<LmDamping>& info) {
                           return std::string(lmDampingName(info.param));
                         });

INSTANTIATE_TEST_SUITE_P(LmAndGn, OptimizerAlgorithm,
                         ::testing::Values(Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton),
                         [](const ::testing::TestParamInfo<Algorithm>& info) {
                           return std::string(info.param == Algorithm::kGaussNewton ? "GaussNewton"
                                                                                    : "LevenbergMarquardt");
                         });


TEST(Optimizer, InitialLambdaIsUsedForTheFirstTrialOrDerivedFromTau) {
  for (double initial_lambda : {0.0, 0.125}) {
    Graph graph;
    buildRangeProblem(graph, 0.4, 5);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    std::vector<IterationSummary> history;
    OptimizerParams params;
    params.initial_lambda = initial_lambda;
    params.tau = 1e-3;
    params.callback = [&history](const IterationSummary& it) { history.push_back(it); };
    (void)optimizer.optimize(params);
    ASSERT_FALSE(history.empty());
    if (initial_lambda > 0.0) {
      EXPECT_EQ(history[0].lambda, initial_lambda);
    } else {
      // τ · max diag(H) at the start; H's diagonal is recomputed here from a fresh system.
      Graph fresh;
      buildRangeProblem(fresh, 0.4, 5);
      SparseSystem system;
      ASSERT_TRUE(system.build(fresh).ok());
      for (const auto& edge : fresh.edges()) edge->linearize();
      system.assemble();
      EXPECT_NEAR(history[0].lambda, 1e-3 * system.maxDiagonal(), 1e-12);
    }
  }
}

TEST(Optimizer, RobustKernelDownweightsAnOutlierToTheHuberOptimum) {
  Graph graph;
  addPoint(graph, 0, {3, 2});
  auto huber = *makeRobustKernel("huber:1");
  for (const Eigen::Vector2d& z : {Eigen::Vector2d(0, 0), Eigen::Vector2d(0, 0), Eigen::Vector2d(10, 0)}) {
    addEdge<EdgePoint2Prior>(graph, {0}, z)->setRobustKernel(huber);
  }
  // Σρ = 2|x|² + 2|x − (10, 0)| − 1 near the optimum: gradient 4x − 2 = 0 at x = (0.5, 0).
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  OptimizerParams params;
  params.relative_decrease_stop = 1e-15;
  const SolverSummary summary = optimizer.optimize(params);
  EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination);
  EXPECT_LT((pointOf(graph, 0) - Eigen::Vector2d(0.5, 0)).norm(), 1e-7) << pointOf(graph, 0).transpose();
  EXPECT_NEAR(summary.final_chi2, 18.5, 1e-10);
  EXPECT_NEAR(summary.final_chi2, graph.chi2(/*robust=*/true), 1e-12);
}

TEST(Optimizer, FinalChi2IsTheRobustChi2OfTheFinalEstimateAndStoredErrorsAreCurrent) {
  for (Algorithm algorithm : {Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton}) {
    for (int max_iterations : {1, 3, 100}) {
      Graph graph;
      testing::buildRandomPointGraph(graph, 10, *makeRobustKernel("huber:0.5"));
      Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
      OptimizerParams params = paramsFor(algorithm);
      params.max_iterations = max_iterations;
      const SolverSummary summary = optimizer.optimize(params);
      std::vector<Eigen::VectorXd> stored;
      for (const auto& edge : graph.edges()) {
        stored.emplace_back(Eigen::Map<const Eigen::VectorXd>(edge->errorData(), edge->errorDim()));
      }
      const double recomputed = graph.chi2(/*robust=*/true);
      EXPECT_NEAR(summary.final_chi2, recomputed, 1e-12 * recomputed);
      for (size_t k = 0; k < stored.size(); ++k) {
        const Eigen::Map<const Eigen::VectorXd> now(graph.edges()[k]->errorData(), graph.edges()[k]->errorDim());
        EXPECT_EQ(stored[k], now) << "edge " << k << " held the error of a rejected trial";
      }
      expectCleanStacks(graph);
    }
  }
}

TEST(Optimizer, StartingAtAZeroResidualOptimumDoesNotMove) {
  for (Algorithm algorithm : {Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton}) {
    Graph graph;
    buildRangeProblem(graph, 0.0, 1);  // starts exactly at the truth
    const auto before = snapshot(graph);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    const SolverSummary summary = optimizer.optimize(paramsFor(algorithm));
    EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
    EXPECT_EQ(summary.iterations, 1);
    EXPECT_LT(summary.final_chi2, 1e-25);
    for (const auto& [id, p] : before) EXPECT_LT((pointOf(graph, id) - p).norm(), 1e-12);
    expectCleanStacks(graph);
  }
}

TEST(Optimizer, SummaryDescribesTheSystem) {
  Graph graph;
  testing::buildRandomPointGraph(graph, 12);
  addPoint(graph, 99, {0, 0});  // isolated: not counted
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.vertices, testing::kRandomGraphPoints - 2);
  EXPECT_EQ(summary.edges, activeEdgeCount(graph));
  EXPECT_EQ(summary.dimension, 2 * summary.vertices);
  EXPECT_EQ(summary.nonzeros, optimizer.system().matrix().nnz());
  EXPECT_EQ(summary.linear_solver, "dense-test");
  EXPECT_TRUE(summary.structure_rebuilt);
  EXPECT_GE(summary.total_ms, 0.0);
  EXPECT_GE(summary.factorizations, summary.iterations);
  EXPECT_EQ(&optimizer.linearSolver(), &optimizer.linearSolver());
  EXPECT_EQ(optimizer.linearSolver().name(), "dense-test");
}

TEST(Optimizer, FactorizeAtCurrentEstimateFactorsTheUndampedHessian) {
  Graph graph;
  buildLinearProblem(graph, 4);
  const auto before = snapshot(graph);
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  ASSERT_TRUE(optimizer.factorizeAtCurrentEstimate().ok());
  EXPECT_EQ(snapshot(graph), before);
  // The factor solves H x = b with the undamped H of the current estimate: one GN step to the optimum.
  const SparseSystem& system = optimizer.system();
  Eigen::VectorXd step(system.dim());
  ASSERT_TRUE(optimizer.linearSolver().solve(system.rhs().data(), step.data()).ok());
  const Eigen::MatrixXd H = testing::denseFromUpper(system.matrix());
  EXPECT_LT((H * step - system.rhs()).cwiseAbs().maxCoeff(), 1e-9 * (1 + system.rhs().cwiseAbs().maxCoeff()));
  const auto expected = denseLeastSquares(graph);
  system.applyUpdate(step.data());
  expectAtSolution(graph, expected, 1e-9);

  Graph all_fixed;
  addPoint(all_fixed, 0, {0, 0}, true);
  Optimizer nothing(all_fixed, std::make_unique<DenseTestSolver>());
  EXPECT_EQ(nothing.factorizeAtCurrentEstimate().code(), StatusCode::kFailedPrecondition);

  Graph gauge;
  addPoint(gauge, 0, {0, 0});
  addPoint(gauge, 1, {1, 0});
  addEdge<EdgePoint2Relative>(gauge, {0, 1}, {1, 0});
  Optimizer singular(gauge, std::make_unique<DenseTestSolver>());
  EXPECT_EQ(singular.factorizeAtCurrentEstimate().code(), StatusCode::kNotPositiveDefinite);
}

}  // namespace
}  // namespace dualgraph
