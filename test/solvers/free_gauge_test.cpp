// SPDX-License-Identifier: MIT
// MarginalCovariance::compute on a free gauge: kFailedPrecondition saying how to fix it, for pose graphs and
// user types, per component; components anchored by a prior, a fixed vertex or an absolute multi-vertex edge pass.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "dualgraph/solvers/marginal_covariance.h"
#include "dualgraph/types/edge_se3.h"
#include "test/solvers/marginal_graphs.h"

namespace dualgraph {
namespace {

/// e = [p_i; p_j] − z: both points measured absolutely by one edge (a marginalisation prior's shape).
class EdgePoint2PairAbsolute
    : public BaseEdge<4, Eigen::Vector4d, testing::VertexPoint2, testing::VertexPoint2> {
 public:
  void computeError() override {
    error_ << vertexAs<0>()->estimate() - measurement_.head<2>(), vertexAs<1>()->estimate() - measurement_.tail<2>();
  }
  Status read(TokenReader&, const ParameterContainer&) override { return Status(); }
  void write(std::ostream&) const override {}

 protected:
  void linearizeOplus() override {
    jacobianOplus<0>().setZero();
    jacobianOplus<1>().setZero();
    jacobianOplus<0>().topRows<2>().setIdentity();
    jacobianOplus<1>().bottomRows<2>().setIdentity();
  }
};

Status computeWith(Graph& graph, LinearSolverKind kind) {
  Optimizer optimizer(graph, makeLinearSolver(kind));
  MarginalCovariance marginals;
  return marginals.compute(optimizer, graph);
}

void expectFreeGauge(const Status& status, int named_vertex) {
  EXPECT_EQ(status.code(), StatusCode::kFailedPrecondition) << status.toString();
  const std::string& message = status.message();
  EXPECT_NE(message.find("gauge is free"), std::string::npos) << message;
  EXPECT_NE(message.find("vertex " + std::to_string(named_vertex) + ":"), std::string::npos) << message;
  EXPECT_NE(message.find("fix a vertex"), std::string::npos) << message;
  EXPECT_NE(message.find("--gauge"), std::string::npos) << message;
  EXPECT_NE(message.find("prior"), std::string::npos) << message;
}

class FreeGauge : public ::testing::TestWithParam<LinearSolverKind> {
 protected:
  void SetUp() override { DG_SKIP_WITHOUT_SHARED("data/posegraph/smallGrid3D.g2o"); }
};

TEST_P(FreeGauge, PoseGraphsWithNothingFixedAreFailedPrecondition) {
  for (const char* name : {"smallGrid3D.g2o", "intel.g2o"}) {
    SCOPED_TRACE(name);
    Graph graph;
    ASSERT_TRUE(testing::loadSharedPoseGraph(name, graph, /*fix_gauge=*/false).ok());
    expectFreeGauge(computeWith(graph, GetParam()), graph.vertices().begin()->first);
    ASSERT_TRUE(graph.setFixed(graph.vertices().rbegin()->first, true).ok());  // the remedy works
    EXPECT_TRUE(computeWith(graph, GetParam()).ok());
  }
}

TEST_P(FreeGauge, OneUnanchoredComponentBesideAnAnchoredOneIsNamed) {
  Graph graph;
  ASSERT_TRUE(testing::loadSharedPoseGraph("smallGrid3D.g2o", graph, /*fix_gauge=*/true).ok());
  testing::addPoint2Network(graph, 5000, 30, /*with_prior=*/false, 3);
  const Status status = computeWith(graph, GetParam());
  expectFreeGauge(status, 5000);
  EXPECT_NE(status.message().find("the 30 vertices"), std::string::npos) << status.message();
}

TEST_P(FreeGauge, UserTypeNetworkIsAnchoredByAPriorOrAFixedVertex) {
  Graph with_prior;
  testing::addPoint2Network(with_prior, 0, 40, /*with_prior=*/true, 9);
  EXPECT_TRUE(computeWith(with_prior, GetParam()).ok());
  Graph without;
  testing::addPoint2Network(without, 0, 40, /*with_prior=*/false, 9);
  expectFreeGauge(computeWith(without, GetParam()), 0);
  ASSERT_TRUE(without.setFixed(17, true).ok());
  EXPECT_TRUE(computeWith(without, GetParam()).ok());
}

TEST_P(FreeGauge, AnAbsoluteEdgeBetweenFreeVerticesAnchorsThemNumerically) {
  Graph graph;  // no fixed vertex, no unary edge: structurally suspect, numerically anchored
  testing::addPoint2Network(graph, 0, 40, /*with_prior=*/false, 21);
  auto pair = std::make_unique<EdgePoint2PairAbsolute>();
  Eigen::Vector4d z;
  z << graph.vertexAs<testing::VertexPoint2>(3)->estimate(), graph.vertexAs<testing::VertexPoint2>(30)->estimate();
  pair->setMeasurement(z);
  ASSERT_TRUE(pair->setVertex(0, graph.vertex(3)).ok());
  ASSERT_TRUE(pair->setVertex(1, graph.vertex(30)).ok());
  ASSERT_TRUE(graph.addEdge(std::move(pair)).ok());
  Optimizer optimizer(graph, makeLinearSolver(GetParam()));
  MarginalCovariance marginals;
  const Status computed = marginals.compute(optimizer, graph);
  ASSERT_TRUE(computed.ok()) << computed.toString();
  const Eigen::MatrixXd sigma = marginals.blocks({3}).value()[0];
  EXPECT_LT(sigma.maxCoeff(), 1.0) << sigma;  // bounded: Ω = I on the pair
}

TEST_P(FreeGauge, OnlyTheSingularComponentIsNamedBesideOneAnchoredByAnAbsoluteEdge) {
  Graph graph;  // two structurally unanchored networks; the first is anchored by an absolute pair edge
  testing::addPoint2Network(graph, 0, 20, /*with_prior=*/false, 4);
  testing::addPoint2Network(graph, 100, 25, /*with_prior=*/false, 6);
  auto pair = std::make_unique<EdgePoint2PairAbsolute>();
  pair->setMeasurement(Eigen::Vector4d(1.0, 2.0, 3.0, 4.0));
  ASSERT_TRUE(pair->setVertex(0, graph.vertex(2)).ok());
  ASSERT_TRUE(pair->setVertex(1, graph.vertex(9)).ok());
  ASSERT_TRUE(graph.addEdge(std::move(pair)).ok());
  Optimizer optimizer(graph, makeLinearSolver(GetParam()));
  // Round-off decides whether the singular H factorises (Eigen: yes here, CHOLMOD: no); only a factor can
  // tell the components apart, so without one both are named.
  const bool factorised = optimizer.factorizeAtCurrentEstimate().ok();
  MarginalCovariance marginals;
  const Status status = marginals.compute(optimizer, graph);
  expectFreeGauge(status, 100);
  EXPECT_NE(status.message().find("the 25 vertices"), std::string::npos) << status.message();
  EXPECT_EQ(status.message().find("vertex 0") == std::string::npos, factorised) << status.message();
}

TEST_P(FreeGauge, IdenticalPosesGiveAnExactlySingularHAndTheSameError) {
  Graph graph;  // H = [A −A; −A A]: the factorisation itself fails (or not: round-off); either way the gauge
  for (int id : {0, 1}) ASSERT_TRUE(graph.addVertex(std::make_unique<VertexSE3>(id)).ok());
  auto edge = std::make_unique<EdgeSE3>();
  ASSERT_TRUE(edge->setVertex(0, graph.vertex(0)).ok());
  ASSERT_TRUE(edge->setVertex(1, graph.vertex(1)).ok());
  ASSERT_TRUE(graph.addEdge(std::move(edge)).ok());
  expectFreeGauge(computeWith(graph, GetParam()), 0);
}

INSTANTIATE_TEST_SUITE_P(Solvers, FreeGauge, ::testing::Values(LinearSolverKind::kCholmod, LinearSolverKind::kEigen),
                         [](const auto& info) { return std::string(linearSolverKindName(info.param)); });

}  // namespace
}  // namespace dualgraph
