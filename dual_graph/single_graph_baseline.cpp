// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/single_graph_baseline.h"

#include <utility>

#include "dualgraph/dual_graph/temporary_graph.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

SingleGraphBaseline::SingleGraphBaseline(const LocalizerParams& params)
    : params_(params), noise_model_(noiseModelOf(params)) {}

bool SingleGraphBaseline::keyframeDueBefore(double t, const Eigen::Isometry3d& odom_T_body,
                                            const MainGraph& main) const {
  const Keyframe& node = main.keyframes().back();
  return t > node.t && incrementExceeds(node.odom_T_body.inverse() * odom_T_body, params_.d_single, params_.theta_single);
}

Result<ObservationUse> SingleGraphBaseline::addObservation(const GateObservation& observation,
                                                           const Eigen::Isometry3d& odom_T_body, const MainGraph& main,
                                                           const OdometryHistory& history) {
  const Keyframe& node = main.keyframes().back();
  Matrix6d compensation = Matrix6d::Zero();
  const bool compensated = observation.t > node.t;
  if (compensated && !params_.single_all_detections) return ObservationUse::kBetweenNodes;
  if (compensated) {
    Result<Matrix6d> covariance = history.relativeCovariance(node.t, observation.t, noise_model_);
    if (!covariance.ok()) return covariance.status();
    compensation = *covariance;
  }
  Result<GateEdgeMeasurement> measurement = attachObservationToNode(
      observation, node.odom_T_body.inverse() * odom_T_body, compensated ? &compensation : nullptr, params_.landmark);
  if (!measurement.ok()) return measurement.status();
  edges_.push_back(*measurement);
  return ObservationUse::kCollected;
}

ClosingEdges SingleGraphBaseline::handOverEdges(const MainGraph& main, bool keyframe_added, const OdometryHistory&) {
  ClosingEdges closing;
  // The previous node's detections, gated against the graph that now holds the new node.
  closing.owner = main.keyframes().size() - (keyframe_added ? 2 : 1);
  closing.observations = static_cast<int>(edges_.size());  // one edge per detection
  closing.edges = std::move(edges_);
  clear();
  return closing;
}

void SingleGraphBaseline::clear() { edges_.clear(); }

}  // namespace dualgraph
