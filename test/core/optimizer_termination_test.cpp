// SPDX-License-Identifier: MIT
// Optimizer: every termination reason (invalid input, nothing to optimise, gauge freedom, solver
// failures, divergent steps, budgets) leaves a finite, consistent estimate; the structure cache.
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

TEST(Optimizer, NonFiniteErrorAtTheStartIsInvalidInputAndLeavesTheEstimate) {
  for (Algorithm algorithm : {Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton}) {
    Graph graph;
    addPoint(graph, 0, {1, 2});
    addPoint(graph, 1, {2, 2});
    addEdge<EdgePoint2Relative>(graph, {0, 1}, {1, 0});
    addEdge<EdgePoint2Prior>(graph, {1}, {kNaN, 0.0})->setSourceLine(7);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    const SolverSummary summary = optimizer.optimize(paramsFor(algorithm));
    EXPECT_EQ(summary.termination, TerminationReason::kInvalidInput);
    EXPECT_FALSE(summary.usable());
    EXPECT_TRUE(contains(summary.message, "vertices 1")) << "names the edge";
    EXPECT_TRUE(contains(summary.message, "line 7"));
    EXPECT_EQ(summary.iterations, 0);
    EXPECT_EQ(summary.factorizations, 0);
    EXPECT_EQ(pointOf(graph, 0), Eigen::Vector2d(1, 2));
    EXPECT_EQ(pointOf(graph, 1), Eigen::Vector2d(2, 2));
  }
}

TEST(Optimizer, AllVerticesFixedIsNothingToOptimize) {
  Graph graph;
  addPoint(graph, 0, {0, 0}, true);
  addPoint(graph, 1, {1, 0}, true);
  addPoint(graph, 2, {5, 5});  // free but attached to nothing
  addEdge<EdgePoint2Relative>(graph, {0, 1}, {2, 0});
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.termination, TerminationReason::kNothingToOptimize);
  EXPECT_FALSE(summary.usable());
  EXPECT_DOUBLE_EQ(summary.initial_chi2, 1.0);
  EXPECT_DOUBLE_EQ(summary.final_chi2, 1.0);
  EXPECT_EQ(summary.dimension, 0);
  EXPECT_EQ(pointOf(graph, 2), Eigen::Vector2d(5, 5));

  Graph empty;
  Optimizer on_empty(empty, std::make_unique<DenseTestSolver>());
  EXPECT_EQ(on_empty.optimize(OptimizerParams{}).termination, TerminationReason::kNothingToOptimize);
}

TEST(Optimizer, GaugeFreedomStopsGaussNewtonButNotLevenbergMarquardt) {
  auto build = [](Graph& graph) {
    addPoint(graph, 0, {0, 0});
    addPoint(graph, 1, {1, 0.5});
    addPoint(graph, 2, {0.5, 2});
    addEdge<EdgePoint2Relative>(graph, {0, 1}, {1, 0});
    addEdge<EdgePoint2Relative>(graph, {1, 2}, {0, 1});
  };
  {
    Graph graph;
    build(graph);
    const auto before = snapshot(graph);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    const SolverSummary summary = optimizer.optimize(paramsFor(Algorithm::kGaussNewton));
    EXPECT_EQ(summary.termination, TerminationReason::kNotPositiveDefinite) << summary.message;
    EXPECT_FALSE(summary.usable());
    EXPECT_EQ(snapshot(graph), before) << "the estimate is untouched";
    EXPECT_EQ(summary.final_chi2, summary.initial_chi2);
  }
  {
    Graph graph;
    build(graph);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    const SolverSummary summary = optimizer.optimize(paramsFor(Algorithm::kLevenbergMarquardt));
    EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination);
    EXPECT_LT(summary.final_chi2, 1e-12);
    EXPECT_LT((pointOf(graph, 1) - pointOf(graph, 0) - Eigen::Vector2d(1, 0)).norm(), 1e-6);
    EXPECT_LT((pointOf(graph, 2) - pointOf(graph, 1) - Eigen::Vector2d(0, 1)).norm(), 1e-6);
    EXPECT_TRUE(std::isfinite(pointOf(graph, 0).norm()));
  }
}

TEST(Optimizer, DisconnectedUnanchoredComponentIsStillSolvedByLevenbergMarquardt) {
  Graph graph;
  addPoint(graph, 0, {0, 0}, true);
  addPoint(graph, 1, {1, 0.5});
  addPoint(graph, 2, {5, 5});  // second component, anchored by nothing
  addPoint(graph, 3, {6, 5});
  addEdge<EdgePoint2Relative>(graph, {0, 1}, {1, 0});
  addEdge<EdgePoint2Relative>(graph, {2, 3}, {1, 1});
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination);
  EXPECT_LT((pointOf(graph, 1) - Eigen::Vector2d(1, 0)).norm(), 1e-6);
  EXPECT_LT((pointOf(graph, 3) - pointOf(graph, 2) - Eigen::Vector2d(1, 1)).norm(), 1e-6);
}

TEST(Optimizer, FailingSolverIsNotPositiveDefiniteAndLeavesTheEstimate) {
  for (Algorithm algorithm : {Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton}) {
    Graph graph;
    addPoint(graph, 0, {3, 4});
    addEdge<EdgePoint2Prior>(graph, {0}, {0, 0});
    Optimizer optimizer(graph, std::make_unique<FailingSolver>());
    const SolverSummary summary = optimizer.optimize(paramsFor(algorithm));
    EXPECT_EQ(summary.termination, TerminationReason::kNotPositiveDefinite);
    EXPECT_TRUE(contains(summary.message, "always fails"));
    EXPECT_EQ(summary.factorizations, algorithm == Algorithm::kGaussNewton ? 1 : OptimizerParams{}.max_trials)
        << "LM raises the damping max_trials times";
    EXPECT_EQ(pointOf(graph, 0), Eigen::Vector2d(3, 4));
    EXPECT_DOUBLE_EQ(summary.final_chi2, 25.0);
    EXPECT_EQ(summary.linear_solver, "failing");
    expectCleanStacks(graph);
  }
}

/// e = p − z while |p| < 2; NaN beyond (a model that breaks down away from the start).
class EdgeFragilePrior : public EdgePoint2Prior {
 public:
  void computeError() override {
    EdgePoint2Prior::computeError();
    if (vertexAs<0>()->estimate().norm() >= 2.0) error_.setConstant(kNaN);
  }
};

TEST(Optimizer, DivergentStepIsRejectedByLevenbergMarquardtAndTheEstimateStaysFinite) {
  Graph graph;
  addPoint(graph, 0, {1.9, 0});
  addEdge<EdgeFragilePrior>(graph, {0}, {5, 0});
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  std::vector<IterationSummary> history;
  OptimizerParams params;
  params.initial_lambda = 1e-9;  // the first, nearly undamped step lands at |p| = 5: NaN
  params.callback = [&history](const IterationSummary& it) { history.push_back(it); };
  const SolverSummary summary = optimizer.optimize(params);
  EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination);
  EXPECT_TRUE(std::isfinite(summary.final_chi2));
  EXPECT_LT(summary.final_chi2, summary.initial_chi2);
  EXPECT_TRUE(pointOf(graph, 0).allFinite());
  EXPECT_LT(pointOf(graph, 0).norm(), 2.0);
  EXPECT_GT(pointOf(graph, 0).x(), 1.9) << "it still moved towards the measurement";
  ASSERT_FALSE(history.empty());
  EXPECT_GT(history[0].trials, 1) << "the NaN trial was rejected and retried with more damping";
  EXPECT_TRUE(history[0].step_accepted);
  EXPECT_TRUE(std::isfinite(graph.chi2()));
  expectCleanStacks(graph);
}

TEST(Optimizer, DivergentGaussNewtonStepKeepsThePreviousEstimate) {
  Graph graph;
  addPoint(graph, 0, {1.9, 0});
  addEdge<EdgeFragilePrior>(graph, {0}, {5, 0});
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(paramsFor(Algorithm::kGaussNewton));
  EXPECT_EQ(summary.termination, TerminationReason::kNoDecrease) << summary.message;
  EXPECT_EQ(pointOf(graph, 0), Eigen::Vector2d(1.9, 0));
  EXPECT_DOUBLE_EQ(summary.final_chi2, summary.initial_chi2);
  EXPECT_TRUE(std::isfinite(graph.edges()[0]->chi2())) << "stored errors are those of the kept estimate";
  expectCleanStacks(graph);
}

class OptimizerWithKernel : public ::testing::TestWithParam<const char*> {};

TEST_P(OptimizerWithKernel, InfiniteErrorAtTheStartIsInvalidInputWhateverTheKernel) {
  // Tukey's ρ is flat at δ²/3 for any large s, including s = ∞: the robust χ² alone would hide it.
  for (Algorithm algorithm : {Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton}) {
    Graph graph;
    addPoint(graph, 0, {0, 0}, true);
    addPoint(graph, 1, {1, 2});
    addEdge<EdgePoint2Prior>(graph, {1}, {0, 0});
    addEdge<EdgePoint2Range>(graph, {0, 1}, -std::numeric_limits<double>::infinity())
        ->setRobustKernel(*makeRobustKernel(GetParam()));
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    const SolverSummary summary = optimizer.optimize(paramsFor(algorithm));
    EXPECT_EQ(summary.termination, TerminationReason::kInvalidInput)
        << terminationReasonName(summary.termination) << ": " << summary.message;
    EXPECT_TRUE(contains(summary.message, "vertices 0 1"));
    EXPECT_FALSE(std::isfinite(summary.initial_chi2));
    EXPECT_EQ(pointOf(graph, 1), Eigen::Vector2d(1, 2));
  }
}

INSTANTIATE_TEST_SUITE_P(Kernels, OptimizerWithKernel, ::testing::Values("huber:1", "cauchy:1", "tukey:1", "dcs:1"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           return std::string(info.param).substr(0, std::string(info.param).find(':'));
                         });

/// e = |p_j − p_i| − z while |p_j| < 2; +∞ beyond (overflow rather than NaN). Analytic
/// Jacobians, so that linearising just inside the boundary stays finite.
class EdgeOverflowingRange : public EdgePoint2Range {
 public:
  void computeError() override {
    EdgePoint2Range::computeError();
    if (vertexAs<1>()->estimate().norm() >= 2.0) error_[0] = std::numeric_limits<double>::infinity();
  }

 protected:
  void linearizeOplus() override {
    const Eigen::RowVector2d u = (vertexAs<1>()->estimate() - vertexAs<0>()->estimate()).normalized().transpose();
    jacobianOplus<0>() = -u;
    jacobianOplus<1>() = u;
  }
};

TEST(Optimizer, StepToAnInfiniteErrorIsRejectedEvenUnderTukey) {
  // A strong prior pulls the point to (5, 0); a Tukey-robust range holds it and overflows beyond
  // |p| = 2. Tukey maps s = ∞ to a finite δ²/3, so only the plain χ² shows the step is divergent.
  Graph graph;
  addPoint(graph, 0, {0, 0}, true);
  addPoint(graph, 1, {1.9, 0});
  addEdge<EdgePoint2Prior>(graph, {1}, {5, 0});
  addEdge<EdgeOverflowingRange>(graph, {0, 1}, 1.9)->setRobustKernel(*makeRobustKernel("tukey:1"));
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  OptimizerParams params;
  params.initial_lambda = 1e-9;  // the first step lands at |p| ≈ 5
  const SolverSummary summary = optimizer.optimize(params);
  EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination) << ": " << summary.message;
  EXPECT_LT(pointOf(graph, 1).norm(), 2.0) << pointOf(graph, 1).transpose();
  EXPECT_GT(pointOf(graph, 1).x(), 1.9);
  for (const auto& edge : graph.edges()) EXPECT_TRUE(std::isfinite(edge->chi2()));
  EXPECT_TRUE(std::isfinite(summary.final_chi2));
  EXPECT_LT(summary.final_chi2, summary.initial_chi2);
  expectCleanStacks(graph);
}

TEST(Optimizer, TinyTimeBudgetStopsWithTimeBudget) {
  for (Algorithm algorithm : {Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton}) {
    Graph graph;
    testing::buildRandomPointGraph(graph, 5);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    OptimizerParams params = paramsFor(algorithm);
    params.max_iterations = 1000;
    params.relative_decrease_stop = 0.0;
    params.step_norm_stop = 0.0;
    params.time_budget_ms = 1e-6;
    const SolverSummary summary = optimizer.optimize(params);
    EXPECT_EQ(summary.termination, TerminationReason::kTimeBudget) << terminationReasonName(summary.termination);
    EXPECT_TRUE(summary.usable());
    EXPECT_LE(summary.iterations, 1);
    EXPECT_LE(summary.final_chi2, summary.initial_chi2);
    EXPECT_NEAR(summary.final_chi2, graph.chi2(), 1e-9 * summary.final_chi2);
    expectCleanStacks(graph);
  }
}

TEST(Optimizer, ZeroMaxIterationsLeavesTheEstimate) {
  for (Algorithm algorithm : {Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton}) {
    Graph graph;
    buildLinearProblem(graph, 3);
    const auto before = snapshot(graph);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    OptimizerParams params = paramsFor(algorithm);
    params.max_iterations = 0;
    const SolverSummary summary = optimizer.optimize(params);
    EXPECT_EQ(summary.termination, TerminationReason::kMaxIterations);
    EXPECT_EQ(summary.iterations, 0);
    EXPECT_EQ(summary.factorizations, 0);
    EXPECT_EQ(summary.final_chi2, summary.initial_chi2);
    EXPECT_EQ(snapshot(graph), before);
  }
}

TEST(Optimizer, IterationCapIsReportedAsMaxIterations) {
  for (Algorithm algorithm : {Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton}) {
    Graph graph;
    buildRangeProblem(graph, 0.8, 11);
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    OptimizerParams params = paramsFor(algorithm);
    params.max_iterations = 2;
    const SolverSummary summary = optimizer.optimize(params);
    EXPECT_EQ(summary.termination, TerminationReason::kMaxIterations) << terminationReasonName(summary.termination);
    EXPECT_TRUE(summary.usable());
    EXPECT_EQ(summary.iterations, 2);
    EXPECT_LT(summary.final_chi2, summary.initial_chi2);
  }
}

TEST(Optimizer, StructureIsCachedUntilTheGraphStructureChanges) {
  Graph graph;
  testing::buildRandomPointGraph(graph, 7);
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  OptimizerParams params;
  params.max_iterations = 2;
  EXPECT_TRUE(optimizer.optimize(params).structure_rebuilt) << "first call";
  EXPECT_FALSE(optimizer.optimize(params).structure_rebuilt) << "same graph";
  graph.vertexAs<VertexPoint2>(3)->setEstimate({1, 1});
  EXPECT_FALSE(optimizer.optimize(params).structure_rebuilt) << "values are not structure";

  graph.vertex(5)->setFixed(true);  // directly on the vertex, bypassing Graph::setFixed
  SolverSummary summary = optimizer.optimize(params);
  EXPECT_TRUE(summary.structure_rebuilt) << "vertex->setFixed(true)";
  EXPECT_EQ(summary.vertices, testing::kRandomGraphPoints - 3);
  EXPECT_FALSE(optimizer.optimize(params).structure_rebuilt);
  graph.vertex(5)->setFixed(false);
  EXPECT_TRUE(optimizer.optimize(params).structure_rebuilt) << "vertex->setFixed(false)";

  ASSERT_TRUE(graph.setFixed(6, true).ok());
  EXPECT_TRUE(optimizer.optimize(params).structure_rebuilt) << "Graph::setFixed";

  addEdge<EdgePoint2Relative>(graph, {1, 2}, {0.5, 0.5});
  summary = optimizer.optimize(params);
  EXPECT_TRUE(summary.structure_rebuilt) << "addEdge";
  EXPECT_EQ(summary.edges, activeEdgeCount(graph));
  EXPECT_FALSE(optimizer.optimize(params).structure_rebuilt);

  ASSERT_TRUE(graph.removeEdge(graph.edges().back().get()).ok());
  EXPECT_TRUE(optimizer.optimize(params).structure_rebuilt) << "removeEdge";
  ASSERT_TRUE(graph.removeVertex(8).ok());
  summary = optimizer.optimize(params);
  EXPECT_TRUE(summary.structure_rebuilt) << "removeVertex";
  EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination);
  expectCleanStacks(graph);
}

TEST(Optimizer, SymbolicAnalysisRunsOncePerStructure) {
  Graph graph;
  testing::buildRandomPointGraph(graph, 13);
  ScriptedSolver::Counts counts;
  Optimizer optimizer(graph, std::make_unique<ScriptedSolver>(ScriptedSolver::Script{}, &counts));
  OptimizerParams params;
  params.max_iterations = 3;
  (void)optimizer.optimize(params);
  (void)optimizer.optimize(params);
  EXPECT_EQ(counts.analyze, 1);
  EXPECT_GE(counts.factorize, 2);
  addEdge<EdgePoint2Relative>(graph, {3, 9}, {1, 1});
  (void)optimizer.optimize(params);
  EXPECT_EQ(counts.analyze, 2);
}

TEST(Optimizer, AnalyzeFailureIsALinearSolverFailureAndIsRetriedNextCall) {
  Graph graph;
  buildLinearProblem(graph, 1);
  const auto before = snapshot(graph);
  ScriptedSolver::Counts counts;
  ScriptedSolver::Script script;
  script.analyze_status = Status(StatusCode::kIoError, "scripted analyze failure");
  Optimizer optimizer(graph, std::make_unique<ScriptedSolver>(script, &counts));
  SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.termination, TerminationReason::kLinearSolverFailure);
  EXPECT_TRUE(contains(summary.message, "scripted analyze failure"));
  EXPECT_EQ(snapshot(graph), before);
  summary = optimizer.optimize(OptimizerParams{});
  EXPECT_TRUE(summary.structure_rebuilt) << "a failed build is not cached";
  EXPECT_EQ(counts.analyze, 2);
}

TEST(Optimizer, SolveFailureOtherThanNotPositiveDefiniteIsALinearSolverFailure) {
  for (Algorithm algorithm : {Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton}) {
    Graph graph;
    buildLinearProblem(graph, 2);
    const auto before = snapshot(graph);
    ScriptedSolver::Counts counts;
    ScriptedSolver::Script script;
    script.solve_failure = StatusCode::kIoError;
    Optimizer optimizer(graph, std::make_unique<ScriptedSolver>(script, &counts));
    const SolverSummary summary = optimizer.optimize(paramsFor(algorithm));
    EXPECT_EQ(summary.termination, TerminationReason::kLinearSolverFailure);
    EXPECT_FALSE(summary.usable());
    EXPECT_TRUE(contains(summary.message, "scripted solve failure"));
    EXPECT_EQ(counts.solve, 1) << "no retry for a failure damping cannot fix";
    EXPECT_EQ(snapshot(graph), before);
    expectCleanStacks(graph);
  }
}

TEST(Optimizer, NonFiniteStepIsRetriedWithMoreDampingByLevenbergMarquardt) {
  Graph graph;
  buildLinearProblem(graph, 3);
  const auto expected = denseLeastSquares(graph);
  const double optimal_chi2 = chi2At(graph, expected);
  ScriptedSolver::Counts counts;
  ScriptedSolver::Script script;
  script.nan_solves = 2;
  Optimizer optimizer(graph, std::make_unique<ScriptedSolver>(script, &counts));
  std::vector<IterationSummary> history;
  OptimizerParams params;
  params.callback = [&history](const IterationSummary& it) { history.push_back(it); };
  const SolverSummary summary = optimizer.optimize(params);
  EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
  ASSERT_FALSE(history.empty());
  EXPECT_EQ(history[0].trials, 3) << "two NaN steps, each retried with more damping";
  EXPECT_TRUE(history[0].step_accepted);
  // After the retries λ is larger, so the last accepted step is damped; χ² reaches the optimum to
  // round-off, and the estimate lies within the region where χ² is flat to round-off
  // (√(ε χ² / σ_min) ≈ 1e-8 here; χ²-based acceptance cannot resolve closer).
  EXPECT_NEAR(summary.final_chi2, optimal_chi2, 1e-13 * optimal_chi2);
  expectAtSolution(graph, expected, 1e-7);
  expectCleanStacks(graph);
}

TEST(Optimizer, NonFiniteStepStopsGaussNewtonAsNotPositiveDefinite) {
  Graph graph;
  buildLinearProblem(graph, 3);
  const auto before = snapshot(graph);
  ScriptedSolver::Counts counts;
  ScriptedSolver::Script script;
  script.nan_solves = 1;
  Optimizer optimizer(graph, std::make_unique<ScriptedSolver>(script, &counts));
  const SolverSummary summary = optimizer.optimize(paramsFor(Algorithm::kGaussNewton));
  EXPECT_EQ(summary.termination, TerminationReason::kNotPositiveDefinite);
  EXPECT_EQ(snapshot(graph), before);
}

TEST(Optimizer, NullLinearSolverIsAContractViolation) {
  Graph graph;
  EXPECT_THROW((void)Optimizer(graph, nullptr), ContractViolation);
}

TEST(TerminationReason, NamesAreDistinctAndUsableMeansAnOptimumOrABudget) {
  const TerminationReason all[] = {
      TerminationReason::kConverged,          TerminationReason::kMaxIterations,
      TerminationReason::kNoDecrease,         TerminationReason::kTimeBudget,
      TerminationReason::kNotPositiveDefinite, TerminationReason::kInvalidInput,
      TerminationReason::kNothingToOptimize,  TerminationReason::kLinearSolverFailure,
      TerminationReason::kNumericalFailure};
  std::set<std::string> names;
  for (TerminationReason reason : all) {
    names.insert(terminationReasonName(reason));
    EXPECT_STRNE(terminationReasonName(reason), "unknown");
    SolverSummary summary;
    summary.termination = reason;
    const bool usable = reason == TerminationReason::kConverged || reason == TerminationReason::kMaxIterations ||
                        reason == TerminationReason::kNoDecrease || reason == TerminationReason::kTimeBudget;
    EXPECT_EQ(summary.usable(), usable) << terminationReasonName(reason);
  }
  EXPECT_EQ(names.size(), std::size(all));
}

}  // namespace
}  // namespace dualgraph
