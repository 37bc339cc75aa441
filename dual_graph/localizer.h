// SPDX-License-Identifier: MIT
// Localizer: drift-corrected localisation from odometry and gate observations (dual or single graph).
#pragma once

#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dualgraph/dual_graph/gate_map.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/main_graph.h"
#include "dualgraph/dual_graph/main_graph_feed.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/dual_graph/odometry_history.h"
#include "dualgraph/dual_graph/odometry_noise_learner.h"
#include "dualgraph/dual_graph/pose_covariance.h"
#include "dualgraph/dual_graph/tracking_monitor.h"

namespace dualgraph {

/// The corrected pose at one odometry sample: world_T_body(t) = map_T_odom · odom_T_body(t), and whether it is
/// a map pose (`state`: tracking; lost: the last correction carried on by the odometry; initialising: not
/// one, the odometry through the initial guess of world_T_odom).
struct CorrectedPose {
  double t = 0.0;
  Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
  TrackingState state = TrackingState::kTracking;
  /// While tracking, after the first main-graph update: the covariance of world_T_body, metric [t; θ] (m², rad²),
  /// a right perturbation in the body frame — the newest optimised keyframe's marginal composed with the odometry
  /// increment's covariance since it (first order). Unset where not known (initialising, lost, before an update).
  std::optional<Matrix6d> covariance;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// One row per main-graph optimisation (a keyframe in dual mode, a node in single mode, and `finish`).
struct KeyframeStats {
  int keyframe = 0;            ///< index of the newest keyframe
  double t = 0.0;              ///< its time [s]
  /// Vertices the run's main graph stands for (marginalised keyframes included), plus the keyframes of the main
  /// graphs given up before a `relocalize` / `resumeWithNewGraph` (their gates are the same gates again).
  int main_vertices = 0;
  /// Edges the main graph stands for (folded into marginal priors included), plus those of the graphs given up.
  int main_edges = 0;
  int active_edges = 0;        ///< edges in the optimisation (fewer than main_edges in fixed-lag mode)
  int iterations = 0;          ///< LM iterations of the main graph
  /// Main-graph update wall time: the new edges' χ² gate (its marginals), LM, and (fixed-lag) the
  /// marginalisation of the keyframe leaving the window. Not the temporary graph (temp_ms).
  double optimize_ms = 0.0;
  TerminationReason termination = TerminationReason::kNothingToOptimize;  ///< of the main graph's LM
  int gate_edges_added = 0;    ///< distilled (dual) or detection (single) edges that entered the main graph
  int gate_edges_rejected = 0; ///< by the χ² gate
  int observations_rejected = 0; ///< detections the rejected edges stood for
  int gates_skipped = 0;       ///< unusable marginals or edges that could not be added
  int observations = 0;        ///< detections this row's edges stand for
  int temp_nodes = 0;          ///< dual mode: the temporary graph's pose nodes (keyframe included)
  int temp_edges = 0;
  int temp_iterations = 0;
  double temp_ms = 0.0;        ///< temporary graph: build, LM and marginals
  double covariance_ms = 0.0;  ///< the newest keyframe's marginal covariance, after the update (CorrectedPose::covariance)
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
  int observations_too_far_ahead = 0;  ///< stamped beyond the newest odometry by max_observation_lead_s
  int observations_failed = 0;         ///< accepted but could not be attached when processed
  int observations_never_processed = 0;///< newer than the last odometry sample at `finish`
  /// Single mode with `single_all_detections` false: detections after a node's instant that did not start
  /// a node, which that baseline does not use (by its definition, not for a fault).
  int observations_between_nodes = 0;
  /// Refused while initialising (the VIO's frame in the map not known yet) or dropped by `relocalize`
  /// (associated in the frame that was given up).
  int observations_without_frame = 0;
  int losses = 0;          ///< tracking turned lost (TrackingMonitor)
  int recoveries = 0;      ///< lost turned tracking without a new frame: gate edges accepted with no failure in lost_after_s, or resumeTracking
  int relocalizations = 0; ///< `relocalize` calls while lost (or after distrustFrame): a new frame, the main graph started again
  /// Keyframe intervals that could not be closed (the keyframe or its update failed; `last_error` says why); the
  /// Localizer goes on with the next interval.
  int keyframes_failed = 0;
  int keyframes_conditioned = 0;  ///< fixed-lag: keyframes whose marginalisation failed, conditioned on instead
  int partial_used = 0;        ///< partial gates (corner rays) that became corner edges in a temporary graph
  int partial_unanchored = 0;  ///< partial gates left out: no pose observation of their gate in the interval
  std::string last_error;
};

/// Drift-corrected localisation with the dual pose graph (dual_graph/README.md), or the single-graph baseline.
/// Feed odometry samples and gate observations in time order (an observation newer than the newest
/// odometry sample waits for the sample that covers it). Dual mode: a keyframe when the VIO increment
/// since the last exceeds d_main/theta_main; the observations of the interval are collected in the
/// temporary graph and distilled into one edge per gate from the new keyframe; the main graph is then
/// optimised. Single mode: a node at a detection instant when the increment since the last node exceeds
/// d_single/theta_single; every detection becomes an edge from its node (motion-compensated; or only those
/// of the node's own instant, `single_all_detections` false); the graph
/// is optimised at every node. The mode's part (what is collected, when a keyframe is due, which edges it gets)
/// is a MainGraphFeed: DualGraphFeed or SingleGraphBaseline. Bad input is rejected with a Status and counted; the
/// Localizer goes on.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class Localizer {
 public:
  /// kInvalidArgument for invalid parameters, or localization mode with an empty map, or `initial` lost.
  /// `initial` kTracking: params.initial_world_T_odom is the frame (a prior, initial_sigma_t/_r); kInitialising:
  /// the frame is unknown, no observation is used until `relocalize` gives it (mapping mode: always tracking).
  static Result<std::unique_ptr<Localizer>> create(const LocalizerParams& params, GateMap map,
                                                   TrackingState initial = TrackingState::kTracking);

  // Inputs: odometry and gate observations in time order.

  /// OK when addOdometry would accept `sample` (valid, and newer than the newest accepted sample);
  /// otherwise the Status it would reject it with. Changes nothing.
  Status checkOdometry(const OdometrySample& sample) const;
  /// The corrected pose at this sample, or why the sample was rejected (the state is unchanged then).
  Result<CorrectedPose> addOdometry(const OdometrySample& sample);
  /// odom_T_body at `t` [s] from the odometry the Localizer holds (the open keyframe interval; the last 5 s while
  /// initialising or lost), interpolated along the geodesic; with `next` (a sample not given yet, newer than the
  /// newest) also between the newest sample and it. The one odometry buffer of a run: a caller that associates a
  /// detection before handing over the sample that covers it asks here. kFailedPrecondition outside that span.
  Result<Eigen::Isometry3d> odometryPoseAt(double t, const OdometrySample* next = nullptr) const {
    return history_.poseAt(t, next);
  }
  /// The oldest odometry time the Localizer holds [s] (odometryPoseAt's span starts there; an observation older than
  /// it can no longer be placed); nullopt before the first sample.
  std::optional<double> oldestOdometryTime() const {
    return history_.empty() ? std::nullopt : std::optional<double>(history_.oldestTime());
  }
  /// OK when accepted (used now or queued until odometry covers its time).
  Status addObservation(const GateObservation& observation);
  // Loss and the frame: the evidence the TrackingMonitor judges, and a frame search's result applied. The onboard
  // pipeline (frontend/pipeline/, FrameSearch) makes these calls; each checks the state it applies to (a no-op or
  // a Status otherwise), so a caller driving the Localizer itself may make them in any order.

  /// Frontend evidence for the TrackingMonitor: the gate centres [m, world frame through the current estimate]
  /// of the detections at time t [s] that passed PnP but matched no map gate near the estimate.
  /// kInvalidArgument for a non-finite time or position.
  Status reportUnmatched(double t, const std::vector<Eigen::Vector3d>& p_world);
  /// The VIO's frame in the map was found (initialising) or found again (lost, or on demand): the main graph
  /// starts again with its first keyframe at the last odometry sample at or before `since` [s] (the newest by
  /// default; while initialising or lost the Localizer keeps the last 5 s of odometry, so a search's own
  /// detections can be handed over again, oldest first, from that keyframe on), world_T_body = world_T_odom ·
  /// odom_T_body, held by a prior with `sigma_t` [m] and `sigma_r` [rad] (initial_sigma_t/_r when ≤ 0). The
  /// keyframes so far stay in
  /// keyframeTrajectory; collected and queued observations, associated in the old frame, are dropped
  /// (counted). State: tracking. Returns the first keyframe's time. kFailedPrecondition before any odometry;
  /// kInvalidArgument for a non-rigid transform or an unusable σ (NaN, infinite, or one whose square overflows).
  /// On any error nothing changes: the run goes on in the graph and state it had.
  Result<double> relocalize(const Eigen::Isometry3d& world_T_odom,
                            double since = std::numeric_limits<double>::infinity(), double sigma_t = 0.0,
                            double sigma_r = 0.0);
  /// A search found the frame the estimate already uses (a false alarm, or a loss the graph recovered from):
  /// tracking again without starting over, counted as a recovery. No-op unless lost.
  void resumeTracking();
  /// Lost, and a search found the frame in use about right (it explains the search's detections about as well
  /// as the best frame found): tracking again at the current estimate, but in a new main graph whose first
  /// keyframe is held by a prior of `sigma_t` [m] / `sigma_r` [rad] — the old graph's marginal prior, confident
  /// in a pose that failed to explain the detections for lost_after_s, is dropped (as `relocalize` does).
  /// Counted as a recovery. No-op unless lost; kFailedPrecondition before any odometry; kInvalidArgument for an
  /// unusable σ, as `relocalize`, and then nothing changes.
  Status resumeWithNewGraph(double sigma_t, double sigma_r);
  TrackingState trackingState() const { return monitor_.state(); }
  /// Whether a gate edge entered the main graph since the frame in use was set (given at `create`, or found and
  /// handed to `relocalize`): false for a frame no gate has confirmed yet, which a loss then says nothing good
  /// of (a given initial_world_T_odom the detections contradict).
  bool frameConfirmed() const { return frame_confirmed_; }
  /// Asks for a keyframe (a node in single mode) at the first odometry sample that covers every observation given
  /// so far, whatever the VIO moved: after `relocalize` and the search's detections handed over again, the graph
  /// refines the frame the search found at once instead of at the first keyframe the motion makes (the output
  /// meanwhile carries the search's error). No-op while initialising.
  void requestKeyframe();
  /// Every observation stamped at or before `t` [s] has been given (a detector that has processed its images up
  /// to t, whatever they held): a keyframe that waits for late detections (detection_latency) closes at the first
  /// sample once this reaches it instead of waiting the whole latency. Only moves forward.
  void observationsCompleteUntil(double t);
  /// Tracking, but at least lost_min_failures detections failed in the last lost_after_s while others were
  /// used: the frame in use may be wrong (a VIO jump by about a gate spacing matches some gates to their
  /// neighbours and leaves the others unmatched). The cue for a search that checks it.
  bool frameSuspicious() const { return monitor_.suspicious(); }
  /// A check found a better frame than the one in use: tracking turns lost (counted as a loss), so the
  /// `relocalize` that follows counts as a relocalisation. No-op unless tracking.
  void distrustFrame();

  // End and reading.

  /// End of input: uses what is still collected (dual: distils into a keyframe at the newest sample;
  /// single: commits the newest node's edges) and optimises once more.
  Status finish();

  /// map_T_odom = K · odom_T_body(t_K)⁻¹ with K the newest optimised keyframe (identity-based guess before).
  Eigen::Isometry3d mapTOdom() const;
  /// The keyframes' current estimates (world_T_body) with their times, those of main graphs given up at a
  /// `relocalize` first (as they were then).
  std::vector<CorrectedPose> keyframeTrajectory() const;
  const std::vector<KeyframeStats>& keyframeStats() const { return stats_; }
  const LocalizerCounters& counters() const { return counters_; }
  const MainGraph& mainGraph() const { return *main_; }
  const LocalizerParams& params() const { return params_; }
  /// The factors learnt in flight (all 1 unless learn_odometry_noise) and the gate pairs they come from.
  const OdometryNoiseLearner::Factors& learntNoiseFactors() const { return noise_learner_.factors(); }
  int learntNoisePairs() const { return noise_learner_.pairsSeen(); }

 private:
  friend class LocalizerTestAccess;  ///< tests only (fault injection into the main graph); defined by the tests
  Localizer(const LocalizerParams& params, GateMap map, std::shared_ptr<const RobustKernel> kernel,
            TrackingState initial);
  Status checkObservation(const GateObservation& observation) const;
  /// True when the interval `observation` belongs to was closed already (checkObservation's last check).
  bool tooLate(const GateObservation& observation) const;
  /// Stamped beyond the newest odometry sample by more than max_observation_lead_s.
  bool tooFarAhead(const GateObservation& observation) const;
  /// Hands a covered observation to the feed (after the keyframe it makes due, if any).
  Status processObservation(const GateObservation& observation);
  /// Closes the open keyframe interval (dual) or node (single): a keyframe at `new_keyframe` unless it is null or
  /// the newest already, the feed's edges of the closing keyframe through the χ² gate, the main graph optimised.
  Status closeKeyframe(const OdometrySample* new_keyframe);
  /// Hands the pending observations up to `until` [s] to the graphs.
  void processPending(double until);
  /// Closes the interval of the keyframe that waited detection_latency, then processes what waited behind it.
  void closeDueKeyframe();
  /// Learns from a distillation's edges (learn_odometry_noise): the odometry's noise, applied to what uses it, and
  /// the edges' covariance factor, applied to `distilled`.
  void learnOdometryNoise(GateEdgeMeasurements& distilled);
  /// Optimises (and slides the window), fills `row` and appends it; `start_ms` is when the update began.
  void optimizeAndRecord(KeyframeStats& row, double start_ms);
  /// `relocalize`'s work without its checks and counting: the main graph given up for a new one in `world_T_odom`
  /// anchored at the sample at or before `since`; tracking. Returns the first keyframe's time.
  Result<double> startGraph(const Eigen::Isometry3d& world_T_odom, double since, double sigma_t, double sigma_r);
  /// Forgets odometry before the keyframe at keyframe_t (tracking), or kept for `relocalize` (otherwise).
  void discardHistory(double keyframe_t);
  /// Time before which no observation can be used any more (the interval's or the node's start).
  double openIntervalStart() const;

  const LocalizerParams params_;
  const GateMap map_;
  std::shared_ptr<const RobustKernel> kernel_;
  std::unique_ptr<MainGraph> main_;
  std::unique_ptr<MainGraphFeed> feed_;  ///< the mode's: DualGraphFeed or SingleGraphBaseline
  OdometryHistory history_;
  std::deque<GateObservation, Eigen::aligned_allocator<GateObservation>> pending_;
  /// A keyframe decided at this time [s] that waits until odometry reaches it + detection_latency.
  std::optional<double> keyframe_due_;
  /// observationsCompleteUntil: every observation up to this time [s] was given.
  double observations_complete_until_ = -std::numeric_limits<double>::infinity();
  /// requestKeyframe: a keyframe at the first sample at or after this time [s].
  std::optional<double> keyframe_requested_after_;
  bool frame_confirmed_ = false;  ///< see frameConfirmed()
  double last_observation_t_ = -std::numeric_limits<double>::infinity();
  std::vector<KeyframeStats> stats_;
  PoseCovarianceTracker pose_covariance_;  ///< CorrectedPose::covariance
  OdometryNoiseModel noise_model_;         ///< params_' model under the learnt scale
  OdometryNoiseLearner noise_learner_;
  LocalizerCounters counters_;
  TrackingMonitor monitor_;
  std::vector<CorrectedPose> given_up_keyframes_;
  size_t given_up_graph_keyframes_ = 0;  ///< keyframes of the main graphs given up (KeyframeStats::main_vertices)
  size_t given_up_graph_edges_ = 0;      ///< and their edges (KeyframeStats::main_edges)
};

}  // namespace dualgraph
