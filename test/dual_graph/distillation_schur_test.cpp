// SPDX-License-Identifier: MIT
// The distilled information equals the exact marginal information of the temporary graph (dense Schur
// complement), odometry noise lowers it exactly as the closed form says, and the record refuses
// observations out of time order.
#include <gtest/gtest.h>

#include "dualgraph/dual_graph/gate_edge.h"
#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/temporary_graph.h"
#include "test/dual_graph/distillation_fixtures.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

/// A consistent temporary graph: odometry poses at t = 0..4 (keyframe at 4), two gates, observations at
/// `observation_times` (each its own node; an observation at t = 4 attaches to the keyframe), all
/// measurements generated from the truth so the optimum is the truth.
struct Scenario {
  std::vector<Eigen::Isometry3d> poses;
  std::vector<Matrix6d> step_covariances;
  std::vector<Eigen::Isometry3d> gates;
  std::vector<double> observation_times;
  Matrix6d observation_covariance = randomCovariance<6>(0.01);
  Eigen::Matrix3d point_covariance = randomCovariance<3>(0.02);

  explicit Scenario(std::vector<double> times) : observation_times(std::move(times)) {
    for (int k = 0; k < 5; ++k) {
      poses.push_back(k == 0 ? randomPose(1.0) : poses.back() * randomPose(0.8));
      step_covariances.push_back(randomCovariance<6>(0.004));
    }
    gates = {poses[2] * randomPose(3.0), poses[3] * randomPose(3.0)};
  }
  GateObservation observation(double t, int gate, LandmarkModel model) const {
    const Eigen::Isometry3d body_T_gate = poses[static_cast<size_t>(t)].inverse() * gates[gate];
    return model == LandmarkModel::kPose ? GateObservation::pose(t, gate, body_T_gate, observation_covariance)
                                         : GateObservation::position(t, gate, body_T_gate.translation(), point_covariance);
  }
};

/// The same graph built by hand through the public API (ids: keyframe first and fixed, then the nodes,
/// then the gates — a different order than the TemporaryGraph's), for the dense oracle.
void buildOracle(const Scenario& s, LandmarkModel model, Graph& graph, std::vector<int>& gate_ids) {
  auto pose_vertex = [&](int id, const Eigen::Isometry3d& pose, bool fixed) {
    auto v = std::make_unique<VertexSE3>(id);
    v->setEstimate(pose);
    v->setFixed(fixed);
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  };
  pose_vertex(100, s.poses[4], true);
  std::vector<int> node_id;
  for (double t : s.observation_times) node_id.push_back(t == 4.0 ? 100 : 200 + static_cast<int>(t));
  for (size_t j = 0; j < node_id.size(); ++j) {
    if (node_id[j] != 100) pose_vertex(node_id[j], s.poses[static_cast<size_t>(s.observation_times[j])], false);
  }
  for (size_t j = 0; j < node_id.size(); ++j) {
    const int from = node_id[j];
    const int to = j + 1 < node_id.size() ? node_id[j + 1] : 100;
    if (from == to) continue;
    const size_t a = static_cast<size_t>(s.observation_times[j]);
    const size_t b = j + 1 < node_id.size() ? static_cast<size_t>(s.observation_times[j + 1]) : 4;
    ASSERT_EQ(b, a + 1) << "the oracle composes single steps only";
    const Matrix6d information = informationMetricToG2o(s.step_covariances[b].inverse());
    ASSERT_TRUE(addRelativePoseEdge(graph, from, to, s.poses[a].inverse() * s.poses[b], information).ok());
  }
  gate_ids = {300, 301};
  for (int g = 0; g < 2; ++g) ASSERT_TRUE(addGateVertex(graph, gate_ids[g], model, s.gates[g]).ok());
  for (size_t j = 0; j < node_id.size(); ++j) {
    for (int g = 0; g < 2; ++g) {
      const GateObservation o = s.observation(s.observation_times[j], g, model);
      Result<GateEdgeMeasurement> m = attachObservationToNode(o, Eigen::Isometry3d::Identity(), nullptr, model);
      ASSERT_TRUE(m.ok());
      ASSERT_TRUE(addGateEdge(graph, node_id[j], gate_ids[g], *m, nullptr).ok());
    }
  }
}

void expectDistilledEqualsSchurComplement(LandmarkModel model, std::vector<double> times) {
  const Scenario s(times);
  const OdometryHistory history = makeHistory(s.poses, s.step_covariances);
  TemporaryGraph temporary(exactParams(model), nullptr);
  for (double t : s.observation_times) {
    for (int g = 0; g < 2; ++g) {
      ASSERT_TRUE(temporary.addObservation(s.observation(t, g, model), s.poses[static_cast<size_t>(t)], history).ok());
    }
  }
  const DistillationResult result = temporary.distil(4.0, s.poses[4], history);
  ASSERT_EQ(result.gates.size(), 2u) << result.skip_reason;
  Graph oracle;
  std::vector<int> gate_ids;
  buildOracle(s, model, oracle, gate_ids);
  for (int g = 0; g < 2; ++g) {
    const Eigen::MatrixXd schur = denseMarginalInformation(oracle, gate_ids[g]);
    const GateEdgeMeasurement& distilled = result.gates[g];
    ASSERT_EQ(distilled.gate_id, g);
    if (model == LandmarkModel::kPose) {
      EXPECT_LT(relativeDifference(distilled.pose_information, schur), 1e-9) << "gate " << g;
      EXPECT_LT((distilled.node_T_gate.matrix() - (s.poses[4].inverse() * s.gates[g]).matrix()).norm(), 1e-8);
    } else {
      // The point's marginal is in odometry axes; the distilled edge's error is in the keyframe's axes.
      const Eigen::Matrix3d R = s.poses[4].linear();
      EXPECT_LT(relativeDifference(distilled.point_information, R.transpose() * schur * R), 1e-9) << "gate " << g;
    }
  }
}

TEST(DistillationSchur, PoseGatesEqualTheDenseSchurComplementWithTheFixedKeyframeBetweenFreeVertices) {
  expectDistilledEqualsSchurComplement(LandmarkModel::kPose, {0, 1, 2, 3});
}

TEST(DistillationSchur, PoseGatesEqualTheDenseSchurComplementWhenAnObservationIsAtTheKeyframeInstant) {
  expectDistilledEqualsSchurComplement(LandmarkModel::kPose, {1, 2, 3, 4});
}

TEST(DistillationSchur, PointGatesEqualTheDenseSchurComplementRotatedIntoTheKeyframe) {
  expectDistilledEqualsSchurComplement(LandmarkModel::kPoint, {0, 1, 2, 3});
}

TEST(DistillationSchur, OdometryNoiseBetweenObservationAndKeyframeLowersTheInformationAsTheClosedFormSays) {
  const Eigen::Isometry3d node = randomPose(1.0);
  const Eigen::Isometry3d increment = randomPose(1.5);
  const Eigen::Isometry3d body_T_gate = randomPose(3.0);
  const Matrix6d observation_covariance = randomCovariance<6>(0.01);
  for (const double odometry_scale : {1e-4, 1e-2, 1.0}) {
    const Matrix6d odometry_covariance = randomCovariance<6>(odometry_scale);
    const OdometryHistory history = makeHistory({node, node * increment}, {Matrix6d::Zero(), odometry_covariance});
    TemporaryGraph temporary(exactParams(LandmarkModel::kPose), nullptr);
    ASSERT_TRUE(temporary.addObservation(GateObservation::pose(0.0, 5, body_T_gate, observation_covariance), node, history).ok());
    const DistillationResult result = temporary.distil(1.0, node * increment, history);
    ASSERT_EQ(result.gates.size(), 1u) << result.skip_reason;
    // L = K·inc⁻¹·z·exp(−Ad(z⁻¹·inc)ε_odom)·exp(ε_z): Σ_L = Ad Σ_odom Adᵀ + Σ_z (metric, exact to first order).
    const Matrix6d adjoint = se3Adjoint(body_T_gate.inverse() * increment);
    const Matrix6d expected_covariance = adjoint * odometry_covariance * adjoint.transpose() + observation_covariance;
    const Matrix6d expected = informationMetricToG2o(expected_covariance.inverse());
    EXPECT_LT(relativeDifference(result.gates[0].pose_information, expected), 1e-9) << "odometry scale " << odometry_scale;
    // Lower than the observation alone, in the Loewner order, and by a visible amount.
    const Matrix6d observation_only = informationMetricToG2o(observation_covariance.inverse());
    const Eigen::SelfAdjointEigenSolver<Matrix6d> difference(observation_only - result.gates[0].pose_information);
    EXPECT_GT(difference.eigenvalues().minCoeff(), -1e-9 * observation_only.norm());
    EXPECT_GT(difference.eigenvalues().maxCoeff(), 1e-6 * observation_only.norm());
  }
}

TEST(DistillationSchur, ObservationsOlderThanTheNewestNodeAreRefusedAndTheRecordStaysUsable) {
  const Scenario s({0, 1, 2, 3});
  const OdometryHistory history = makeHistory(s.poses, s.step_covariances);
  TemporaryGraph temporary(exactParams(LandmarkModel::kPose), nullptr);
  ASSERT_TRUE(temporary.addObservation(s.observation(2, 0, LandmarkModel::kPose), s.poses[2], history).ok());
  EXPECT_EQ(temporary.addObservation(s.observation(1, 0, LandmarkModel::kPose), s.poses[1], history).code(),
            StatusCode::kFailedPrecondition);
  EXPECT_EQ(temporary.numObservations(), 1u);
  const DistillationResult result = temporary.distil(4.0, s.poses[4], history);
  EXPECT_EQ(result.gates.size(), 1u);
  EXPECT_EQ(result.skipped_gates, 0);
}

}  // namespace
}  // namespace dualgraph
