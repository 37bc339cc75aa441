// SPDX-License-Identifier: MIT
// SingleGraphBaseline: the ablation baseline's feed of the main graph — every detection an edge from a node.
#pragma once

#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/main_graph_feed.h"

namespace dualgraph {

/// The single-graph baseline of the ablation as a MainGraphFeed (dual_graph/README.md, "Single-graph baseline"):
/// the main graph's keyframes are nodes at detection instants, a new one due before a detection whose VIO
/// increment since the newest node exceeds d_single/theta_single. Each detection becomes an edge from the newest
/// node, motion-compensated (the node-to-detection odometry covariance, under the odometry scale, added to the
/// detection's); with `single_all_detections` false only the detections of the node's own instant do, the rest are
/// kBetweenNodes. A node's edges are handed over when the next node has been added (they are the node before it's),
/// or at `finish` (the newest node's). Frames and units as MainGraphFeed.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once.
class SingleGraphBaseline final : public MainGraphFeed {
 public:
  explicit SingleGraphBaseline(const LocalizerParams& params);

  /// Never: the baseline's nodes come with the detections.
  bool keyframeDueAfter(const OdometrySample&, const MainGraph&) const override { return false; }
  bool keyframeDueBefore(double t, const Eigen::Isometry3d& odom_T_body, const MainGraph& main) const override;
  /// No: `finish` commits the newest node's edges.
  bool keyframeAtFinish() const override { return false; }

  /// An edge from the newest node of `main` (kCollected), or kBetweenNodes.
  Result<ObservationUse> addObservation(const GateObservation& observation, const Eigen::Isometry3d& odom_T_body,
                                        const MainGraph& main, const OdometryHistory& history) override;
  /// The edges collected at the node before the newest one when `keyframe_added`, else at the newest.
  ClosingEdges handOverEdges(const MainGraph& main, bool keyframe_added, const OdometryHistory& history) override;

  size_t numObservations() const override { return edges_.size(); }  ///< one edge per detection
  void clear() override;
  void setOdometryScale(const OdometryNoiseScale& scale) override { noise_model_.scale = scale; }

 private:
  const LocalizerParams params_;
  OdometryNoiseModel noise_model_;  ///< the motion compensation's
  GateEdgeMeasurements edges_;      ///< of the newest node, handed over when the next one is added
};

}  // namespace dualgraph
