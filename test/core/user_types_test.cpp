// SPDX-License-Identifier: MIT
// A user's own types, defined outside the library (user_types.h) and registered here, run through
// the whole engine: read from g2o text, optimised to the exact least-squares answer, written back.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/optimizer.h"
#include "test/core/test_fixtures.h"

namespace dualgraph {
namespace {

using testing::DenseTestSolver;
using testing::VertexPoint2;

Eigen::Vector2d pointOf(const Graph& graph, int id) { return graph.vertexAs<VertexPoint2>(id)->estimate(); }

/// Registers the user's types in a fresh registry, the way a user's main would.
TypeRegistry userRegistry() {
  TypeRegistry registry;
  EXPECT_TRUE(registry.registerVertex<testing::VertexPoint2>("VERTEX_P2").ok());
  EXPECT_TRUE(registry.registerEdge<testing::EdgePoint2Relative>("EDGE_P2_REL").ok());
  EXPECT_TRUE(registry.registerEdge<testing::EdgePoint2Range>("EDGE_P2_RANGE").ok());
  EXPECT_TRUE(registry.registerEdge<testing::EdgePoint2Prior>("EDGE_P2_PRIOR").ok());
  return registry;
}

// x0 fixed at the origin; x1 − x0 ≈ z01, x2 − x1 ≈ z12, x2 − x0 ≈ z02, unit information.
// Normal equations: 2x1 − x2 = z01 − z12 and −x1 + 2x2 = z12 + z02, so
// x1 = (2 z01 − z12 + z02)/3 = (1.1, 0.2) and x2 = (z01 + z12 + 2 z02)/3 = (2.2, 0.4);
// every residual is ±(0.1, 0.2), χ² = 3 · 0.05 = 0.15.
const char kLoop[] =
    "# a loop of three points, the first fixed\n"
    "VERTEX_P2 0 0 0\n"
    "VERTEX_P2 1 0.3 -0.2\n"
    "VERTEX_P2 2 5 5\n"
    "FIX 0\n"
    "EDGE_P2_REL 0 1 1 0 1 0 1\n"
    "EDGE_P2_REL 1 2 1 0 1 0 1\n"
    "EDGE_P2_REL 0 2 2.3 0.6 1 0 1  # the loop closure disagrees by (0.3, 0.6)\n";

class UserTypes : public ::testing::TestWithParam<Algorithm> {};

TEST_P(UserTypes, RegisteredFromATestFileReadAndOptimisedToTheExactLeastSquaresAnswer) {
  const TypeRegistry registry = userRegistry();
  Graph graph;
  std::istringstream text(kLoop);
  const auto report = readG2o(text, "loop.g2o", registry, graph);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->vertices, 3);
  EXPECT_EQ(report->edges, 3);
  EXPECT_EQ(report->fixed, 1);

  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  OptimizerParams params;
  params.algorithm = GetParam();
  const SolverSummary summary = optimizer.optimize(params);
  EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
  EXPECT_EQ(pointOf(graph, 0), Eigen::Vector2d(0, 0));
  EXPECT_LT((pointOf(graph, 1) - Eigen::Vector2d(1.1, 0.2)).norm(), 1e-9) << pointOf(graph, 1).transpose();
  EXPECT_LT((pointOf(graph, 2) - Eigen::Vector2d(2.2, 0.4)).norm(), 1e-9) << pointOf(graph, 2).transpose();
  EXPECT_NEAR(summary.final_chi2, 0.15, 1e-12);

  // Written back with the user's tags and read again to the same χ².
  std::stringstream written;
  ASSERT_TRUE(writeG2o(written, registry, graph).ok());
  EXPECT_NE(written.str().find("EDGE_P2_REL 0 2 2.2999999999999998 0.59999999999999998 1 0 1"), std::string::npos)
      << written.str();
  Graph reread;
  ASSERT_TRUE(readG2o(written, "written.g2o", registry, reread).ok());
  EXPECT_NEAR(reread.chi2(), summary.final_chi2, 1e-15);
  EXPECT_TRUE(reread.vertex(0)->fixed());
}

INSTANTIATE_TEST_SUITE_P(LmAndGn, UserTypes,
                         ::testing::Values(Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton),
                         [](const ::testing::TestParamInfo<Algorithm>& info) {
                           return std::string(info.param == Algorithm::kGaussNewton ? "GaussNewton"
                                                                                    : "LevenbergMarquardt");
                         });

TEST(UserTypesRange, EdgeWithoutAnalyticJacobiansIsOptimisedThroughNumericDifferentiation) {
  // Two fixed anchors 2 m apart, a point 1.5 m from both: (1, √1.25) from a start above the axis.
  const char text[] =
      "VERTEX_P2 0 0 0\n"
      "VERTEX_P2 1 2 0\n"
      "VERTEX_P2 2 0.7 1.4\n"
      "FIX 0 1\n"
      "EDGE_P2_RANGE 0 2 1.5 1\n"
      "EDGE_P2_RANGE 2 1 1.5 1\n";
  const TypeRegistry registry = userRegistry();
  Graph graph;
  std::istringstream in(text);
  ASSERT_TRUE(readG2o(in, "range.g2o", registry, graph).ok());
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
  EXPECT_LT(summary.final_chi2, 1e-20);
  EXPECT_NEAR(pointOf(graph, 2).x(), 1.0, 1e-9);
  EXPECT_NEAR(pointOf(graph, 2).y(), std::sqrt(1.25), 1e-9);
}

TEST(UserTypesPrior, CorrelatedInformationGivesTheWeightedLeastSquaresAnswer) {
  // One free point with two priors: x = (Ω1 + Ω2)⁻¹ (Ω1 z1 + Ω2 z2).
  const char text[] =
      "VERTEX_P2 0 9 -9\n"
      "EDGE_P2_PRIOR 0 1 2 4 1 3\n"
      "EDGE_P2_PRIOR 0 -1 0 1 -0.5 2\n";
  const TypeRegistry registry = userRegistry();
  Graph graph;
  std::istringstream in(text);
  ASSERT_TRUE(readG2o(in, "priors.g2o", registry, graph).ok());
  Eigen::Matrix2d omega1;
  omega1 << 4, 1, 1, 3;
  Eigen::Matrix2d omega2;
  omega2 << 1, -0.5, -0.5, 2;
  const Eigen::Vector2d expected =
      (omega1 + omega2).inverse() * (omega1 * Eigen::Vector2d(1, 2) + omega2 * Eigen::Vector2d(-1, 0));
  Optimizer optimizer(graph, std::make_unique<DenseTestSolver>());
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.termination, TerminationReason::kConverged) << summary.message;
  EXPECT_LT((pointOf(graph, 0) - expected).norm(), 1e-9) << pointOf(graph, 0).transpose() << " vs "
                                                          << expected.transpose();
}

}  // namespace
}  // namespace dualgraph
