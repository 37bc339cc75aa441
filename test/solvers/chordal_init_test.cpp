// SPDX-License-Identifier: MIT
// The chordal initialiser: exact recovery of noise-free SE(2)/SE(3) pose graphs from far-off starts (both
// solvers), its anchors, the SO(3) projection, and the graphs it refuses or (kAuto) leaves alone.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/solvers/chordal_init.h"
#include "dualgraph/solvers/chordal_systems.h"
#include "test/types/test_states.h"
#include "dualgraph/types/edge_se2.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/vertex_point_xyz.h"

namespace dualgraph {
namespace {

using testing::Rng;
using testing::Regime;

constexpr int kPoses = 40;

void connect(Graph& graph, std::unique_ptr<EdgeBase> edge, int i, int j) {
  ASSERT_TRUE(edge->setVertex(0, graph.vertex(i)).ok());
  ASSERT_TRUE(edge->setVertex(1, graph.vertex(j)).ok());
  ASSERT_TRUE(graph.addEdge(std::move(edge)).ok());
}

/// A chain of kPoses plus loop closures every 3 poses back to a random earlier pose.
std::vector<std::pair<int, int>> edgePairs(Rng& rng) {
  std::vector<std::pair<int, int>> pairs;
  for (int k = 1; k < kPoses; ++k) pairs.emplace_back(k - 1, k);
  for (int k = 3; k < kPoses; k += 3) pairs.emplace_back(static_cast<int>(testing::uniform(rng, 0.0, k - 1.0)), k);
  return pairs;
}

/// Noise-free SE(3) graph: exact measurements from `truth`, random SPD informations, every estimate replaced by
/// an unrelated random pose (rotations of any angle), vertex `fixed` (if ≥ 0) fixed at its truth.
void buildSe3(Graph& graph, std::vector<Eigen::Isometry3d>& truth, int fixed, Rng& rng) {
  for (int k = 0; k < kPoses; ++k) {
    truth.push_back(testing::randomPose(rng, Regime::kRandom));
    auto v = std::make_unique<VertexSE3>(k);
    v->setEstimate(k == fixed ? truth.back() : testing::randomPose(rng, Regime::kRandom));
    v->setFixed(k == fixed);
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  for (const auto& [i, j] : edgePairs(rng)) {
    auto edge = std::make_unique<EdgeSE3>();
    edge->setMeasurement(truth[i].inverse() * truth[j]);
    edge->setInformation(testing::randomInformation<6>(rng));
    connect(graph, std::move(edge), i, j);
  }
}

void buildSe2(Graph& graph, std::vector<SE2>& truth, int fixed, Rng& rng) {
  const auto randomSe2 = [&rng] {
    return SE2(testing::uniform(rng, -5, 5), testing::uniform(rng, -5, 5), testing::uniform(rng, -3.1, 3.1));
  };
  for (int k = 0; k < kPoses; ++k) {
    truth.push_back(randomSe2());
    auto v = std::make_unique<VertexSE2>(k);
    v->setEstimate(k == fixed ? truth.back() : randomSe2());
    v->setFixed(k == fixed);
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  for (const auto& [i, j] : edgePairs(rng)) {
    auto edge = std::make_unique<EdgeSE2>();
    edge->setMeasurement(truth[i].inverse() * truth[j]);
    edge->setInformation(testing::randomInformation<3>(rng));
    connect(graph, std::move(edge), i, j);
  }
}

class ChordalExact : public ::testing::TestWithParam<LinearSolverKind> {};

TEST_P(ChordalExact, RecoversANoiseFreeSe3GraphFromRandomRotations) {
  Rng rng(testing::kSeed);
  Graph graph;
  std::vector<Eigen::Isometry3d> truth;
  buildSe3(graph, truth, kPoses - 1, rng);
  ASSERT_GT(graph.chi2(), 1e3);  // the start is far off
  const auto report = initializePoseGraph(graph, PoseGraphInit::kChordal, GetParam());
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->applied, PoseGraphInit::kChordal);
  EXPECT_EQ(report->dimension, 3);
  EXPECT_EQ(report->moved_poses, kPoses - 1);
  EXPECT_EQ(report->anchors, 1);
  for (int k = 0; k < kPoses; ++k) {
    const Eigen::Isometry3d& estimate = graph.vertexAs<VertexSE3>(k)->estimate();
    EXPECT_LT((estimate.linear() - truth[k].linear()).norm(), 1e-10) << "vertex " << k;
    EXPECT_LT((estimate.translation() - truth[k].translation()).norm(), 1e-9) << "vertex " << k;
    EXPECT_NEAR(estimate.linear().determinant(), 1.0, 1e-12);
  }
  EXPECT_LT(graph.chi2(), 1e-16);
}

TEST_P(ChordalExact, RecoversANoiseFreeSe2GraphFromRandomAngles) {
  Rng rng(testing::kSeed + 1);
  Graph graph;
  std::vector<SE2> truth;
  buildSe2(graph, truth, 0, rng);
  ASSERT_GT(graph.chi2(), 1e3);
  const auto report = initializePoseGraph(graph, PoseGraphInit::kChordal, GetParam());
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->dimension, 2);
  for (int k = 0; k < kPoses; ++k) {
    const SE2& estimate = graph.vertexAs<VertexSE2>(k)->estimate();
    EXPECT_NEAR(std::remainder(estimate.angle() - truth[k].angle(), 2.0 * M_PI), 0.0, 1e-10) << "vertex " << k;
    EXPECT_LT((estimate.translation() - truth[k].translation()).norm(), 1e-9) << "vertex " << k;
  }
  EXPECT_LT(graph.chi2(), 1e-16);
}

INSTANTIATE_TEST_SUITE_P(Solvers, ChordalExact, ::testing::Values(LinearSolverKind::kCholmod, LinearSolverKind::kEigen),
                         [](const auto& info) { return std::string(linearSolverKindName(info.param)); });

TEST(ChordalInit, WithoutAFixedVertexHoldsEachComponentsLowestIdAndRecoversTheRest) {
  Rng rng(testing::kSeed + 2);
  Graph graph;
  std::vector<Eigen::Isometry3d> truth;
  buildSe3(graph, truth, -1, rng);
  // A second component, 100 and 101, also with nothing fixed.
  for (int id : {100, 101}) {
    auto v = std::make_unique<VertexSE3>(id);
    v->setEstimate(testing::randomPose(rng, Regime::kRandom));
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  const Eigen::Isometry3d z = testing::randomPose(rng, Regime::kRandom);
  auto edge = std::make_unique<EdgeSE3>();
  edge->setMeasurement(z);
  connect(graph, std::move(edge), 100, 101);
  const Eigen::Isometry3d start0 = graph.vertexAs<VertexSE3>(0)->estimate();
  const Eigen::Isometry3d start100 = graph.vertexAs<VertexSE3>(100)->estimate();

  const auto report = initializePoseGraph(graph, PoseGraphInit::kChordal);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->anchors, 2);
  EXPECT_EQ(report->moved_poses, kPoses - 1 + 1);
  EXPECT_TRUE(graph.vertexAs<VertexSE3>(0)->estimate().isApprox(start0, 0.0));  // held, bit for bit
  EXPECT_TRUE(graph.vertexAs<VertexSE3>(100)->estimate().isApprox(start100, 0.0));
  // The truth moved rigidly onto the held vertex: every relative pose exact, χ² zero.
  for (int k = 0; k < kPoses; ++k) {
    const Eigen::Isometry3d expected = start0 * truth[0].inverse() * truth[k];
    EXPECT_LT((graph.vertexAs<VertexSE3>(k)->estimate().matrix() - expected.matrix()).norm(), 1e-9) << k;
  }
  EXPECT_LT((graph.vertexAs<VertexSE3>(101)->estimate().matrix() - (start100 * z).matrix()).norm(), 1e-12);
  EXPECT_LT(graph.chi2(), 1e-16);
}

TEST(ChordalInit, NearestRotationOfAReflectionHasDeterminantPlusOne) {
  const Eigen::Matrix3d reflection = Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal();
  const Eigen::Matrix3d r = chordal::nearestRotation<3>(2.0 * reflection + 0.01 * Eigen::Matrix3d::Ones());
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  const Eigen::Matrix2d scaled_rotation = 3.0 * Eigen::Rotation2Dd(0.7).toRotationMatrix();
  EXPECT_LT((chordal::nearestRotation<2>(scaled_rotation) - Eigen::Rotation2Dd(0.7).toRotationMatrix()).norm(), 1e-15);
}

TEST(ChordalInit, NoisyLoopIsCloserThanTheOdometryStart) {
  // A 2-D square driven 5 times with a biased heading: odometry composition drifts, the loop closures
  // to the first lap pull the chordal estimate back (χ² well below the odometry start's).
  Rng rng(testing::kSeed + 3);
  Graph graph;
  std::vector<SE2> truth;
  for (int k = 0; k < 40; ++k) truth.emplace_back(k % 4 == 0 || k % 4 == 3 ? 0.0 : 4.0, k % 4 < 2 ? 0.0 : 4.0,
                                                   (k % 4) * M_PI / 2.0);
  SE2 odometry = truth[0];
  for (int k = 0; k < 40; ++k) {
    auto v = std::make_unique<VertexSE2>(k);
    if (k > 0) odometry = odometry * (truth[k - 1].inverse() * truth[k]) * SE2(0.0, 0.0, 0.05);
    v->setEstimate(odometry);
    v->setFixed(k == 0);
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  for (int k = 1; k < 40; ++k) {
    auto edge = std::make_unique<EdgeSE2>();
    edge->setMeasurement((truth[k - 1].inverse() * truth[k]) * SE2(0.01 * testing::gaussian(rng), 0.0, 0.05));
    connect(graph, std::move(edge), k - 1, k);
  }
  for (int k = 4; k < 40; ++k) {
    auto edge = std::make_unique<EdgeSE2>();
    edge->setMeasurement(truth[k % 4].inverse() * truth[k]);
    connect(graph, std::move(edge), k % 4, k);
  }
  const double start = graph.chi2();
  ASSERT_TRUE(initializePoseGraph(graph, PoseGraphInit::kChordal).ok());
  EXPECT_LT(graph.chi2(), 0.01 * start);
}

TEST(ChordalInit, RefusesGraphsThatAreNotPureAndAutoLeavesThemAlone) {
  Rng rng(testing::kSeed + 4);
  Graph graph;
  std::vector<Eigen::Isometry3d> truth;
  buildSe3(graph, truth, 0, rng);
  auto point = std::make_unique<VertexPointXYZ>(500);
  point->setEstimate(Eigen::Vector3d(1.0, 2.0, 3.0));
  ASSERT_TRUE(graph.addVertex(std::move(point)).ok());
  auto seen = std::make_unique<EdgeSE3PointXYZ>();
  seen->setOffset(0, Eigen::Isometry3d::Identity());
  connect(graph, std::move(seen), 3, 500);
  const double start = graph.chi2();

  const auto refused = initializePoseGraph(graph, PoseGraphInit::kChordal);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(refused.status().message().find("vertex 500 is neither a VERTEX_SE2 nor a VERTEX_SE3:QUAT"), std::string::npos)
      << refused.status().message();
  EXPECT_EQ(graph.chi2(), start);  // nothing moved

  const auto automatic = initializePoseGraph(graph, PoseGraphInit::kAuto);
  ASSERT_TRUE(automatic.ok());
  EXPECT_EQ(automatic->applied, PoseGraphInit::kNone);
  EXPECT_NE(automatic->reason.find("vertex 500"), std::string::npos) << automatic->reason;
  EXPECT_EQ(graph.chi2(), start);
}

TEST(ChordalInit, MixedDimensionsAndEdgelessGraphsAreNamed) {
  Graph graph;
  ASSERT_TRUE(graph.addVertex(std::make_unique<VertexSE2>(0)).ok());
  ASSERT_TRUE(graph.addVertex(std::make_unique<VertexSE2>(1)).ok());
  EXPECT_NE(poseGraphDimension(graph).status().message().find("no edges"), std::string::npos);
  connect(graph, std::make_unique<EdgeSE2>(), 0, 1);
  ASSERT_TRUE(graph.addVertex(std::make_unique<VertexSE3>(2)).ok());
  const auto mixed = poseGraphDimension(graph);
  ASSERT_FALSE(mixed.ok());
  EXPECT_NE(mixed.status().message().find("vertex 2 is VERTEX_SE3:QUAT among VERTEX_SE2 vertices"), std::string::npos)
      << mixed.status().message();
}

TEST(ChordalInit, AutoSkipsRobustKernelsWhileChordalStillRuns) {
  Rng rng(testing::kSeed + 5);
  Graph graph;
  std::vector<SE2> truth;
  buildSe2(graph, truth, 0, rng);
  for (const auto& edge : graph.edges()) edge->setRobustKernel(*makeRobustKernel("huber:1.0"));
  const double start = graph.chi2();
  const auto automatic = initializePoseGraph(graph, PoseGraphInit::kAuto);
  ASSERT_TRUE(automatic.ok());
  EXPECT_EQ(automatic->applied, PoseGraphInit::kNone);
  EXPECT_NE(automatic->reason.find("robust kernel"), std::string::npos);
  EXPECT_EQ(graph.chi2(), start);
  const auto chordal = initializePoseGraph(graph, PoseGraphInit::kChordal);
  ASSERT_TRUE(chordal.ok());
  EXPECT_LT(graph.chi2(), 1e-16);
}

TEST(ChordalInit, NamesParseBothWays) {
  for (PoseGraphInit init : {PoseGraphInit::kAuto, PoseGraphInit::kChordal, PoseGraphInit::kNone}) {
    EXPECT_EQ(*parsePoseGraphInit(poseGraphInitName(init)), init);
  }
  EXPECT_NE(parsePoseGraphInit("spectral").status().message().find("'spectral'"), std::string::npos);
}

}  // namespace
}  // namespace dualgraph
