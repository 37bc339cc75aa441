// SPDX-License-Identifier: MIT
// Localizer: drift-corrected localisation from odometry and gate observations (dual or single graph).
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "dual_graph/gate_map.h"
#include "dual_graph/localizer_params.h"
#include "dual_graph/main_graph.h"
#include "dual_graph/measurements.h"
#include "dual_graph/odometry_history.h"
#include "dual_graph/temporary_graph.h"

namespace dualgraph {

/// The corrected pose at one odometry sample: world_T_body(t) = map_T_odom · odom_T_body(t).
struct CorrectedPose {
  double t = 0.0;
  Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// One row per main-graph optimisation (a keyframe in dual mode, a node in single mode, and `finish`).
struct KeyframeStats {
  int keyframe = 0;            ///< index of the newest keyframe
  double t = 0.0;              ///< its time [s]
  int main_vertices = 0;
  int main_edges = 0;          ///< edges the main graph stands for (folded into marginal priors included)
  int active_edges = 0;        ///< edges in the optimisation (fewer than main_edges in fixed-lag mode)
  int iterations = 0;          ///< LM iterations of the main graph
  /// Main-graph update wall time: the new edges' χ² gate (its marginals), LM, and (fixed-lag) the
  /// marginalisation of the keyframe leaving the window. Not the temporary graph (temp_ms).
  double optimize_ms = 0.0;
  std::string termination;
  int gate_edges_added = 0;    ///< distilled (dual) or detection (single) edges that entered the main graph
  int gate_edges_rejected = 0; ///< by the χ² gate
  int gates_skipped = 0;       ///< unusable marginals or edges that could not be added
  int observations = 0;        ///< detections this row's edges stand for
  int temp_nodes = 0;          ///< dual mode: the temporary graph's pose nodes (keyframe included)
  int temp_edges = 0;
  int temp_iterations = 0;
  double temp_ms = 0.0;        ///< temporary graph: build, LM and marginals
};

/// Inputs that were not used, by reason (never silently).
struct LocalizerCounters {
  int odometry_accepted = 0;
  int odometry_rejected = 0;
  int observations_accepted = 0;
  int observations_rejected = 0;       ///< invalid, unknown gate, out of order, too late, before odometry
  /// Of the rejected: older than the keyframe (or node) that had already closed their interval. A caller
  /// that hands each observation over before the odometry sample that covers it never sees one.
  int observations_too_late = 0;
  int observations_failed = 0;         ///< accepted but could not be attached when processed
  int observations_never_processed = 0;///< newer than the last odometry sample at `finish`
  /// Single mode with `single_all_detections` false: detections after a node's instant that did not start
  /// a node, which that baseline does not use (by its definition, not for a fault).
  int observations_between_nodes = 0;
  std::string last_error;
};

/// Drift-corrected localisation with the dual pose graph (DESIGN.md §3), or the single-graph baseline.
/// Feed odometry samples and gate observations in time order (an observation newer than the newest
/// odometry sample waits for the sample that covers it). Dual mode: a keyframe when the VIO increment
/// since the last exceeds d_main/theta_main; the observations of the interval are collected in the
/// temporary graph and distilled into one edge per gate from the new keyframe; the main graph is then
/// optimised. Single mode: a node at a detection instant when the increment since the last node exceeds
/// d_single/theta_single; every detection becomes an edge from its node (motion-compensated; or only those
/// of the node's own instant, `single_all_detections` false); the graph
/// is optimised at every node. Bad input is rejected with a Status and counted; the Localizer goes on.
/// Not thread-safe.
class Localizer {
 public:
  /// kInvalidArgument for invalid parameters, or localization mode with an empty map.
  static Result<std::unique_ptr<Localizer>> create(const LocalizerParams& params, GateMap map);

  /// OK when addOdometry would accept `sample` (valid, and newer than the newest accepted sample);
  /// otherwise the Status it would reject it with. Changes nothing.
  Status checkOdometry(const OdometrySample& sample) const;
  /// The corrected pose at this sample, or why the sample was rejected (the state is unchanged then).
  Result<CorrectedPose> addOdometry(const OdometrySample& sample);
  /// OK when accepted (used now or queued until odometry covers its time).
  Status addObservation(const GateObservation& observation);
  /// End of input: uses what is still collected (dual: distils into a keyframe at the newest sample;
  /// single: commits the newest node's edges) and optimises once more.
  Status finish();

  /// map_T_odom = K · odom_T_body(t_K)⁻¹ with K the newest optimised keyframe (identity-based guess before).
  Eigen::Isometry3d mapTOdom() const;
  /// The keyframes' current estimates (world_T_body) with their times.
  std::vector<CorrectedPose> keyframeTrajectory() const;
  const std::vector<KeyframeStats>& keyframeStats() const { return stats_; }
  const LocalizerCounters& counters() const { return counters_; }
  const MainGraph& mainGraph() const { return *main_; }
  const LocalizerParams& params() const { return params_; }

 private:
  Localizer(const LocalizerParams& params, GateMap map, std::shared_ptr<const RobustKernel> kernel);
  Status checkObservation(const GateObservation& observation) const;
  /// True when the interval `observation` belongs to was closed already (checkObservation's last check).
  bool tooLate(const GateObservation& observation) const;
  Status processObservation(const GateObservation& observation);
  Status processSingleObservation(const GateObservation& observation, const Eigen::Isometry3d& odom_T_body);
  /// Dual mode: keyframe at the newest sample (unless it is one already), distillation, optimisation.
  Status closeInterval();
  /// Single mode: commits the newest node's edges, adds a node at (t, odom_T_body) unless final, optimises.
  Status closeSingleNode(double t, const Eigen::Isometry3d& odom_T_body, bool final_row);
  /// Optimises (and slides the window), fills `row` and appends it; `start_ms` is when the update began.
  void optimizeAndRecord(KeyframeStats& row, double start_ms);
  /// Time before which no observation can be used any more (the interval's or the node's start).
  double openIntervalStart() const;

  const LocalizerParams params_;
  const GateMap map_;
  std::shared_ptr<const RobustKernel> kernel_;
  std::unique_ptr<MainGraph> main_;
  TemporaryGraph temporary_;
  OdometryHistory history_;
  std::deque<GateObservation, Eigen::aligned_allocator<GateObservation>> pending_;
  GateEdgeMeasurements single_edges_;  ///< single mode: edges of the newest node, committed at the next
  int single_observations_ = 0;
  double last_observation_t_ = -std::numeric_limits<double>::infinity();
  std::vector<KeyframeStats> stats_;
  LocalizerCounters counters_;
};

}  // namespace dualgraph
