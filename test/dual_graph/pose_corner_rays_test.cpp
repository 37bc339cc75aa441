// SPDX-License-Identifier: MIT
// A pose observation that carries the four corners it was solved from: the temporary graph fits the gate to the
// rays (exactly the information of their corner edges, the pose only the first estimate, so a biased pose does
// not move the distilled edge); such observations are validated, turned with their gate frame consistently; and
// the per-metre odometry model's yaw and tilt.
#include <gtest/gtest.h>

#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/odometry_history.h"
#include "dualgraph/dual_graph/temporary_graph.h"
#include "test/dual_graph/distillation_fixtures.h"
#include "dualgraph/types/edge_se3_corner_projection.h"
#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

Eigen::Isometry3d cameraAlongX() {  // looking along the body's x axis
  Eigen::Isometry3d body_T_camera = Eigen::Isometry3d::Identity();
  body_T_camera.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  body_T_camera.translation() << 0.05, 0.0, 0.02;
  return body_T_camera;
}

/// Poses t = 0..4 flying towards a 1.5 m gate 9 m ahead (keyframe at 4); pose observations at t = 1..3, each
/// with its four corners' exact rays, and a pose `range_error` too near (a PnP's short range).
struct RaysScenario : GateApproach {
  double ray_sigma = 2.0 / 450.0;  // 2 px at f = 450 px
  GateObservation at(int t, double range_error) const {
    const Eigen::Isometry3d body_T_gate = poses[static_cast<size_t>(t)].inverse() * gate;
    Eigen::Isometry3d biased = body_T_gate;
    biased.translation() *= 1.0 - range_error / body_T_gate.translation().norm();
    GateObservation o = GateObservation::pose(t, 0, biased, randomCovariance<6>(0.01));
    GateCornerRays& rays = o.corner_rays;
    rays.count = 4;
    rays.body_T_camera = cameraAlongX();
    rays.p_gate << 0, 0, 0, 0, 0.75, -0.75, -0.75, 0.75, 0.75, 0.75, -0.75, -0.75;
    for (Eigen::Matrix2d& covariance : rays.covariance) covariance = ray_sigma * ray_sigma * Eigen::Matrix2d::Identity();
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d p = cameraAlongX().inverse() * (body_T_gate * Eigen::Vector3d(rays.p_gate.col(k)));
      rays.normalized.col(k) = p.head<2>() / p.z();
    }
    return o;
  }
};

/// The oracle by hand: fixed keyframe 100, nodes 201..203 on the odometry, gate 300, twelve corner edges.
Eigen::MatrixXd raysOracleInformation(const RaysScenario& s) {
  Graph graph;
  addOracleChain(graph, s.poses, s.steps);
  EXPECT_TRUE(addGateVertex(graph, 300, LandmarkModel::kPose, s.gate).ok());
  for (int t = 1; t <= 3; ++t) addOracleCornerEdges(graph, 200 + t, 300, s.at(t, 0.0).corner_rays, cameraAlongX(), s.ray_sigma);
  return denseMarginalInformation(graph, 300);
}

TEST(PoseCornerRays, TheGateIsFittedToTheRaysAndABiasedPoseOnlyStartsIt) {
  const RaysScenario s;
  const OdometryHistory history = makeHistory(s.poses, s.steps);
  TemporaryGraph temporary(exactParams(LandmarkModel::kPose), nullptr);
  for (int t = 1; t <= 3; ++t) {
    const GateObservation o = s.at(t, 0.3);  // every pose 0.3 m short
    ASSERT_TRUE(validateGateObservation(o).ok()) << validateGateObservation(o).message();
    ASSERT_TRUE(temporary.addObservation(o, s.poses[static_cast<size_t>(t)], history).ok());
  }
  const DistillationResult result = temporary.distil(4.0, s.poses[4], history);
  ASSERT_EQ(result.gates.size(), 1u) << result.skip_reason;
  EXPECT_EQ(result.gates[0].observations, 3);
  EXPECT_EQ(result.edges, 3 + 12);  // the odometry chain and four corners per observation, no pose edge
  const Eigen::Isometry3d truth = s.poses[4].inverse() * s.gate;
  EXPECT_LT((result.gates[0].node_T_gate.translation() - truth.translation()).norm(), 1e-7);
  EXPECT_LT(relativeDifference(result.gates[0].pose_information, raysOracleInformation(s)), 1e-6);

  // The same observations without their rays: the edge is the poses', 0.3 m short.
  TemporaryGraph poses_only(exactParams(LandmarkModel::kPose), nullptr);
  for (int t = 1; t <= 3; ++t) {
    GateObservation o = s.at(t, 0.3);
    o.corner_rays.count = 0;
    ASSERT_TRUE(poses_only.addObservation(o, s.poses[static_cast<size_t>(t)], history).ok());
  }
  const DistillationResult biased = poses_only.distil(4.0, s.poses[4], history);
  ASSERT_EQ(biased.gates.size(), 1u);
  EXPECT_GT((biased.gates[0].node_T_gate.translation() - truth.translation()).norm(), 0.1);
}

TEST(PoseCornerRays, APoseCarriesNoneOrAllFourCornersValid) {
  const RaysScenario s;
  GateObservation three = s.at(1, 0.0);
  three.corner_rays.count = 3;
  const Status refused = validateGateObservation(three);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.message().find("corner_rays.count 3 on a pose"), std::string::npos) << refused.message();
  GateObservation nan = s.at(1, 0.0);
  nan.corner_rays.normalized(1, 2) = std::nan("");
  EXPECT_NE(validateGateObservation(nan).message().find("corner_rays.has a non-finite"), std::string::npos)
      << validateGateObservation(nan).message();
  GateObservation none = s.at(1, 0.0);
  none.corner_rays.count = 0;
  none.corner_rays.normalized(1, 2) = std::nan("");  // not carried: not read
  EXPECT_TRUE(validateGateObservation(none).ok());
}

TEST(PoseCornerRays, TurningTheGateFrameKeepsTheCornersWhereTheyAreSeen) {
  const RaysScenario s;
  const GateObservation o = s.at(2, 0.0);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                               Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const GateObservation turned = inTurnedGateFrame(o, turn);
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d before = o.body_T_gate * Eigen::Vector3d(o.corner_rays.p_gate.col(k));
    const Eigen::Vector3d after = turned.body_T_gate * Eigen::Vector3d(turned.corner_rays.p_gate.col(k));
    EXPECT_LT((before - after).norm(), 1e-12) << k;
    EXPECT_EQ(turned.corner_rays.normalized.col(k), o.corner_rays.normalized.col(k));
  }
  // The covariance turns with the frame: a perturbation ε in the old frame is Ad(turn⁻¹) ε in the new one.
  Eigen::Isometry3d gate_T_turned = Eigen::Isometry3d::Identity();
  gate_T_turned.linear() = turn;
  const Matrix6d adjoint = se3Adjoint(gate_T_turned.inverse());
  EXPECT_LT(relativeDifference(turned.pose_covariance, adjoint * o.pose_covariance * adjoint.transpose()), 1e-14);
  EXPECT_TRUE(validateGateObservation(turned).ok());
}

TEST(OdometryModel, YawIsAboutTheOdometryVerticalAndTiltAboutItsHorizontalAxes) {
  OdometryNoiseModel model;
  model.sigma_t = 0.05;
  model.sigma_r = 0.01;
  model.sigma_tilt = 0.001;
  Eigen::Isometry3d increment = Eigen::Isometry3d::Identity();
  increment.translation() << 3.0, 4.0, 0.0;  // 5 m
  const Eigen::Vector3d up = Eigen::Vector3d(0.3, -0.2, 0.9).normalized();  // the odometry's z in a tilted body
  const Matrix6d covariance = odometryModelCovariance(increment, up, model);
  EXPECT_NEAR(covariance(0, 0), 0.05 * 0.05 * 5.0, 1e-15);
  EXPECT_TRUE((covariance.topRightCorner<3, 3>().isZero(0.0)));
  const Eigen::Matrix3d rotation = covariance.bottomRightCorner<3, 3>();
  EXPECT_NEAR(up.dot(rotation * up), 0.01 * 0.01 * 5.0, 1e-15);
  const Eigen::Vector3d across = up.cross(Eigen::Vector3d::UnitX()).normalized();
  const Eigen::Vector3d third = up.cross(across);
  EXPECT_NEAR(across.dot(rotation * across), 0.001 * 0.001 * 5.0, 1e-15);
  EXPECT_NEAR(third.dot(rotation * third), 0.001 * 0.001 * 5.0, 1e-15);
  EXPECT_NEAR(up.dot(rotation * across), 0.0, 1e-15);
  // Equal sigmas: the isotropic model; a hover: the floor distance.
  model.sigma_tilt = model.sigma_r;
  EXPECT_LT((odometryModelCovariance(Eigen::Isometry3d::Identity(), up, model).bottomRightCorner<3, 3>() -
             Eigen::Matrix3d::Identity() * (0.01 * 0.01 * model.min_distance)).norm(), 1e-18);
}

TEST(OdometryModel, TheHistoryTakesTheVerticalFromTheIncrementsEnd) {
  // A body rolled 90° about x at the end of the increment: the odometry's z is the body's +y there (R⁻¹ z).
  std::vector<Eigen::Isometry3d> poses(2, Eigen::Isometry3d::Identity());
  poses[1].translation() << 2.0, 0.0, 0.0;
  poses[1].linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  OdometryHistory history;
  for (size_t k = 0; k < 2; ++k) {
    OdometrySample sample;
    sample.t = static_cast<double>(k);
    sample.odom_T_body = poses[k];
    history.push(sample);  // no input covariance: the per-metre model
  }
  OdometryNoiseModel model;
  model.sigma_r = 0.01;
  model.sigma_tilt = 0.001;
  Result<Matrix6d> covariance = history.relativeCovariance(0.0, 1.0, model);
  ASSERT_TRUE(covariance.ok());
  const Eigen::Vector3d up_in_body = poses[1].linear().transpose() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(up_in_body.dot(covariance->bottomRightCorner<3, 3>() * up_in_body), 0.01 * 0.01 * 2.0, 1e-15);
  EXPECT_NEAR((*covariance)(3, 3), 0.001 * 0.001 * 2.0, 1e-15);  // body x stays horizontal
}

}  // namespace
}  // namespace dualgraph
