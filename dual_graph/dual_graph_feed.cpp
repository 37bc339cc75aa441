// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/dual_graph_feed.h"

#include <utility>

#include "dualgraph/core/stamp_tolerance.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

DualGraphFeed::DualGraphFeed(const LocalizerParams& params, std::shared_ptr<const RobustKernel> kernel)
    : params_(params), temporary_(params, std::move(kernel)) {}

bool DualGraphFeed::keyframeDueAfter(const OdometrySample& sample, const MainGraph& main) const {
  const Keyframe& last = main.keyframes().back();
  if (!(last.t < sample.t)) return false;
  const bool moved =
      incrementExceeds(last.odom_T_body.inverse() * sample.odom_T_body, params_.d_main, params_.theta_main);
  const bool waited = params_.keyframe_max_interval_s > 0.0 && temporary_.numObservations() > 0 &&
                      elapsedAtLeast(sample.t, last.t, params_.keyframe_max_interval_s);
  return moved || waited;
}

Result<ObservationUse> DualGraphFeed::addObservation(const GateObservation& observation,
                                                     const Eigen::Isometry3d& odom_T_body, const MainGraph&,
                                                     const OdometryHistory& history) {
  DG_RETURN_IF_ERROR(temporary_.addObservation(observation, odom_T_body, history));
  return ObservationUse::kCollected;
}

ClosingEdges DualGraphFeed::handOverEdges(const MainGraph& main, bool, const OdometryHistory& history) {
  const size_t newest = main.keyframes().size() - 1;
  const Keyframe& keyframe = main.keyframes()[newest];
  DistillationResult distilled = temporary_.distil(keyframe.t, keyframe.odom_T_body, history);
  ClosingEdges closing;
  closing.owner = newest;
  for (const GateEdgeMeasurement& gate : distilled.gates) closing.observations += gate.observations;
  closing.edges = std::move(distilled.gates);
  closing.skipped_gates = distilled.skipped_gates;
  closing.skip_reason = std::move(distilled.skip_reason);
  closing.partial_used = distilled.partial_used;
  closing.partial_unanchored = distilled.partial_unanchored;
  closing.temp_nodes = distilled.nodes;
  closing.temp_edges = distilled.edges;
  closing.temp_iterations = distilled.iterations;
  closing.temp_ms = distilled.optimize_ms;
  return closing;
}

}  // namespace dualgraph
