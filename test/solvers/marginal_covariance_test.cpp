// SPDX-License-Identifier: MIT
// MarginalCovariance against the dense inverse of an independently assembled H = Σ JᵀWJ on a pose/landmark
// graph (fixed vertices first, in the middle, last), a closed form, robust weights and every error status.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/solvers/marginal_covariance.h"
#include "test/types/test_states.h"
#include "dualgraph/types/edge_point_xyz_prior.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {

// Parameter names in gtest's messages (found by argument-dependent lookup, so outside the anonymous namespace).
inline void PrintTo(LinearSolverKind kind, std::ostream* os) { *os << linearSolverKindName(kind); }

namespace {

using testing::Rng;
using testing::Regime;

// Pose and landmark ids interleave, so the highest id (8) is a pose and a point sits between poses.
const std::vector<int> kPoses = {0, 2, 4, 6, 8};
const std::vector<int> kPoints = {1, 3, 5, 7};
// Every id of the mixed graph, shuffled (the system lays out the free ones by increasing id).
const std::vector<int> kAllIdsShuffled = {5, 8, 0, 3, 6, 1, 4, 7, 2};

void connect(Graph& graph, std::unique_ptr<EdgeBase> edge, std::initializer_list<int> ids) {
  size_t slot = 0;
  for (int id : ids) ASSERT_TRUE(edge->setVertex(slot++, graph.vertex(id)).ok());
  ASSERT_TRUE(graph.addEdge(std::move(edge)).ok());
}

/// Random poses chained by EdgeSE3 plus a loop closure, each point seen from two poses through a
/// sensor offset; measurements are noisy (non-zero residuals), informations random non-diagonal SPD.
void buildMixedGraph(Graph& graph, const std::vector<int>& fixed) {
  Rng rng(testing::kSeed);
  std::map<int, Eigen::Isometry3d> world_T_body;
  for (int id : kPoses) {
    world_T_body[id] = testing::randomPose(rng, Regime::kRandom);
    auto v = std::make_unique<VertexSE3>(id);
    v->setEstimate(world_T_body[id]);
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  auto noisyPose = [&rng]() {
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi[k] = 0.1 * testing::gaussian(rng);
    return se3Exp(xi);
  };
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{0, 2}, {2, 4}, {4, 6}, {6, 8}, {8, 2}}) {
    auto edge = std::make_unique<EdgeSE3>();
    edge->setMeasurement(world_T_body[i].inverse() * world_T_body[j] * noisyPose());
    edge->setInformation(testing::randomInformation<6>(rng));
    connect(graph, std::move(edge), {i, j});
  }
  const Eigen::Isometry3d body_T_sensor = noisyPose();
  for (size_t k = 0; k < kPoints.size(); ++k) {
    const Eigen::Vector3d p_world = testing::randomPoint(rng, Regime::kRandom);
    auto v = std::make_unique<VertexPointXYZ>(kPoints[k]);
    v->setEstimate(p_world);
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
    for (int pose : {kPoses[k], kPoses[k + 1]}) {
      auto edge = std::make_unique<EdgeSE3PointXYZ>();
      edge->setOffset(0, body_T_sensor);
      const Eigen::Vector3d noise(testing::gaussian(rng), testing::gaussian(rng), testing::gaussian(rng));
      edge->setMeasurement((world_T_body[pose] * body_T_sensor).inverse() * p_world + 0.1 * noise);
      edge->setInformation(testing::randomInformation<3>(rng));
      connect(graph, std::move(edge), {pose, kPoints[k]});
    }
  }
  for (int id : fixed) ASSERT_TRUE(graph.setFixed(id, true).ok());
}

/// The dense inverse of H = Σ JᵀWJ (W = ρ'(eᵀΩe)·Ω) assembled from each edge's raw linearisation,
/// the free vertices laid out in decreasing id order (deliberately not the system's order).
struct DenseReference {
  std::map<int, int> offset;
  Eigen::MatrixXd covariance;

  /// The reference joint block of `ids`; zero rows and columns for vertices without an offset.
  Eigen::MatrixXd jointBlock(const Graph& graph, const std::vector<int>& ids) const {
    std::vector<int> at(1, 0);
    for (int id : ids) at.push_back(at.back() + graph.vertex(id)->tangentDim());
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(at.back(), at.back());
    for (size_t i = 0; i < ids.size(); ++i) {
      for (size_t j = 0; j < ids.size(); ++j) {
        if (offset.count(ids[i]) == 0 || offset.count(ids[j]) == 0) continue;
        const int rows = at[i + 1] - at[i];
        const int cols = at[j + 1] - at[j];
        out.block(at[i], at[j], rows, cols) = covariance.block(offset.at(ids[i]), offset.at(ids[j]), rows, cols);
      }
    }
    return out;
  }
};

DenseReference denseReference(const Graph& graph) {
  DenseReference ref;
  for (const auto& edge : graph.edges()) {
    for (const VertexBase* v : edge->vertices()) {
      if (!v->fixed()) ref.offset[v->id()] = 0;
    }
  }
  int n = 0;
  for (auto it = ref.offset.rbegin(); it != ref.offset.rend(); ++it) {
    it->second = n;
    n += graph.vertex(it->first)->tangentDim();
  }
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  for (const auto& edge : graph.edges()) {
    edge->linearize();
    const int m = edge->errorDim();
    const double weight = edge->robustKernel() ? edge->robustKernel()->robustify(edge->chi2())[1] : 1.0;
    const Eigen::MatrixXd w = weight * Eigen::Map<const Eigen::MatrixXd>(edge->informationData(), m, m);
    for (size_t a = 0; a < edge->numVertices(); ++a) {
      for (size_t b = 0; b < edge->numVertices(); ++b) {
        const VertexBase* va = edge->vertex(a);
        const VertexBase* vb = edge->vertex(b);
        if (va->fixed() || vb->fixed()) continue;
        const Eigen::Map<const Eigen::MatrixXd> j_a(edge->jacobianData(a), m, va->tangentDim());
        const Eigen::Map<const Eigen::MatrixXd> j_b(edge->jacobianData(b), m, vb->tangentDim());
        h.block(ref.offset.at(va->id()), ref.offset.at(vb->id()), va->tangentDim(), vb->tangentDim()) +=
            j_a.transpose() * w * j_b;
      }
    }
  }
  ref.covariance = h.inverse();
  return ref;
}

double relativeMaxDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& reference) {
  return (a - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

/// Every vertex's block and the joint block of all vertices (shuffled order) equal the dense
/// inverse's; fixed vertices' blocks, rows and columns are exactly zero.
void expectBlocksEqualDenseInverse(Graph& graph, LinearSolverKind kind) {
  Optimizer optimizer(graph, makeLinearSolver(kind));
  MarginalCovariance marginals;
  const Status computed = marginals.compute(optimizer, graph);
  ASSERT_TRUE(computed.ok()) << computed.toString();
  const DenseReference ref = denseReference(graph);
  for (const auto& [id, vertex] : graph.vertices()) {
    SCOPED_TRACE("vertex " + std::to_string(id));
    const Result<Eigen::MatrixXd> sigma = marginals.block(id);
    ASSERT_TRUE(sigma.ok()) << sigma.status().toString();
    ASSERT_TRUE(sigma->rows() == vertex->tangentDim() && sigma->cols() == vertex->tangentDim());
    const Eigen::MatrixXd expected = ref.jointBlock(graph, {id});  // zero for a fixed vertex
    EXPECT_TRUE(vertex->fixed() ? sigma->isZero(0.0) : relativeMaxDifference(*sigma, expected) < 1e-9)
        << *sigma << "\nexpected\n" << expected;
  }
  const Result<Eigen::MatrixXd> joint = marginals.jointBlock(kAllIdsShuffled);
  ASSERT_TRUE(joint.ok()) << joint.status().toString();
  const Eigen::MatrixXd expected = ref.jointBlock(graph, kAllIdsShuffled);
  EXPECT_LT(relativeMaxDifference(*joint, expected), 1e-9);
  EXPECT_TRUE(joint->isApprox(joint->transpose(), 0.0)) << "exactly symmetric";
  // The reference is exactly zero only in the rows and columns of fixed vertices.
  EXPECT_TRUE((expected.array() != 0.0 || joint->array() == 0.0).all()) << "fixed rows/columns not zero";
}

class MarginalCovarianceTest : public ::testing::TestWithParam<LinearSolverKind> {};

TEST_P(MarginalCovarianceTest, BlocksAndJointBlocksEqualDenseInverseWithFixedVertexFirst) {
  Graph graph;
  buildMixedGraph(graph, {0});
  expectBlocksEqualDenseInverse(graph, GetParam());
}

TEST_P(MarginalCovarianceTest, JointBlockEqualsDenseInverseWithFixedVertexInTheMiddle) {
  Graph graph;
  buildMixedGraph(graph, {4});
  expectBlocksEqualDenseInverse(graph, GetParam());
}

TEST_P(MarginalCovarianceTest, JointBlockEqualsDenseInverseWithFixedVertexLast) {
  Graph graph;
  buildMixedGraph(graph, {8});
  expectBlocksEqualDenseInverse(graph, GetParam());
}

TEST_P(MarginalCovarianceTest, JointBlockEqualsDenseInverseWithTwoFixedVertices) {
  for (const std::vector<int>& fixed : {std::vector<int>{2, 8}, std::vector<int>{4, 5}}) {
    SCOPED_TRACE("fixed " + std::to_string(fixed[0]) + ", " + std::to_string(fixed[1]));
    Graph graph;
    buildMixedGraph(graph, fixed);
    expectBlocksEqualDenseInverse(graph, GetParam());
  }
}

TEST_P(MarginalCovarianceTest, PointWithNPriorsOfInformationOmegaHasCovarianceInverseOfNOmega) {
  constexpr int kPriors = 5;
  Rng rng(testing::kSeed);
  const Eigen::Matrix3d information = testing::randomInformation<3>(rng);
  Graph graph;
  ASSERT_TRUE(graph.addVertex(std::make_unique<VertexPointXYZ>(3)).ok());  // linear: H does not depend on x
  for (int k = 0; k < kPriors; ++k) {
    auto prior = std::make_unique<EdgePointXYZPrior>();
    prior->setMeasurement(testing::randomPoint(rng, Regime::kRandom));
    prior->setInformation(information);
    connect(graph, std::move(prior), {3});
  }
  const Eigen::Matrix3d expected = (kPriors * information).inverse();
  const Result<Eigen::MatrixXd> sigma = computeMarginalCovariance(graph, {3}, GetParam());
  ASSERT_TRUE(sigma.ok()) << sigma.status().toString();
  EXPECT_LT(relativeMaxDifference(*sigma, expected), 1e-12) << *sigma << "\nexpected\n" << expected;
}

TEST_P(MarginalCovarianceTest, RobustKernelWeightsEnterTheCovarianceLikeTheOptimiser) {
  Graph graph;
  buildMixedGraph(graph, {4});
  const Eigen::MatrixXd unweighted = denseReference(graph).jointBlock(graph, kAllIdsShuffled);
  // Huber's width at the median edge χ²: about half the edges get W = ρ'·Ω with ρ' < 1.
  std::vector<double> chi2;
  for (const auto& edge : graph.edges()) chi2.push_back(edge->chi2());  // linearised by denseReference
  std::sort(chi2.begin(), chi2.end());
  const auto huber = std::make_shared<HuberKernel>(std::sqrt(chi2[chi2.size() / 2]));
  for (const auto& edge : graph.edges()) edge->setRobustKernel(huber);
  expectBlocksEqualDenseInverse(graph, GetParam());
  const Result<Eigen::MatrixXd> sigma = computeMarginalCovariance(graph, kAllIdsShuffled, GetParam());
  ASSERT_TRUE(sigma.ok()) << sigma.status().toString();
  EXPECT_GT(relativeMaxDifference(*sigma, unweighted), 1e-3) << "the weights must matter in this test";
}

TEST_P(MarginalCovarianceTest, NothingFixedIsAFreeGaugeAndLeavesNoBlocks) {
  // Identity poses, measurements and information: H = [A −A; −A A], exactly singular along the gauge.
  Graph graph;
  for (int id : {0, 1}) ASSERT_TRUE(graph.addVertex(std::make_unique<VertexSE3>(id)).ok());
  connect(graph, std::make_unique<EdgeSE3>(), {0, 1});
  Optimizer optimizer(graph, makeLinearSolver(GetParam()));
  MarginalCovariance marginals;
  EXPECT_EQ(marginals.jointBlock({}).status().code(), StatusCode::kFailedPrecondition) << "before compute";
  EXPECT_EQ(marginals.compute(optimizer, graph).code(), StatusCode::kFailedPrecondition);  // free gauge
  EXPECT_EQ(marginals.block(0).status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(computeMarginalCovariance(graph, {0}, GetParam()).status().code(), StatusCode::kFailedPrecondition);
}

INSTANTIATE_TEST_SUITE_P(Solvers, MarginalCovarianceTest,
                         ::testing::Values(LinearSolverKind::kCholmod, LinearSolverKind::kEigen),
                         [](const auto& info) { return std::string(linearSolverKindName(info.param)); });

/// Expects `status` to have `code` and a message naming `id`.
void expectError(const Status& status, StatusCode code, int id) {
  EXPECT_EQ(status.code(), code) << status.toString();
  EXPECT_NE(status.message().find("vertex " + std::to_string(id)), std::string::npos) << status.message();
}

TEST(MarginalCovariance, BadIdsAndAnotherGraphAreStatusesNamingTheCulprit) {
  Graph graph;
  Graph other;
  buildMixedGraph(graph, {0});
  buildMixedGraph(other, {0});
  ASSERT_TRUE(graph.addVertex(std::make_unique<VertexPointXYZ>(20)).ok());  // free, no edge
  ASSERT_TRUE(graph.addVertex(std::make_unique<VertexPointXYZ>(21)).ok());
  ASSERT_TRUE(graph.setFixed(21, true).ok());
  Optimizer optimizer(graph, makeLinearSolver(LinearSolverKind::kCholmod));
  MarginalCovariance marginals;
  EXPECT_EQ(marginals.compute(optimizer, other).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(marginals.block(2).status().code(), StatusCode::kFailedPrecondition);
  ASSERT_TRUE(marginals.compute(optimizer, graph).ok());
  expectError(marginals.block(42).status(), StatusCode::kNotFound, 42);
  expectError(marginals.jointBlock({2, 42}).status(), StatusCode::kNotFound, 42);
  expectError(marginals.block(20).status(), StatusCode::kFailedPrecondition, 20);
  expectError(marginals.jointBlock({2, 5, 2}).status(), StatusCode::kInvalidArgument, 2);
  EXPECT_TRUE(marginals.block(21).value().isZero(0.0));  // fixed: known exactly, attached or not
  EXPECT_EQ(marginals.jointBlock({}).value().size(), 0);
}

TEST(MarginalCovariance, StructureChangedAfterComputeIsFailedPreconditionUntilRecomputed) {
  Graph graph;
  buildMixedGraph(graph, {0});
  Optimizer optimizer(graph, makeLinearSolver(LinearSolverKind::kCholmod));
  MarginalCovariance marginals;
  ASSERT_TRUE(marginals.compute(optimizer, graph).ok());
  ASSERT_TRUE(marginals.block(2).ok());
  ASSERT_TRUE(graph.addVertex(std::make_unique<VertexPointXYZ>(30)).ok());
  EXPECT_EQ(marginals.block(2).status().code(), StatusCode::kFailedPrecondition);
  ASSERT_TRUE(marginals.compute(optimizer, graph).ok());
  ASSERT_TRUE(marginals.block(2).ok());
  graph.vertex(6)->setFixed(true);  // bypasses the graph's version counter
  expectError(marginals.block(2).status(), StatusCode::kFailedPrecondition, 6);
  ASSERT_TRUE(marginals.compute(optimizer, graph).ok());
  EXPECT_TRUE(marginals.block(6).value().isZero(0.0));
  ASSERT_TRUE(graph.removeEdge(graph.edges().back().get()).ok());
  EXPECT_EQ(marginals.jointBlock({2, 4}).status().code(), StatusCode::kFailedPrecondition);
}

}  // namespace
}  // namespace dualgraph
