// SPDX-License-Identifier: MIT
// What the onboard pipeline takes in and gives back: odometry input, per-sample output, update report, counters.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/frontend/pipeline/frame_search.h"
#include "dualgraph/frontend/pipeline/odometry_input.h"

namespace dualgraph {

/// What a self-calibrating run did (metrics.json `self_calibration_*`).
struct SelfCalibrationReport {
  bool attempted = false;            ///< the flight lasted past the calibration time and had corners and a camera
  int attempts = 0;                  ///< calibrations run (SelfCalibrator::kMaxAttempts at most)
  /// The last attempt found too little to go on (failed, did not converge, or a significant part could not be
  /// checked on both halves); another follows while attempts remain.
  bool evidence_missing = false;
  bool applied = false;              ///< the rest of the run used a calibrated camera (either calibration's)
  double at_s = 0.0;                 ///< t_c: the flight so far ends there [s]
  /// When the camera in use took effect: the first sample at or after at_s + frontend.self_calibration_budget_s
  /// (the clock offset calibrated alone first: its own) [s]; 0: never (not applied, or the flight ended first).
  double applied_at_s = 0.0;
  double time_offset_before = 0.0;   ///< the clock offset the run started with [s]
  double time_offset_after = 0.0;    ///< the calibrated one [s] (applied: the one in use from at_s on)
  double time_offset_sigma = 0.0;    ///< its formal 1σ [s]
  double mount_change_deg = 0.0;     ///< the angle of the mount rotation's correction, as estimated [deg]
  /// The mount correction of each half of the flight so far, calibrated apart, and what they show together (their
  /// inverse-variance mean's angle and its 1σ) [deg]; 0 when the halves were not both calibrated.
  double half_mount_change_deg[2] = {0.0, 0.0};
  double halves_mount_change_deg = 0.0, halves_mount_sigma_deg = 0.0;
  int iterations = 0;                ///< match-and-solve iterations
  /// Each part is applied only when significant and shown by both halves of the flight so far
  /// (frontend/calibration/calibration_acceptance.h); `applied` when either is.
  bool time_offset_applied = false;
  bool mount_applied = false;
  std::string why_not_time_offset;   ///< why the clock offset was kept (empty when applied)
  std::string why_not_mount;         ///< why the mount was kept (empty when applied)
  std::string why_not;               ///< when nothing was applied: why (empty when applied)
  /// What the last calibration estimated (SelfCalibrator's step-down): "clock offset and mount", "clock offset
  /// alone" or "mount alone" — the other part held at its value then.
  std::string parts;
  /// The clock offset calibrated alone first, on fewer corners than the whole calibration needs
  /// (SelfCalibrator::kMinCornersClockOffset): when it ran [s] (0: it did not), whether it was applied, its value [s].
  double clock_offset_first_at_s = 0.0;
  bool clock_offset_first_applied = false;
  double clock_offset_first_s = 0.0;
};

/// What one odometry sample did inside the pipeline (the work of that call, synchronous mode; in worker mode the
/// report of the sample the worker finished last).
struct UpdateReport {
  double t = 0.0;                                           ///< the sample's time [s]
  TrackingState state_before = TrackingState::kInitialising;
  TrackingState state = TrackingState::kInitialising;       ///< after the sample
  int instants = 0;             ///< detection instants handed over at this sample
  int observations_added = 0;   ///< observations the Localizer accepted
  int observations_rejected = 0;///< observations the Localizer refused (LocalizerCounters says why)
  int detections_refused = 0;   ///< detections refused before the frontend (PipelineCounters says why)
  /// Main-graph updates this sample caused (a keyframe closed, or a relocalisation's first keyframe), in order.
  std::vector<KeyframeStats> updates;
  bool keyframe_failed = false; ///< a keyframe interval could not be closed (LocalizerCounters::last_error)
  SearchAction search = SearchAction::kNone;  ///< what a frame search did (the last action, when several)
  bool search_started = false;  ///< a relocalisation search or a frame check began
  bool odometry_gap = false;    ///< this sample came after a gap longer than max_odometry_gap_s
  bool camera_switched = false; ///< the camera switched (self-calibration) before this sample's detections
  /// The odometry clock went back and the pipeline restarted before this sample (StreamingLocalizer): what came
  /// before belongs to another flight.
  bool clock_restarted = false;
};

/// The corrected pose at one odometry sample: world_T_body = map_T_odom · odom_T_body(t) through the newest
/// optimised keyframe (the last result in worker mode), its tracking state, and what the sample did.
struct PoseUpdate {
  CorrectedPose pose;
  UpdateReport report;
};

/// Inputs the pipeline did not use, by reason, on top of LocalizerCounters and GateFrontendCounters (never
/// silently: every refused input lands in one counter).
struct PipelineCounters {
  int odometry_invalid = 0;            ///< non-finite or non-rigid samples, or a covariance that is not one
  int odometry_not_after_previous = 0; ///< time not after the newest accepted sample (backwards or repeated)
  int odometry_queue_full = 0;         ///< worker mode: refused with the worker's queue full (a worker far behind)
  int odometry_gaps = 0;               ///< gaps longer than max_odometry_gap_s (bridged or not)
  int odometry_gaps_bridged = 0;       ///< of those, bridged (bridge_odometry_gap_s): frame and state kept
  /// Samples whose absolute covariance was all or partly zero: used as without one (not refused).
  int odometry_covariance_unknown = 0;
  /// Samples held at a jump beyond max_odometry_jump_s, either way (OdometryClockGuard): a glitch, or the first
  /// samples of a new clock before it was confirmed.
  int odometry_held_at_clock_jump = 0;
  int odometry_clock_jumps = 0;        ///< new clocks ahead confirmed (their first confirmed sample taken, after a gap)
  /// New clocks behind confirmed (a looped bag, a restarted VIO): the pipeline restarted there (StreamingLocalizer).
  int odometry_clock_restarts = 0;
  /// Samples held at a pose jump faster than max_odometry_speed_mps / max_odometry_turn_rate_radps
  /// (OdometryMotionGuard): a glitched pose, or the first samples of a VIO that really jumped.
  int odometry_held_at_pose_jump = 0;
  int odometry_pose_jumps = 0;         ///< pose jumps confirmed (3 samples in a row continued from one) and taken
  int detections_invalid = 0;          ///< non-finite values, or corners and poses in one instant
  int detections_backwards = 0;        ///< older than an instant given before
  int detections_too_far_ahead = 0;    ///< beyond the newest odometry by more than max_detection_lead_s
  /// More instants waiting than the queue holds (no odometry arriving), or the worker's queue full (worker mode).
  int detections_queue_full = 0;
  int detections_before_odometry = 0;  ///< earlier than the first odometry sample: not usable
  int detections_after_odometry = 0;   ///< later than the last odometry sample at `finish`
  int detections_in_gap = 0;           ///< inside an odometry gap: no pose to place them at
  int detections_unplaced = 0;         ///< older than the odometry the Localizer still holds
  /// While initialising: given to the frame search alone (PnP), not to the association or the Localizer.
  int detections_frame_search_only = 0;
  int observations_rejected = 0;       ///< refused by the Localizer (LocalizerCounters says why)
  /// Instants whose handling failed after they were accepted (a relocalisation refused, say); `last_error` says why.
  int instants_failed = 0;
  std::string last_error;
  int frame_checks = 0;                ///< checks of the frame in use started while tracking
  int frame_checks_replaced = 0;       ///< of them: a clearly better frame found, relocalised
  /// Relocalisation searches over the whole map because the frame lost was never confirmed by a gate edge (a given
  /// initial_world_T_odom the detections contradicted, or a found frame lost before its first edge).
  int unconfirmed_frame_searches = 0;
  int covariance_clamped = 0;          ///< eigenvalues RelativeCovarianceStream raised to its floor
  int covariance_shrinks = 0;          ///< samples whose absolute covariance really shrank (RelativeCovarianceStream)
};

/// Calls visit(name, &PipelineCounters::field) for every count of PipelineCounters (all but last_error), in
/// declaration order: the one list for code that handles them all (a restart's sums, Python's dict). A new count
/// goes here too.
template <typename Visit>
void forEachPipelineCount(Visit&& visit) {
  visit("odometry_invalid", &PipelineCounters::odometry_invalid);
  visit("odometry_not_after_previous", &PipelineCounters::odometry_not_after_previous);
  visit("odometry_queue_full", &PipelineCounters::odometry_queue_full);
  visit("odometry_gaps", &PipelineCounters::odometry_gaps);
  visit("odometry_gaps_bridged", &PipelineCounters::odometry_gaps_bridged);
  visit("odometry_covariance_unknown", &PipelineCounters::odometry_covariance_unknown);
  visit("odometry_held_at_clock_jump", &PipelineCounters::odometry_held_at_clock_jump);
  visit("odometry_clock_jumps", &PipelineCounters::odometry_clock_jumps);
  visit("odometry_clock_restarts", &PipelineCounters::odometry_clock_restarts);
  visit("odometry_held_at_pose_jump", &PipelineCounters::odometry_held_at_pose_jump);
  visit("odometry_pose_jumps", &PipelineCounters::odometry_pose_jumps);
  visit("detections_invalid", &PipelineCounters::detections_invalid);
  visit("detections_backwards", &PipelineCounters::detections_backwards);
  visit("detections_too_far_ahead", &PipelineCounters::detections_too_far_ahead);
  visit("detections_queue_full", &PipelineCounters::detections_queue_full);
  visit("detections_before_odometry", &PipelineCounters::detections_before_odometry);
  visit("detections_after_odometry", &PipelineCounters::detections_after_odometry);
  visit("detections_in_gap", &PipelineCounters::detections_in_gap);
  visit("detections_unplaced", &PipelineCounters::detections_unplaced);
  visit("detections_frame_search_only", &PipelineCounters::detections_frame_search_only);
  visit("observations_rejected", &PipelineCounters::observations_rejected);
  visit("instants_failed", &PipelineCounters::instants_failed);
  visit("frame_checks", &PipelineCounters::frame_checks);
  visit("frame_checks_replaced", &PipelineCounters::frame_checks_replaced);
  visit("unconfirmed_frame_searches", &PipelineCounters::unconfirmed_frame_searches);
  visit("covariance_clamped", &PipelineCounters::covariance_clamped);
  visit("covariance_shrinks", &PipelineCounters::covariance_shrinks);
}

}  // namespace dualgraph
