// SPDX-License-Identifier: MIT
// The systematic-error floor on distilled gate edges: its shape by range and line of sight, its units in g2o's
// [t; q.vec] chart, and that distillation adds exactly it to the marginal covariance.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "dualgraph/dual_graph/systematic_floor.h"
#include "dualgraph/dual_graph/temporary_graph.h"
#include "test/dual_graph/distillation_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

TEST(SystematicFloor, GrowsWithRangeAlongAndAcrossTheLineOfSight) {
  const SystematicFloor floor{0.02, 0.01, 0.0};
  const Eigen::Vector3d p(3.0, 4.0, 0.0);  // 5 m away
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d cov = floorTranslationCovariance(floor, p, rotation);
  const Eigen::Vector3d along = rotation * p.normalized();
  const Eigen::Vector3d across1 = rotation * Eigen::Vector3d(-0.8, 0.6, 0.0);
  const Eigen::Vector3d across2 = rotation * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(along.dot(cov * along), 0.1 * 0.1, 1e-15);  // (0.02 · 5 m)²
  EXPECT_NEAR(across1.dot(cov * across1), 0.05 * 0.05, 1e-15);
  EXPECT_NEAR(across2.dot(cov * across2), 0.05 * 0.05, 1e-15);
  EXPECT_NEAR(along.dot(cov * across1), 0.0, 1e-15);
  // Twice the range, twice the σ.
  EXPECT_NEAR(along.dot(floorTranslationCovariance(floor, 2.0 * p, rotation) * along), 0.2 * 0.2, 1e-15);
  EXPECT_TRUE(floorTranslationCovariance(floor, Eigen::Vector3d::Zero(), rotation).isZero());
  EXPECT_FALSE(SystematicFloor{}.active());
}

TEST(SystematicFloor, PoseFloorIsTheMetricFloorInTheGateAxesAndHalfAngles) {
  const SystematicFloor floor{0.03, 0.01, 0.08};
  const Eigen::Isometry3d node_T_gate = randomPose(6.0);
  Matrix6d added = Matrix6d::Zero();
  addFloorToPoseCovariance(floor, node_T_gate, added);
  // Translation: the floor seen from the gate's axes; the line of sight is the gate centre's direction.
  const Eigen::Matrix3d gate_R_node = node_T_gate.linear().transpose();
  const Eigen::Vector3d sight = gate_R_node * node_T_gate.translation().normalized();
  const double range = node_T_gate.translation().norm();
  const Eigen::Matrix3d translation = added.topLeftCorner<3, 3>();
  const Eigen::Matrix3d rotation = added.bottomRightCorner<3, 3>();
  const Eigen::Matrix3d coupling = added.topRightCorner<3, 3>();
  EXPECT_NEAR(sight.dot(translation * sight), std::pow(0.03 * range, 2), 1e-12);
  EXPECT_NEAR(translation.trace(), std::pow(0.03 * range, 2) + 2.0 * std::pow(0.01 * range, 2), 1e-12);
  // Rotation in q.vec ≈ θ/2: σ² / 4 per axis, no coupling with the translation.
  EXPECT_LT((rotation - Eigen::Matrix3d::Identity() * (0.08 * 0.08 / 4.0)).norm(), 1e-15);
  EXPECT_TRUE(coupling.isZero());
}

TEST(SystematicFloor, DistillationAddsExactlyTheFloorToTheMarginal) {
  LocalizerParams params = exactParams(LandmarkModel::kPose);
  params.distilled_floor_range = 0.02;
  params.distilled_floor_lateral = 0.01;
  params.distilled_floor_rotation = 0.08;
  const Eigen::Isometry3d odom_T_keyframe = randomPose(3.0);
  const OdometryHistory history = makeHistory({randomPose(3.0), odom_T_keyframe}, {Matrix6d::Zero(), randomCovariance<6>(0.01)});
  const Eigen::Isometry3d body_T_gate = randomPose(8.0);
  const Matrix6d covariance = randomCovariance<6>(0.02);
  constexpr int kN = 12;
  TemporaryGraph temporary(params, nullptr);
  for (int k = 0; k < kN; ++k) {
    ASSERT_TRUE(temporary.addObservation(GateObservation::pose(1.0, 3, body_T_gate, covariance), odom_T_keyframe, history).ok());
  }
  const DistillationResult result = temporary.distil(1.0, odom_T_keyframe, history);
  ASSERT_EQ(result.gates.size(), 1u) << result.skip_reason;
  // Without the floor: N·Ω (Distillation.NIdenticalObservations…); with it, that covariance plus the floor.
  Matrix6d expected = (kN * informationMetricToG2o(covariance.inverse())).inverse();
  addFloorToPoseCovariance(SystematicFloor{0.02, 0.01, 0.08}, body_T_gate, expected);
  EXPECT_LT(relativeDifference(result.gates[0].pose_information.inverse(), expected), 1e-9);
  // The floor bounds the information whatever N: no direction more certain than the floor allows.
  const double range = body_T_gate.translation().norm();
  const Eigen::Matrix3d translation_cov = result.gates[0].pose_information.inverse().topLeftCorner<3, 3>();
  EXPECT_GE(translation_cov.eigenvalues().real().minCoeff(), std::pow(0.01 * range, 2) * (1.0 - 1e-9));
}

TEST(SystematicFloor, PointEdgesGetTheTranslationFloorInTheKeyframeAxes) {
  LocalizerParams params = exactParams(LandmarkModel::kPoint);
  params.distilled_floor_range = 0.02;
  params.distilled_floor_lateral = 0.01;
  const Eigen::Isometry3d odom_T_keyframe = randomPose(3.0);
  const OdometryHistory history = makeHistory({randomPose(1.0), odom_T_keyframe}, {Matrix6d::Zero(), randomCovariance<6>(0.01)});
  const Eigen::Matrix3d covariance = randomCovariance<3>(0.05);
  const Eigen::Vector3d p(9.0, -2.0, 1.5);
  constexpr int kN = 7;
  TemporaryGraph temporary(params, nullptr);
  for (int k = 0; k < kN; ++k) {
    ASSERT_TRUE(temporary.addObservation(GateObservation::position(1.0, 0, p, covariance), odom_T_keyframe, history).ok());
  }
  const DistillationResult result = temporary.distil(1.0, odom_T_keyframe, history);
  ASSERT_EQ(result.gates.size(), 1u) << result.skip_reason;
  const Eigen::Matrix3d expected =
      covariance / kN + floorTranslationCovariance(SystematicFloor{0.02, 0.01, 0.0}, p, Eigen::Matrix3d::Identity());
  EXPECT_LT(relativeDifference(result.gates[0].point_information.inverse(), expected), 1e-9);
}

}  // namespace
}  // namespace dualgraph
