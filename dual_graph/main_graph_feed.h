// SPDX-License-Identifier: MIT
// MainGraphFeed: how gate observations reach the Localizer's main graph (dual pose graph or single-graph baseline).
#pragma once

#include <cstddef>
#include <string>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/gate_edge.h"
#include "dualgraph/dual_graph/main_graph.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/dual_graph/odometry_history.h"

namespace dualgraph {

/// What a MainGraphFeed did with one observation it was handed.
enum class ObservationUse {
  kCollected,     ///< kept: it enters the edges of the keyframe (node) that closes next
  /// Left out by the feed's definition, not for a fault: the single-graph baseline with `single_all_detections`
  /// false uses only the detections of a node's own instant (LocalizerCounters::observations_between_nodes).
  kBetweenNodes,
};

/// The gate edges a closing keyframe (dual) or node (single) hands to the main graph, and what made them. The
/// edges are relative to keyframe `owner` (GateEdgeMeasurement: node_T_gate in that keyframe's body frame, metric
/// units). The distillation figures are the dual feed's; the single baseline leaves them 0.
struct ClosingEdges {
  GateEdgeMeasurements edges;
  size_t owner = 0;         ///< index in MainGraph::keyframes() of the keyframe the edges start from
  int observations = 0;     ///< detections the edges stand for (KeyframeStats::observations)
  int skipped_gates = 0;    ///< gates whose marginal covariance was not usable (left out of `edges`)
  std::string skip_reason;  ///< why the first one was skipped
  int partial_used = 0;     ///< LocalizerCounters::partial_used
  int partial_unanchored = 0;
  int temp_nodes = 0;       ///< KeyframeStats::temp_nodes, temp_edges, temp_iterations, temp_ms
  int temp_edges = 0;
  int temp_iterations = 0;
  double temp_ms = 0.0;
};

/// How gate observations reach the Localizer's main graph: what a feed collects between keyframes, when a
/// keyframe is due, and the gate edges it hands over when one closes. The Localizer owns the odometry, the main
/// graph and its keyframes, and drives one feed: DualGraphFeed (the dual pose graph: a temporary graph per
/// keyframe interval, distilled into one edge per gate) or SingleGraphBaseline (the ablation baseline: nodes at
/// detection instants, every detection an edge from its node). Frames and units: observations as GateObservation
/// gives them (body frame), VIO poses odom_T_body, times [s]; `main` is the main graph the edges go into, read only
/// (its newest keyframe is the open interval's start).
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once (the Localizer's own instance).
class MainGraphFeed {
 public:
  virtual ~MainGraphFeed() = default;

  /// After the odometry sample `sample` (already in the history): whether a keyframe is due at it.
  virtual bool keyframeDueAfter(const OdometrySample& sample, const MainGraph& main) const = 0;
  /// Before the observation at `t` taken at `odom_T_body`: whether a keyframe (node) is due at its instant, to be
  /// added before the observation is attached.
  virtual bool keyframeDueBefore(double t, const Eigen::Isometry3d& odom_T_body, const MainGraph& main) const = 0;
  /// Whether `finish` adds a keyframe at the newest odometry sample before the last hand-over.
  virtual bool keyframeAtFinish() const = 0;

  /// Collects a valid observation taken at `odom_T_body` (the VIO pose at its instant); `history` covers
  /// [newest keyframe of `main`, observation]. Observations come in non-decreasing time.
  virtual Result<ObservationUse> addObservation(const GateObservation& observation,
                                                const Eigen::Isometry3d& odom_T_body, const MainGraph& main,
                                                const OdometryHistory& history) = 0;
  /// The edges of the keyframe (node) that closes, and clears what they were made of. `main` holds the closing
  /// keyframe (new, `keyframe_added`, or the newest already there); `history` covers the open interval.
  virtual ClosingEdges handOverEdges(const MainGraph& main, bool keyframe_added, const OdometryHistory& history) = 0;

  /// Observations collected and not handed over yet.
  virtual size_t numObservations() const = 0;
  /// Forgets what was collected (a new main graph: it was associated in the frame given up).
  virtual void clear() = 0;
  /// The odometry's learnt scale (OdometryNoiseLearner) for the motion compensation the feed does.
  virtual void setOdometryScale(const OdometryNoiseScale& scale) = 0;
};

}  // namespace dualgraph
