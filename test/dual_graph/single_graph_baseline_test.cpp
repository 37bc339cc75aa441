// SPDX-License-Identifier: MIT
// SingleGraphBaseline on its own: a node due before a detection d_single away, the detections between nodes left
// out with single_all_detections false, motion compensation, and edges owned by the node before the newest.
#include <gtest/gtest.h>

#include "dualgraph/dual_graph/single_graph_baseline.h"
#include "dualgraph/dual_graph/temporary_graph.h"

namespace dualgraph {
namespace {

// A VIO flying along x at 4 m/s, a sample every 0.1 s up to 1 s; a gate 6 m ahead of the start.
struct BaselineFlight {
  LocalizerParams params;
  GateMap map;
  OdometryHistory history;
  Matrix6d detection_covariance = Matrix6d::Zero();

  BaselineFlight() {
    params.mode = LocalizerMode::kSingle;
    Eigen::Isometry3d world_T_gate = Eigen::Isometry3d::Identity();
    world_T_gate.translation() << 6.0, 0.0, 1.5;
    map.world_T_gate[0] = world_T_gate;
    for (int k = 0; k <= 10; ++k) history.push(sampleAt(0.1 * k));
    detection_covariance.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 3e-4, 3e-4, 3e-4;
  }
  static OdometrySample sampleAt(double t) {
    OdometrySample sample;
    sample.t = t;
    sample.odom_T_body.translation() << 4.0 * t, 0.0, 0.0;
    return sample;
  }
  /// The gate (at 6, 0, 1.5 in the odometry frame, which is the world here) seen exactly from the body at t.
  GateObservation detectionAt(double t) const {
    return GateObservation::pose(t, 0, sampleAt(t).odom_T_body.inverse() * map.world_T_gate.at(0), detection_covariance);
  }
  std::unique_ptr<MainGraph> mainGraphWithFirstNode() const {
    auto main = std::make_unique<MainGraph>(params, map, nullptr);
    EXPECT_TRUE(main->addFirstKeyframe(0.0, Eigen::Isometry3d::Identity()).ok());
    return main;
  }
  /// Adds the next node at t, as the Localizer does once the baseline says one is due.
  void addNode(MainGraph& main, double t) const {
    const Result<Matrix6d> covariance = history.relativeCovariance(main.keyframes().back().t, t, noiseModelOf(params));
    ASSERT_TRUE(covariance.ok()) << covariance.status().toString();
    ASSERT_TRUE(main.addKeyframe(t, sampleAt(t).odom_T_body, *covariance).ok());
  }
};

TEST(SingleGraphBaseline, ANodeIsDueBeforeADetectionDSingleOrThetaSingleAwayAndNeverAfterOdometry) {
  BaselineFlight flight;
  flight.params.d_single = 2.0;
  const SingleGraphBaseline baseline(flight.params);
  const std::unique_ptr<MainGraph> main = flight.mainGraphWithFirstNode();
  // 1.6 m and 2.4 m from the node at the origin.
  EXPECT_FALSE(baseline.keyframeDueBefore(0.4, BaselineFlight::sampleAt(0.4).odom_T_body, *main));
  EXPECT_TRUE(baseline.keyframeDueBefore(0.6, BaselineFlight::sampleAt(0.6).odom_T_body, *main));
  // Not at the node's own instant, however far the pose.
  EXPECT_FALSE(baseline.keyframeDueBefore(0.0, BaselineFlight::sampleAt(0.6).odom_T_body, *main));
  // A turn past theta_single in place.
  const Eigen::Isometry3d turned(Eigen::AngleAxisd(flight.params.theta_single + 0.01, Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(baseline.keyframeDueBefore(0.1, turned, *main));
  // Nodes come with detections only, and finish adds none.
  EXPECT_FALSE(baseline.keyframeDueAfter(BaselineFlight::sampleAt(1.0), *main));
  EXPECT_FALSE(baseline.keyframeAtFinish());
}

TEST(SingleGraphBaseline, WithoutAllDetectionsOnlyTheNodesOwnInstantBecomesAnEdge) {
  BaselineFlight flight;
  flight.params.single_all_detections = false;
  SingleGraphBaseline baseline(flight.params);
  const std::unique_ptr<MainGraph> main = flight.mainGraphWithFirstNode();
  Result<ObservationUse> at_node =
      baseline.addObservation(flight.detectionAt(0.0), Eigen::Isometry3d::Identity(), *main, flight.history);
  ASSERT_TRUE(at_node.ok()) << at_node.status().toString();
  EXPECT_EQ(*at_node, ObservationUse::kCollected);
  for (double t : {0.1, 0.2, 0.3}) {
    Result<ObservationUse> between =
        baseline.addObservation(flight.detectionAt(t), BaselineFlight::sampleAt(t).odom_T_body, *main, flight.history);
    ASSERT_TRUE(between.ok()) << between.status().toString();
    EXPECT_EQ(*between, ObservationUse::kBetweenNodes);
  }
  EXPECT_EQ(baseline.numObservations(), 1u);
}

TEST(SingleGraphBaseline, ADetectionAfterItsNodeIsMotionCompensated) {
  BaselineFlight flight;
  SingleGraphBaseline baseline(flight.params);
  const std::unique_ptr<MainGraph> main = flight.mainGraphWithFirstNode();
  ASSERT_TRUE(baseline.addObservation(flight.detectionAt(0.0), Eigen::Isometry3d::Identity(), *main, flight.history).ok());
  const Result<ObservationUse> later =
      baseline.addObservation(flight.detectionAt(0.3), BaselineFlight::sampleAt(0.3).odom_T_body, *main, flight.history);
  ASSERT_TRUE(later.ok()) << later.status().toString();
  EXPECT_EQ(*later, ObservationUse::kCollected);
  const ClosingEdges closing = baseline.handOverEdges(*main, false, flight.history);
  ASSERT_EQ(closing.edges.size(), 2u);
  // Both re-expressed at the node: the gate where the map has it (exact detections, exact VIO).
  for (const GateEdgeMeasurement& edge : closing.edges) {
    EXPECT_TRUE(edge.node_T_gate.isApprox(flight.map.world_T_gate.at(0), 1e-12));
  }
  // The odometry from the node to the detection's instant (1.2 m) makes the later edge less certain.
  EXPECT_LT(closing.edges[1].pose_information.trace(), 0.99 * closing.edges[0].pose_information.trace());
}

TEST(SingleGraphBaseline, TheEdgesHandedOverAreTheNodeBeforeTheNewOnesOrTheNewestAtFinish) {
  BaselineFlight flight;
  SingleGraphBaseline baseline(flight.params);
  const std::unique_ptr<MainGraph> main = flight.mainGraphWithFirstNode();
  for (double t : {0.0, 0.2, 0.4}) {
    ASSERT_TRUE(
        baseline.addObservation(flight.detectionAt(t), BaselineFlight::sampleAt(t).odom_T_body, *main, flight.history).ok());
  }
  ASSERT_TRUE(baseline.keyframeDueBefore(0.6, BaselineFlight::sampleAt(0.6).odom_T_body, *main));
  flight.addNode(*main, 0.6);
  const ClosingEdges first = baseline.handOverEdges(*main, true, flight.history);
  EXPECT_EQ(first.owner, 0u);  // the node at 0, not the new one at 0.6
  EXPECT_EQ(first.edges.size(), 3u);
  EXPECT_EQ(first.observations, 3);
  EXPECT_EQ(first.temp_nodes, 0);  // no distillation
  EXPECT_EQ(baseline.numObservations(), 0u);

  ASSERT_TRUE(
      baseline.addObservation(flight.detectionAt(0.7), BaselineFlight::sampleAt(0.7).odom_T_body, *main, flight.history).ok());
  const ClosingEdges last = baseline.handOverEdges(*main, false, flight.history);  // finish: no node added
  EXPECT_EQ(last.owner, 1u);
  ASSERT_EQ(last.edges.size(), 1u);
  // Relative to the node at 0.6: the gate 6 - 2.4 m ahead.
  EXPECT_NEAR(last.edges[0].node_T_gate.translation().x(), 6.0 - 2.4, 1e-9);

  // A new main graph: what was collected is forgotten.
  ASSERT_TRUE(
      baseline.addObservation(flight.detectionAt(0.8), BaselineFlight::sampleAt(0.8).odom_T_body, *main, flight.history).ok());
  EXPECT_EQ(baseline.numObservations(), 1u);
  baseline.clear();
  EXPECT_EQ(baseline.numObservations(), 0u);
  EXPECT_TRUE(baseline.handOverEdges(*main, false, flight.history).edges.empty());
}

}  // namespace
}  // namespace dualgraph
