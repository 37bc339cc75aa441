// SPDX-License-Identifier: MIT
// The engine with types a user defines in their own file: registration and g2o I/O, the assembled
// normal equations against a dense JᵀWJ, and the optimiser's results and termination reasons.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <sstream>

#include "core/g2o_io.h"
#include "core/optimizer.h"
#include "test/core/dense_solver.h"
#include "test/core/user_types.h"

namespace dualgraph {
namespace {

using testing::DenseTestSolver;
using testing::EdgePoint2Prior;
using testing::EdgePoint2Range;
using testing::EdgePoint2Relative;
using testing::FailingSolver;
using testing::VertexPoint2;

TypeRegistry userRegistry() {
  TypeRegistry registry;
  EXPECT_TRUE(registry.registerVertex<VertexPoint2>("VERTEX_P2").ok());
  EXPECT_TRUE(registry.registerEdge<EdgePoint2Relative>("EDGE_P2_REL").ok());
  EXPECT_TRUE(registry.registerEdge<EdgePoint2Range>("EDGE_P2_RANGE").ok());
  EXPECT_TRUE(registry.registerEdge<EdgePoint2Prior>("EDGE_P2_PRIOR").ok());
  return registry;
}

VertexPoint2* addPoint(Graph& graph, int id, const Eigen::Vector2d& p) {
  auto v = std::make_unique<VertexPoint2>(id);
  v->setEstimate(p);
  VertexPoint2* raw = v.get();
  EXPECT_TRUE(graph.addVertex(std::move(v)).ok());
  return raw;
}

template <typename E>
E* addEdge(Graph& graph, std::initializer_list<int> ids, const typename E::Measurement& z) {
  auto e = std::make_unique<E>();
  size_t slot = 0;
  for (int id : ids) EXPECT_TRUE(e->setVertex(slot++, graph.vertex(id)).ok());
  e->setMeasurement(z);
  return static_cast<E*>(*graph.addEdge(std::move(e)));
}

const char kTriangle[] =
    "# three points, a prior, a loop of relative measurements and a range\n"
    "VERTEX_P2 0 0.1 -0.2\n"
    "VERTEX_P2 1 0.8 0.3\n"
    "VERTEX_P2 2 0.2 1.1\n"
    "EDGE_P2_PRIOR 0 0 0 100 0 100\n"
    "EDGE_P2_REL 0 1 1 0 4 1 9   # correlated information\n"
    "EDGE_P2_REL 1 2 -1 1 4 0 4\n"
    "EDGE_P2_REL 2 0 0.1 -1.05 1 0 1\n";

TEST(UserTypes, RegisteredFromATestFileReadOptimisedAndWrittenBack) {
  const TypeRegistry registry = userRegistry();
  Graph graph;
  std::istringstream text(kTriangle);
  const auto report = readG2o(text, "triangle.g2o", registry, graph);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->vertices, 3);
  EXPECT_EQ(report->edges, 4);

  // The problem is linear: the optimum is the dense weighted least-squares solution.
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(6, 6);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(6);
  for (const auto& edge : graph.edges()) {
    edge->linearize();
    const int m = edge->errorDim();
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, 6);
    for (size_t k = 0; k < edge->numVertices(); ++k) {
      J.block(0, 2 * edge->vertex(k)->id(), m, 2) = Eigen::Map<const Eigen::MatrixXd>(edge->jacobianData(k), m, 2);
    }
    const Eigen::Map<const Eigen::MatrixXd> omega(edge->informationData(), m, m);
    const Eigen::Map<const Eigen::VectorXd> e(edge->errorData(), m);
    H += J.transpose() * omega * J;
    g += J.transpose() * omega * e;
  }
  Eigen::VectorXd expected(6);
  for (int id = 0; id < 3; ++id) expected.segment<2>(2 * id) = graph.vertexAs<VertexPoint2>(id)->estimate();
  expected -= H.ldlt().solve(g);

  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
  for (int id = 0; id < 3; ++id) {
    EXPECT_LT((graph.vertexAs<VertexPoint2>(id)->estimate() - expected.segment<2>(2 * id)).norm(), 1e-9);
  }
  std::stringstream written;
  ASSERT_TRUE(writeG2o(written, registry, graph).ok());
  Graph reread;
  ASSERT_TRUE(readG2o(written, "written", registry, reread).ok());
  EXPECT_NEAR(reread.chi2(), summary.final_chi2, 1e-12);
}

TEST(UserTypes, RangeEdgeWithoutAnalyticJacobiansConvergesThroughNumericDifferentiation) {
  Graph graph;
  addPoint(graph, 0, {0, 0})->setFixed(true);
  addPoint(graph, 1, {2, 0})->setFixed(true);
  addPoint(graph, 2, {0.7, 1.4});
  addEdge<EdgePoint2Range>(graph, {0, 2}, 1.5);
  addEdge<EdgePoint2Range>(graph, {1, 2}, 1.5);
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  std::vector<double> history;
  OptimizerParams params;
  params.callback = [&history](const IterationSummary& it) { history.push_back(it.chi2); };
  const SolverSummary summary = optimizer.optimize(params);
  EXPECT_TRUE(summary.usable());
  EXPECT_LT(summary.final_chi2, 1e-18);
  for (size_t k = 1; k < history.size(); ++k) EXPECT_LE(history[k], history[k - 1]);
  const Eigen::Vector2d p = graph.vertexAs<VertexPoint2>(2)->estimate();
  EXPECT_NEAR(p.x(), 1.0, 1e-8);
  EXPECT_NEAR(p.y(), std::sqrt(1.25), 1e-8);
}

/// A seeded random graph of points with relative, range and prior edges, edges in both id orders,
/// a robust kernel on some and fixed vertices.
void buildRandomGraph(Graph& graph, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<int> pick(0, 29);
  for (int id = 0; id < 30; ++id) addPoint(graph, id, {normal(rng) * 3, normal(rng) * 3});
  graph.vertex(4)->setFixed(true);
  graph.vertex(17)->setFixed(true);
  auto huber = *makeRobustKernel("huber:0.5");
  for (int k = 0; k < 80; ++k) {
    int i = pick(rng);
    int j = pick(rng);
    if (i == j) continue;
    EdgeBase* edge = nullptr;
    if (k % 3 == 0) {
      edge = addEdge<EdgePoint2Range>(graph, {i, j}, 2.0 + normal(rng));
    } else {
      auto* rel = addEdge<EdgePoint2Relative>(graph, {i, j}, {normal(rng), normal(rng)});
      Eigen::Matrix2d a;
      a << 1 + std::abs(normal(rng)), 0.3 * normal(rng), 0, 1 + std::abs(normal(rng));
      rel->setInformation(a * a.transpose());
      edge = rel;
    }
    if (k % 4 == 0) edge->setRobustKernel(huber);
  }
  addEdge<EdgePoint2Prior>(graph, {0}, {0.0, 0.0});
}

TEST(SparseSystem, HessianAndRhsMatchADenseJtWJWithRobustWeights) {
  Graph graph;
  buildRandomGraph(graph, 3);
  addPoint(graph, 99, {1, 1});  // no edges: must stay out of the system
  SparseSystem system;
  ASSERT_TRUE(system.build(graph).ok());
  for (const auto& edge : graph.edges()) edge->linearize();
  system.assemble();
  const int n = system.dim();
  EXPECT_EQ(n, 2 * 28) << "30 points, two fixed, one isolated not counted";
  EXPECT_EQ(system.offsetOf(graph.vertex(4)), -1);
  EXPECT_EQ(system.offsetOf(graph.vertex(99)), -1);

  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (const auto& edge : graph.edges()) {
    const int m = edge->errorDim();
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, n);
    for (size_t k = 0; k < edge->numVertices(); ++k) {
      const int offset = system.offsetOf(edge->vertex(k));
      if (offset >= 0) J.block(0, offset, m, 2) = Eigen::Map<const Eigen::MatrixXd>(edge->jacobianData(k), m, 2);
    }
    const double weight = edge->robustKernel() ? edge->robustKernel()->robustify(edge->chi2())[1] : 1.0;
    const Eigen::MatrixXd W = weight * Eigen::Map<const Eigen::MatrixXd>(edge->informationData(), m, m);
    H += J.transpose() * W * J;
    b -= J.transpose() * W * Eigen::Map<const Eigen::VectorXd>(edge->errorData(), m);
  }
  const SparseMatrixView view = system.matrix();
  EXPECT_LT((testing::denseFromUpper(view) - H).cwiseAbs().maxCoeff(), 1e-12 * H.cwiseAbs().maxCoeff());
  EXPECT_LT((system.rhs() - b).cwiseAbs().maxCoeff(), 1e-12 * b.cwiseAbs().maxCoeff());
  for (int c = 0; c < n; ++c) {
    for (int k = view.col_ptr[c]; k < view.col_ptr[c + 1]; ++k) {
      EXPECT_LE(view.row_index[k], c) << "only the upper triangle is stored";
      if (k > view.col_ptr[c]) {
        EXPECT_LT(view.row_index[k - 1], view.row_index[k]) << "rows sorted";
      }
    }
  }
  system.setDamping(2.5);
  EXPECT_LT((testing::denseFromUpper(system.matrix()) - H - 2.5 * Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-9);
  system.setDamping(0.0);
  EXPECT_LT((testing::denseFromUpper(system.matrix()) - H).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Optimizer, NonFiniteErrorAtTheStartIsInvalidInputAndLeavesTheEstimate) {
  Graph graph;
  addPoint(graph, 0, {1, 2});
  addEdge<EdgePoint2Prior>(graph, {0}, {std::numeric_limits<double>::quiet_NaN(), 0.0});
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.termination, TerminationReason::kInvalidInput);
  EXPECT_NE(summary.message.find("vertices 0"), std::string::npos) << summary.message;
  EXPECT_EQ(graph.vertexAs<VertexPoint2>(0)->estimate(), Eigen::Vector2d(1, 2));
  EXPECT_FALSE(summary.usable());
}

TEST(Optimizer, AllVerticesFixedIsNothingToOptimize) {
  Graph graph;
  addPoint(graph, 0, {0, 0})->setFixed(true);
  addPoint(graph, 1, {1, 0})->setFixed(true);
  addEdge<EdgePoint2Relative>(graph, {0, 1}, {2, 0});
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.termination, TerminationReason::kNothingToOptimize);
  EXPECT_DOUBLE_EQ(summary.final_chi2, 1.0);
}

TEST(Optimizer, GaugeFreedomStopsGaussNewtonButNotLevenbergMarquardt) {
  for (Algorithm algorithm : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt}) {
    Graph graph;
    addPoint(graph, 0, {0, 0});
    addPoint(graph, 1, {1, 0.5});
    addPoint(graph, 2, {5, 5});  // a second, disconnected component
    addPoint(graph, 3, {6, 5});
    addEdge<EdgePoint2Relative>(graph, {0, 1}, {1, 0});
    addEdge<EdgePoint2Relative>(graph, {2, 3}, {1, 1});
    Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
    OptimizerParams params;
    params.algorithm = algorithm;
    const SolverSummary summary = optimizer.optimize(params);
    if (algorithm == Algorithm::kGaussNewton) {
      EXPECT_EQ(summary.termination, TerminationReason::kNotPositiveDefinite);
      EXPECT_EQ(graph.vertexAs<VertexPoint2>(1)->estimate(), Eigen::Vector2d(1, 0.5));
    } else {
      EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination);
      EXPECT_LT(summary.final_chi2, 1e-10);
    }
  }
}

TEST(Optimizer, FailingFactorisationAtEveryDampingLeavesTheEstimate) {
  Graph graph;
  addPoint(graph, 0, {3, 4});
  addEdge<EdgePoint2Prior>(graph, {0}, {0, 0});
  Optimizer optimizer(graph, std::make_unique<FailingSolver>());
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.termination, TerminationReason::kNotPositiveDefinite);
  EXPECT_EQ(summary.factorizations, OptimizerParams{}.max_trials);
  EXPECT_EQ(graph.vertexAs<VertexPoint2>(0)->estimate(), Eigen::Vector2d(3, 4));
  EXPECT_DOUBLE_EQ(summary.final_chi2, 25.0);
}

/// e = p − z while |p| < 2; NaN beyond (a model that breaks down away from the start).
class EdgeFragilePrior : public EdgePoint2Prior {
 public:
  void computeError() override {
    EdgePoint2Prior::computeError();
    if (vertexAs<0>()->estimate().norm() >= 2.0) error_.setConstant(std::numeric_limits<double>::quiet_NaN());
  }
};

TEST(Optimizer, DivergentStepIsRejectedAndTheEstimateStaysFinite) {
  Graph graph;
  addPoint(graph, 0, {1.9, 0});
  addEdge<EdgeFragilePrior>(graph, {0}, {5, 0});
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  OptimizerParams params;
  params.initial_lambda = 1e-9;  // the first, undamped step lands at |p| = 5: NaN
  const SolverSummary summary = optimizer.optimize(params);
  EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination);
  EXPECT_TRUE(std::isfinite(summary.final_chi2));
  EXPECT_LE(summary.final_chi2, summary.initial_chi2);
  EXPECT_LT(graph.vertexAs<VertexPoint2>(0)->estimate().norm(), 2.0);
  EXPECT_GT(summary.factorizations, summary.iterations) << "rejected trials were retried with more damping";
}

TEST(Optimizer, ZeroIterationsAndTimeBudgetStopCleanly) {
  Graph graph;
  buildRandomGraph(graph, 5);
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  OptimizerParams params;
  params.max_iterations = 0;
  SolverSummary summary = optimizer.optimize(params);
  EXPECT_EQ(summary.termination, TerminationReason::kMaxIterations);
  EXPECT_EQ(summary.iterations, 0);
  params.max_iterations = 1000;
  params.relative_decrease_stop = 0.0;
  params.step_norm_stop = 0.0;
  params.time_budget_ms = 1e-6;
  summary = optimizer.optimize(params);
  EXPECT_EQ(summary.termination, TerminationReason::kTimeBudget);
  EXPECT_LE(summary.iterations, 1);
}

TEST(Optimizer, StructureIsCachedUntilEdgesOrFixedFlagsChange) {
  Graph graph;
  buildRandomGraph(graph, 7);
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  OptimizerParams params;
  params.max_iterations = 2;
  EXPECT_TRUE(optimizer.optimize(params).structure_rebuilt);
  EXPECT_FALSE(optimizer.optimize(params).structure_rebuilt);
  graph.vertex(5)->setFixed(true);  // directly on the vertex, bypassing Graph::setFixed
  EXPECT_TRUE(optimizer.optimize(params).structure_rebuilt);
  addEdge<EdgePoint2Relative>(graph, {1, 2}, {0.5, 0.5});
  const SolverSummary after_edge = optimizer.optimize(params);
  EXPECT_TRUE(after_edge.structure_rebuilt);
  EXPECT_EQ(after_edge.edges, static_cast<int>(graph.numEdges()));
}

}  // namespace
}  // namespace dualgraph
