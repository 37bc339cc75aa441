// SPDX-License-Identifier: MIT
// MainGraph called directly with parameters no validation saw (a σ whose square underflows to 0): the prior that cannot
// be built is refused with its name, and the graph is left as it was, so the next call meets the same error.
#include <gtest/gtest.h>

#include <cmath>

#include "dualgraph/dual_graph/main_graph.h"

namespace dualgraph {
namespace main_graph_errors {

GateMap oneGateMap() {
  GateMap map;
  map.world_T_gate[7] = Eigen::Isometry3d(Eigen::Translation3d(4.0, 0.0, 1.5));
  return map;
}

GateEdgeMeasurements sightingOfGate7(LandmarkModel model) {
  GateEdgeMeasurement measurement;
  measurement.gate_id = 7;
  measurement.model = model;
  measurement.node_T_gate = Eigen::Isometry3d(Eigen::Translation3d(4.0, 0.0, 1.5));
  measurement.p_node = measurement.node_T_gate.translation();
  return GateEdgeMeasurements{measurement};
}

TEST(MainGraphErrors, AFirstKeyframeWhosePriorFailsLeavesNoVertex) {
  LocalizerParams params;
  params.initial_sigma_t = 1e-200;
  const GateMap map = oneGateMap();
  MainGraph graph(params, map, nullptr);
  for (int attempt = 0; attempt < 2; ++attempt) {
    const Status status = graph.addFirstKeyframe(0.0, Eigen::Isometry3d::Identity());
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.message().find("initial pose prior"), std::string::npos) << status.message();
    EXPECT_EQ(graph.graph().numVertices(), 0u) << "attempt " << attempt;
    EXPECT_TRUE(graph.keyframes().empty());
  }
}

TEST(MainGraphErrors, AMapGateWhosePriorFailsIsNotLeftInTheGraph) {
  for (LandmarkModel model : {LandmarkModel::kPose, LandmarkModel::kPoint}) {
    LocalizerParams params;
    params.landmark = model;
    params.map_sigma_t = 1e-200;
    const GateMap map = oneGateMap();
    MainGraph graph(params, map, nullptr);
    ASSERT_TRUE(graph.addFirstKeyframe(0.0, Eigen::Isometry3d::Identity()).ok());
    const size_t vertices = graph.graph().numVertices();
    const size_t edges = graph.graph().numEdges();
    // Twice: the second sighting meets the prior's own error again, not a vertex id left taken by the first.
    for (int attempt = 0; attempt < 2; ++attempt) {
      const GateEdgeOutcome outcome = graph.addGateEdges(0, sightingOfGate7(model));
      EXPECT_EQ(outcome.added, 0);
      EXPECT_EQ(outcome.failed, 1);
      EXPECT_NE(outcome.message.find("gate map prior"), std::string::npos) << outcome.message;
      EXPECT_EQ(graph.graph().numVertices(), vertices) << landmarkModelName(model) << " attempt " << attempt;
      EXPECT_EQ(graph.graph().numEdges(), edges);
      EXPECT_EQ(graph.landmarkVertex(7), -1);
    }
  }
}

// The same graph with a usable σ takes the gate: the refusal above is the σ's, not the set-up's.
TEST(MainGraphErrors, WithAUsableSigmaTheSameSightingIsAdded) {
  for (LandmarkModel model : {LandmarkModel::kPose, LandmarkModel::kPoint}) {
    LocalizerParams params;
    params.landmark = model;
    const GateMap map = oneGateMap();
    MainGraph graph(params, map, nullptr);
    ASSERT_TRUE(graph.addFirstKeyframe(0.0, Eigen::Isometry3d::Identity()).ok());
    const GateEdgeOutcome outcome = graph.addGateEdges(0, sightingOfGate7(model));
    EXPECT_EQ(outcome.failed, 0) << outcome.message;
    EXPECT_EQ(outcome.added + outcome.rejected, 1);
    EXPECT_GE(graph.landmarkVertex(7), 0);
  }
}

}  // namespace main_graph_errors
}  // namespace dualgraph
