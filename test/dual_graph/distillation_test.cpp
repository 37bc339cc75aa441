// SPDX-License-Identifier: MIT
// The compressed edge, verified with numbers (issue 3 §3): N·Ω, the exact Schur complement of the
// temporary graph's Hessian, the odometry's share in closed form, fixed vertices anywhere.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "dualgraph/dual_graph/edge_factories.h"
#include "test/dual_graph/distillation_fixtures.h"
#include "dualgraph/dual_graph/temporary_graph.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

TEST(Distillation, NIdenticalObservationsFromTheFixedKeyframeGiveNTimesTheirInformation) {
  const LocalizerParams params = exactParams(LandmarkModel::kPose);
  const Eigen::Isometry3d odom_T_keyframe = randomPose(3.0);
  const OdometryHistory history = makeHistory({randomPose(3.0), odom_T_keyframe}, {Matrix6d::Zero(), randomCovariance<6>(0.01)});
  const Eigen::Isometry3d body_T_gate = randomPose(4.0);
  const Matrix6d covariance = randomCovariance<6>(0.02);
  for (const int n : {1, 2, 5, 17}) {
    TemporaryGraph temporary(params, nullptr);
    for (int k = 0; k < n; ++k) {
      ASSERT_TRUE(temporary.addObservation(GateObservation::pose(1.0, 3, body_T_gate, covariance), odom_T_keyframe, history).ok());
    }
    const DistillationResult result = temporary.distil(1.0, odom_T_keyframe, history);
    ASSERT_EQ(result.gates.size(), 1u) << result.skip_reason;
    EXPECT_EQ(result.gates[0].observations, n);
    EXPECT_EQ(result.nodes, 1);  // the observations were taken at the keyframe instant: they attach to it
    const Matrix6d expected = n * informationMetricToG2o(covariance.inverse());
    EXPECT_LT(relativeDifference(result.gates[0].pose_information, expected), 1e-9) << "n = " << n;
    EXPECT_LT((result.gates[0].node_T_gate.matrix() - body_T_gate.matrix()).norm(), 1e-9);
  }
}

TEST(Distillation, NNoisyPointObservationsGiveNTimesTheirInformationAndTheirMean) {
  const LocalizerParams params = exactParams(LandmarkModel::kPoint);
  const Eigen::Isometry3d odom_T_keyframe = randomPose(3.0);
  const OdometryHistory history = makeHistory({randomPose(1.0), odom_T_keyframe}, {Matrix6d::Zero(), randomCovariance<6>(0.01)});
  const Eigen::Matrix3d covariance = randomCovariance<3>(0.05);
  TemporaryGraph temporary(params, nullptr);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  constexpr int kN = 9;
  std::normal_distribution<double> normal(0.0, 0.2);
  for (int k = 0; k < kN; ++k) {
    const Eigen::Vector3d p(4.0 + normal(distillationRng()), -1.0 + normal(distillationRng()), 0.5 + normal(distillationRng()));
    sum += p;
    ASSERT_TRUE(temporary.addObservation(GateObservation::position(1.0, 0, p, covariance), odom_T_keyframe, history).ok());
  }
  const DistillationResult result = temporary.distil(1.0, odom_T_keyframe, history);
  ASSERT_EQ(result.gates.size(), 1u) << result.skip_reason;
  EXPECT_LT(relativeDifference(result.gates[0].point_information, kN * covariance.inverse()), 1e-9);
  EXPECT_LT((result.gates[0].p_node - sum / kN).norm(), 1e-9) << "iterations " << result.iterations;
}

}  // namespace
}  // namespace dualgraph
