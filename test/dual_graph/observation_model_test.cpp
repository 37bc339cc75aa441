// SPDX-License-Identifier: MIT
// The observation models: each kind's motion compensation against numeric differentiation, which settings can use
// it, whether it anchors its gate, and the one table of kinds (an unknown kind is refused, never read as a pose).
#include <gtest/gtest.h>

#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/observation_model.h"
#include "dualgraph/types/se3_covariance.h"
#include "test/dual_graph/distillation_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

constexpr double kStep = 1e-6;

/// A node a little behind the body (the increment since the node's instant) and its covariance.
struct Compensation {
  Eigen::Isometry3d node_T_body = se3Exp((Vector6d() << 0.3, -0.1, 0.05, 0.02, -0.04, 0.1).finished());
  Matrix6d covariance = randomCovariance<6>(0.01);
  NodeAttachment at() const {
    NodeAttachment attachment;
    attachment.node_T_body = node_T_body;
    attachment.compensation = &covariance;
    return attachment;
  }
};

/// d f(node_T_body · exp(ε)) / dε by central differences, f returning an M-vector.
template <int M, typename F>
Eigen::Matrix<double, M, 6> numericJacobian(const Eigen::Isometry3d& node_T_body, F f) {
  Eigen::Matrix<double, M, 6> jacobian;
  for (int i = 0; i < 6; ++i) {
    Vector6d step = Vector6d::Zero();
    step[i] = kStep;
    jacobian.col(i) = (f(node_T_body * se3Exp(step)) - f(node_T_body * se3Exp(-step))) / (2.0 * kStep);
  }
  return jacobian;
}

Eigen::Isometry3d gateAhead() {
  return se3Exp((Vector6d() << 6.0, 0.8, -0.4, 0.05, 0.1, -0.2).finished());
}

TEST(ObservationModel, PoseCompensationIsTheAdjointOfTheIncrementCovariance) {
  const Compensation c;
  const GateObservation o = GateObservation::pose(1.0, 3, gateAhead(), randomCovariance<6>(0.001));
  Result<AttachedObservation> attached = observationModel(o.kind).attach(o, c.at(), LandmarkModel::kPose);
  ASSERT_TRUE(attached.ok()) << attached.status().message();
  const Eigen::Isometry3d nominal = c.node_T_body * o.body_T_gate;
  const Matrix6d J = numericJacobian<6>(c.node_T_body, [&](const Eigen::Isometry3d& node_T_body) {
    return se3Log(nominal.inverse() * node_T_body * o.body_T_gate);  // right perturbation in the gate frame
  });
  Result<Matrix6d> expected =
      poseInformationFromMetricCovariance(Matrix6d(o.pose_covariance + J * c.covariance * J.transpose()), "expected");
  ASSERT_TRUE(expected.ok());
  EXPECT_LT(relativeDifference(attached->edge.pose_information, *expected), 1e-6);
  EXPECT_TRUE(attached->edge.node_T_gate.isApprox(nominal, 1e-12));
  EXPECT_EQ(attached->edge.model, LandmarkModel::kPose);
}

TEST(ObservationModel, CentreCompensationMatchesNumericDifferentiationForPoseAndPosition) {
  const Compensation c;
  const GateObservation pose = GateObservation::pose(1.0, 3, gateAhead(), randomCovariance<6>(0.001));
  const GateObservation position =
      GateObservation::position(1.0, 3, gateAhead().translation(), randomCovariance<3>(0.002));
  for (const GateObservation& o : {pose, position}) {
    Result<AttachedObservation> attached = observationModel(o.kind).attach(o, c.at(), LandmarkModel::kPoint);
    ASSERT_TRUE(attached.ok()) << attached.status().message();
    const Eigen::Vector3d p_body = o.centreInBody();
    const Eigen::Matrix<double, 3, 6> J = numericJacobian<3>(
        c.node_T_body, [&](const Eigen::Isometry3d& node_T_body) { return Eigen::Vector3d(node_T_body * p_body); });
    const Eigen::Matrix3d rotation = c.node_T_body.linear();
    const Eigen::Matrix3d expected =
        rotation * o.centreCovarianceInBody() * rotation.transpose() + J * c.covariance * J.transpose();
    EXPECT_LT(relativeDifference(attached->edge.point_information.inverse(), expected), 1e-6) << observationModel(o.kind).name();
    EXPECT_TRUE(attached->edge.p_node.isApprox(c.node_T_body * p_body, 1e-12));
    EXPECT_EQ(attached->edge.model, LandmarkModel::kPoint);
  }
}

TEST(ObservationModel, CornerRayCompensationMatchesNumericDifferentiation) {
  const Compensation c;
  GateCornerRays rays;
  rays.count = 3;
  rays.p_gate << 0, 0, 0, 0, 0.75, -0.75, -0.75, 0.75, 0.75, 0.75, -0.75, -0.75;
  rays.body_T_camera.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // looking along the body's x axis
  rays.body_T_camera.translation() << 0.05, 0.0, 0.02;
  const Eigen::Isometry3d body_T_gate = gateAhead();
  for (int k = 0; k < rays.count; ++k) {
    const Eigen::Vector3d p = rays.body_T_camera.inverse() * (body_T_gate * Eigen::Vector3d(rays.p_gate.col(k)));
    rays.normalized.col(k) = p.head<2>() / p.z();
    rays.covariance[static_cast<size_t>(k)] = randomCovariance<2>(1e-6);
  }
  const GateObservation o = GateObservation::corners(1.0, 3, rays, body_T_gate);
  const ObservationModel& model = observationModel(o.kind);
  Result<AttachedObservation> attached = model.attach(o, c.at(), LandmarkModel::kPose);
  ASSERT_TRUE(attached.ok()) << attached.status().message();
  EXPECT_TRUE(attached->rays.body_T_camera.isApprox(c.node_T_body * rays.body_T_camera, 1e-12));
  for (int k = 0; k < rays.count; ++k) {
    // The corner as the camera of a body moved by ε from the node would see it (the node's frame held still).
    const Eigen::Vector3d p_node = c.node_T_body * (body_T_gate * Eigen::Vector3d(rays.p_gate.col(k)));
    const Eigen::Matrix<double, 2, 6> J = numericJacobian<2>(c.node_T_body, [&](const Eigen::Isometry3d& node_T_body) {
      const Eigen::Vector3d p = (node_T_body * rays.body_T_camera).inverse() * p_node;
      return Eigen::Vector2d(p.head<2>() / p.z());
    });
    const Eigen::Matrix2d expected = rays.covariance[static_cast<size_t>(k)] + J * c.covariance * J.transpose();
    EXPECT_LT(relativeDifference(attached->ray_information[static_cast<size_t>(k)].inverse(), expected), 1e-6) << k;
  }
}

TEST(ObservationModel, AtTheNodesOwnInstantNothingIsAdded) {
  const GateObservation o = GateObservation::pose(1.0, 3, gateAhead(), randomCovariance<6>(0.001));
  Result<AttachedObservation> attached = observationModel(o.kind).attach(o, NodeAttachment{}, LandmarkModel::kPose);
  ASSERT_TRUE(attached.ok());
  Result<Matrix6d> own = poseInformationFromMetricCovariance(o.pose_covariance, "own");
  ASSERT_TRUE(own.ok());
  EXPECT_LT(relativeDifference(attached->edge.pose_information, *own), 1e-12);
}

TEST(ObservationModel, EachKindSaysWhichSettingsCanUseItAndWhetherItAnchorsItsGate) {
  LocalizerParams dual_pose;
  LocalizerParams dual_point;
  dual_point.landmark = LandmarkModel::kPoint;
  LocalizerParams single_pose;
  single_pose.mode = LocalizerMode::kSingle;
  const ObservationModel& pose = observationModel(ObservationKind::kPose);
  const ObservationModel& position = observationModel(ObservationKind::kPosition);
  const ObservationModel& corners = observationModel(ObservationKind::kCorners);
  for (const LocalizerParams* params : {&dual_pose, &dual_point, &single_pose}) EXPECT_TRUE(pose.checkUsable(*params, "o").ok());
  EXPECT_FALSE(position.checkUsable(dual_pose, "o").ok());
  EXPECT_TRUE(position.checkUsable(dual_point, "o").ok());
  EXPECT_TRUE(corners.checkUsable(dual_pose, "o").ok());
  EXPECT_FALSE(corners.checkUsable(dual_point, "o").ok());
  EXPECT_FALSE(corners.checkUsable(single_pose, "o").ok());
  EXPECT_TRUE(pose.anchorsGate());
  EXPECT_TRUE(position.anchorsGate());
  EXPECT_FALSE(corners.anchorsGate());
  EXPECT_STREQ(pose.name(), "pose");
  EXPECT_STREQ(position.name(), "position");
  EXPECT_STREQ(corners.name(), "corners");
  for (ObservationKind kind : {ObservationKind::kPose, ObservationKind::kPosition, ObservationKind::kCorners}) {
    EXPECT_EQ(observationModel(kind).kind(), kind);
  }
  // A position cannot constrain an SE(3) landmark: refused, not attached as something else.
  const GateObservation o = GateObservation::position(1.0, 3, Eigen::Vector3d(5, 0, 0), Eigen::Matrix3d::Identity() * 0.01);
  Result<AttachedObservation> refused = position.attach(o, NodeAttachment{}, LandmarkModel::kPose);
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
}

TEST(ObservationModel, AnUnknownKindIsRefusedNotReadAsAPose) {
  GateObservation o = GateObservation::pose(1.0, 3, gateAhead(), randomCovariance<6>(0.001));
  o.kind = static_cast<ObservationKind>(7);
  EXPECT_EQ(findObservationModel(o.kind), nullptr);
  const Status status = validateGateObservation(o);
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(status.message().find("unknown kind 7"), std::string::npos) << status.message();
}

}  // namespace
}  // namespace dualgraph
