// SPDX-License-Identifier: MIT
// Partial gates in the temporary graph: corner rays anchored by a pose observation of their gate add exactly
// the information of their corner edges (dense Schur oracle), both solvers agree, and rays without an anchor,
// or outside the dual graph's SE(3) gates, are counted, never silently used or dropped.
#include <gtest/gtest.h>

#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/gate_edge.h"
#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/dual_graph/temporary_graph.h"
#include "test/dual_graph/distillation_fixtures.h"
#include "dualgraph/types/edge_se3_corner_projection.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

/// The camera looks along the body's x axis (RDF camera: x right = −y body, y down = −z body).
Eigen::Isometry3d forwardCamera() {
  Eigen::Isometry3d body_T_camera = Eigen::Isometry3d::Identity();
  body_T_camera.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  body_T_camera.translation() << 0.05, 0.0, 0.02;
  return body_T_camera;
}

/// A 1.5 m gate's corners in its own frame (normal x): tl, tr, br, bl seen from the front.
Eigen::Matrix<double, 3, 4> gateCorners() {
  Eigen::Matrix<double, 3, 4> corners;
  corners << 0, 0, 0, 0, 0.75, -0.75, -0.75, 0.75, 0.75, 0.75, -0.75, -0.75;
  return corners;
}

/// Poses t = 0..4 flying along x towards a gate 9 m ahead (keyframe at 4), a second gate off to the side.
struct PartialScenario : GateApproach {
  Matrix6d pose_covariance = randomCovariance<6>(0.01);
  double ray_sigma = 3.0 / 400.0;  // 3 px at f = 400 px
  GateObservation poseAt(int t) const {
    return GateObservation::pose(t, 0, poses[static_cast<size_t>(t)].inverse() * gate, pose_covariance);
  }
  /// Corner rays of `corners` (indices into gateCorners) seen exactly from the pose at t.
  GateObservation raysAt(int t, std::vector<int> corners) const {
    GateCornerRays rays;
    rays.count = static_cast<int>(corners.size());
    rays.body_T_camera = forwardCamera();
    for (Eigen::Matrix2d& covariance : rays.covariance) covariance = ray_sigma * ray_sigma * Eigen::Matrix2d::Identity();
    const Eigen::Isometry3d camera_T_gate = (poses[static_cast<size_t>(t)] * forwardCamera()).inverse() * gate;
    for (int k = 0; k < rays.count; ++k) {
      rays.p_gate.col(k) = gateCorners().col(corners[static_cast<size_t>(k)]);
      const Eigen::Vector3d p = camera_T_gate * Eigen::Vector3d(rays.p_gate.col(k));
      rays.normalized.col(k) = p.head<2>() / p.z();
    }
    return GateObservation::corners(t, 0, rays, poses[static_cast<size_t>(t)].inverse() * gate);
  }
};

/// The oracle graph by hand: fixed keyframe 100, nodes 201..203, gate 300; the pose observation at t = 1 and
/// the corner rays at t = 2, 3 (corners 0 and 1, then 0, 1 and 3).
Eigen::MatrixXd oracleInformation(const PartialScenario& s) {
  Graph graph;
  addOracleChain(graph, s.poses, s.steps);
  EXPECT_TRUE(addGateVertex(graph, 300, LandmarkModel::kPose, s.gate).ok());
  Result<GateEdgeMeasurement> m = attachObservationToNode(s.poseAt(1), Eigen::Isometry3d::Identity(), nullptr, LandmarkModel::kPose);
  EXPECT_TRUE(m.ok());
  EXPECT_TRUE(addGateEdge(graph, 201, 300, *m, nullptr).ok());
  const std::vector<std::vector<int>> seen = {{0, 1}, {0, 1, 3}};
  for (int t = 2; t <= 3; ++t) {
    addOracleCornerEdges(graph, 200 + t, 300, s.raysAt(t, seen[static_cast<size_t>(t - 2)]).corner_rays, forwardCamera(),
                         s.ray_sigma);
  }
  return denseMarginalInformation(graph, 300);
}

DistillationResult distilScenario(const PartialScenario& s, const LocalizerParams& params, bool with_rays) {
  const OdometryHistory history = makeHistory(s.poses, s.steps);
  TemporaryGraph temporary(params, nullptr);
  EXPECT_TRUE(temporary.addObservation(s.poseAt(1), s.poses[1], history).ok());
  if (with_rays) {
    EXPECT_TRUE(temporary.addObservation(s.raysAt(2, {0, 1}), s.poses[2], history).ok());
    EXPECT_TRUE(temporary.addObservation(s.raysAt(3, {0, 1, 3}), s.poses[3], history).ok());
  }
  return temporary.distil(4.0, s.poses[4], history);
}

TEST(PartialGateDistillation, AnchoredCornerRaysAddExactlyTheInformationOfTheirCornerEdges) {
  const PartialScenario s;
  const DistillationResult result = distilScenario(s, exactParams(LandmarkModel::kPose), true);
  ASSERT_EQ(result.gates.size(), 1u) << result.skip_reason;
  EXPECT_EQ(result.partial_used, 2);
  EXPECT_EQ(result.partial_unanchored, 0);
  EXPECT_EQ(result.gates[0].observations, 3);
  EXPECT_EQ(result.edges, 3 + 1 + 5);  // odometry chain, the pose observation, five corners
  EXPECT_LT(relativeDifference(result.gates[0].pose_information, oracleInformation(s)), 1e-8);
  EXPECT_LT((result.gates[0].node_T_gate.matrix() - (s.poses[4].inverse() * s.gate).matrix()).norm(), 1e-8);
  // More information than the pose observation alone, by a visible amount.
  const DistillationResult without = distilScenario(s, exactParams(LandmarkModel::kPose), false);
  ASSERT_EQ(without.gates.size(), 1u);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> gain(result.gates[0].pose_information - without.gates[0].pose_information);
  EXPECT_GT(gain.eigenvalues().minCoeff(), -1e-9 * without.gates[0].pose_information.norm());
  EXPECT_GT(gain.eigenvalues().maxCoeff(), 0.1 * without.gates[0].pose_information.norm());
}

TEST(PartialGateDistillation, TheBlockSolverAndTheGenericOptimizerGiveTheSameEdge) {
  const PartialScenario s;
  LocalizerParams generic = exactParams(LandmarkModel::kPose);
  generic.temp_solver = TemporarySolverKind::kGraph;
  const DistillationResult block = distilScenario(s, exactParams(LandmarkModel::kPose), true);
  const DistillationResult graph = distilScenario(s, generic, true);
  ASSERT_EQ(block.gates.size(), 1u);
  ASSERT_EQ(graph.gates.size(), 1u) << graph.skip_reason;
  EXPECT_LT(relativeDifference(block.gates[0].pose_information, graph.gates[0].pose_information), 1e-9);
}

TEST(PartialGateDistillation, RaysWithoutAPoseObservationOfTheirGateAreCountedUnanchored) {
  const PartialScenario s;
  const OdometryHistory history = makeHistory(s.poses, s.steps);
  TemporaryGraph temporary(exactParams(LandmarkModel::kPose), nullptr);
  GateObservation other = s.raysAt(2, {0, 1});
  other.gate_id = 7;  // no pose observation of gate 7 in the interval
  ASSERT_TRUE(temporary.addObservation(s.poseAt(1), s.poses[1], history).ok());
  ASSERT_TRUE(temporary.addObservation(other, s.poses[2], history).ok());
  ASSERT_TRUE(temporary.addObservation(s.raysAt(3, {0, 1, 3}), s.poses[3], history).ok());
  const DistillationResult result = temporary.distil(4.0, s.poses[4], history);
  ASSERT_EQ(result.gates.size(), 1u) << result.skip_reason;
  EXPECT_EQ(result.gates[0].gate_id, 0);
  EXPECT_EQ(result.partial_used, 1);
  EXPECT_EQ(result.partial_unanchored, 1);

  TemporaryGraph rays_only(exactParams(LandmarkModel::kPose), nullptr);
  ASSERT_TRUE(rays_only.addObservation(s.raysAt(2, {0, 1}), s.poses[2], history).ok());
  ASSERT_TRUE(rays_only.addObservation(s.raysAt(3, {0, 1, 3}), s.poses[3], history).ok());
  const DistillationResult none = rays_only.distil(4.0, s.poses[4], history);
  EXPECT_TRUE(none.gates.empty());
  EXPECT_EQ(none.partial_unanchored, 2);
  EXPECT_TRUE(rays_only.empty());
}

TEST(PartialGateDistillation, PointGatesAndTheSingleGraphRefuseCornerRaysWithAReason) {
  const PartialScenario s;
  const OdometryHistory history = makeHistory(s.poses, s.steps);
  TemporaryGraph points(exactParams(LandmarkModel::kPoint), nullptr);
  const Status refused = points.addObservation(s.raysAt(2, {0, 1}), s.poses[2], history);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.message().find("landmark: pose"), std::string::npos) << refused.message();

  LocalizerParams single;
  single.mode = LocalizerMode::kSingle;
  GateMap map;
  map.world_T_gate[0] = s.gate;
  auto localizer = Localizer::create(single, map);
  ASSERT_TRUE(localizer.ok()) << localizer.status().toString();
  OdometrySample sample;
  sample.t = 2.0;
  sample.odom_T_body = s.poses[2];
  ASSERT_TRUE((*localizer)->addOdometry(sample).ok());
  const Status rejected = (*localizer)->addObservation(s.raysAt(2, {0, 1}));
  EXPECT_EQ(rejected.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(rejected.message().find("corner rays"), std::string::npos) << rejected.message();
  EXPECT_EQ((*localizer)->counters().observations_rejected, 1);
}

TEST(PartialGateDistillation, InvalidCornerRaysAreRefusedNamingTheField) {
  const PartialScenario s;
  GateObservation one = s.raysAt(2, {0, 1});
  one.corner_rays.count = 1;
  EXPECT_NE(validateGateObservation(one).message().find("count"), std::string::npos);
  GateObservation nan = s.raysAt(2, {0, 1});
  nan.corner_rays.normalized(0, 1) = std::nan("");
  EXPECT_NE(validateGateObservation(nan).message().find("non-finite"), std::string::npos);
  GateObservation singular = s.raysAt(2, {0, 1});
  singular.corner_rays.covariance[1](0, 0) = 0.0;
  EXPECT_NE(validateGateObservation(singular).message().find("corner_rays.covariance[1]"), std::string::npos)
      << validateGateObservation(singular).message();
  GateObservation unused = s.raysAt(2, {0, 1});
  unused.corner_rays.covariance[3].setZero();  // past count: not read
  EXPECT_TRUE(validateGateObservation(unused).ok());
  EXPECT_TRUE(validateGateObservation(s.raysAt(3, {0, 1, 3})).ok());
}

}  // namespace
}  // namespace dualgraph
