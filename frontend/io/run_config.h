// SPDX-License-Identifier: MIT
// SequenceRunParams, `dualgraph run`'s configuration: the localizer: and frontend: sections of a YAML file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/odometry_scale.h"
#include "dualgraph/frontend/gates/frame_initializer.h"
#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

/// How the run path searches for the VIO's frame again once the Localizer is lost (units m, rad, s).
struct RelocalizationParams {
  double sigma_t = 2.0;          ///< the estimate when lost, as the search's start pose: position σ [m]
  double sigma_r = 0.5;          ///< and yaw σ [rad] (hypotheses beyond 3 σ are discarded)
  double global_after_s = 5.0;   ///< no lock after this long: search the whole map instead [s]
  /// Tracking but suspicious (detections keep failing beside used ones: Localizer::frameSuspicious), the same
  /// search checks the frame in use; a different frame it finds replaces it only when the estimate in use
  /// explained (placed within the search's inlier distance of a map gate) fewer than this share of the
  /// detections the found frame explains — the found frame is the best of many hypotheses, so a fair
  /// comparison needs a margin. 0 disables the check.
  double replace_ratio = 0.5;
};

/// Everything `dualgraph run` configures.
struct SequenceRunParams {
  LocalizerParams localizer;
  GateFrontendParams frontend;
  double pose_detection_sigma_t = 0.1;   ///< covariance of detections.csv rows without one: σ [m]
  double pose_detection_sigma_r = 0.05;  ///< and [rad] (diagonal, metric [t; θ])
  /// true (`initialization: auto`): world_T_odom is found from the first detections (FrameInitializer, with
  /// localizer.initial_world_T_body as its coarse start pose when given) before the Localizer starts; false
  /// (`given`): localizer.initial_world_T_odom is taken as it is.
  bool auto_initialize = true;
  FrameInitializerParams initialization;
  RelocalizationParams relocalization;
  /// Camera-to-VIO clock offset [s] (`frontend.time_offset`): when set, used instead of the camera file's
  /// CameraModel::time_offset (and for pose detections, which have no camera file).
  std::optional<double> time_offset;
  /// Self-calibration (`frontend.self_calibration_after_s`, 0: off): once this much odometry time has passed,
  /// the camera's clock offset and mount rotation are calibrated on the flight so far and the rest of the run
  /// uses that camera (frontend/replay/self_calibration.h; corner sequences with a camera only) [s].
  double self_calibration_after_s = 8.0;
  /// The odometry time a self-calibration has (`frontend.self_calibration_budget_s`): it runs on a thread of its own
  /// and its camera is used from the first sample this long after it started; the pipeline waits for it there if it
  /// is still running, so the result does not depend on the machine's speed. 0: on the pipeline's thread, at once
  /// (one sample then takes its 0.1-0.5 s) [s], >= 0.
  double self_calibration_budget_s = 1.0;
  /// A detection instant stamped (on the odometry clock) more than this beyond the newest odometry sample is
  /// refused and counted (`frontend.max_detection_lead_s`; a stamp from another clock would otherwise block every
  /// later detection as out of order) [s], > 0.
  double max_detection_lead_s = 1.0;
  /// Consecutive odometry samples further apart than this are a gap (`frontend.max_odometry_gap_s`, 0: off): the
  /// detections inside it are refused (no pose to place them at); unless the gap is bridged (below), the samples
  /// after it are lost until gates fit again or a search finds the frame (counted, PipelineCounters::odometry_gaps)
  /// [s], >= 0.
  double max_odometry_gap_s = 0.5;
  /// A gap of at most this long while tracking is bridged (`frontend.bridge_odometry_gap_s`, 0: never): the frame
  /// and the tracking state are kept, the VIO's own increment across the gap is the odometry edge (a VIO whose output
  /// stalled kept integrating), and the state turns lost only as it does anywhere else — when gates are seen that
  /// do not fit (TrackingMonitor). Counted, PipelineCounters::odometry_gaps_bridged [s], >= 0.
  double bridge_odometry_gap_s = 2.0;
  /// An odometry sample stamped more than this after or before the newest accepted one is a clock jump
  /// (`frontend.max_odometry_jump_s`, 0: off): held until OdometryClockGuard::kConfirmations samples in a row
  /// continue from it, so one glitched stamp cannot make the rest of the flight "not after" it; a confirmed jump back
  /// restarts the pipeline (frontend/pipeline/odometry_clock_guard.h; counted,
  /// PipelineCounters::odometry_held_at_clock_jump, odometry_clock_restarts) [s], >= 0.
  double max_odometry_jump_s = 10.0;
  /// An odometry sample further from the newest accepted one than a drone flies — more than this speed [m/s]
  /// (`frontend.max_odometry_speed_mps`) or turn rate [rad/s] (`frontend.max_odometry_turn_rate_radps`) over their
  /// time apart, plus 0.1 m / 0.1 rad — is a pose jump: held until OdometryMotionGuard::kConfirmations samples in a
  /// row continue from it, so one glitched pose is never taken as motion, and a VIO that really jumps is taken two
  /// samples later (frontend/pipeline/odometry_motion_guard.h; counted, PipelineCounters::odometry_held_at_pose_jump,
  /// odometry_pose_jumps). >= 0; 0: that check off.
  double max_odometry_speed_mps = 50.0;
  double max_odometry_turn_rate_radps = 40.0;
  /// The VIO's translation scale estimated in flight and taken out of the odometry (`frontend.estimate_odometry_scale`,
  /// `frontend.odometry_scale_min_error`; dual_graph/odometry_scale.h).
  OdometryScaleParams odometry_scale;
  /// Set in code, not read: the camera the run switches to once the odometry reaches `t` [s] (its model, mount
  /// and time_offset for the detections handed over after that; params.time_offset no longer applies).
  struct CameraSwitch {
    double t = 0.0;
    CameraModel camera;
  };
  std::optional<CameraSwitch> camera_switch;

  /// The diagonal covariance from the two sigmas above.
  Matrix6d defaultPoseDetectionCovariance() const;
};

/// Reads `dualgraph run`'s configuration (data/config/default.yaml lists every key with its default
/// and unit): a `localizer:` section (LocalizerParams, frontend/io/localizer_params_yaml.h) and a
/// `frontend:` section, flat:
///
///     frontend:
///       trust_ids: false             # detector gate ids decide (still gated) instead of the assignment
///       pixel_sigma: 1.0             # GatePnpParams [px] (the prior when adaptive); likewise max_reprojection_rms [px],
///       ...                          #   min_range, max_range [m], min_corner_angle_deg,
///                                    #   max_condition_number, max_refinement_iterations
///       adaptive_pixel_sigma: true   # GateFrontendParams: σ estimated from the PnP residuals
///       upright_prior_sigma_deg: 0.0 # GateFrontendParams: > 0, PnP holds gates upright to this σ per tilt [deg]
///       partial_gates: true          # GateFrontendParams: 2–3 corners seen → corner rays (dual, landmark pose)
///       max_association_distance: 2.0  # AssociationParams::max_distance [m]; likewise max_normal_angle
///                                      #   [rad], allow_reversed, mapping_min_sightings, mapping_consistency [m]
///       pose_detection_sigma_t: 0.1  # SequenceRunParams [m], [rad] (_r)
///       time_offset: 0.015           # optional [s]: overrides the camera file's time_offset
///       estimate_odometry_scale: true  # the VIO's scale estimated in flight (dual_graph/odometry_scale.h);
///       odometry_scale_min_error: 0.02 #   applied once beyond this and 3 sigma from 1, in [0, 0.5)
///       self_calibration_after_s: 15 # [s], >= 0 (0: off): self-calibration (frontend/replay/self_calibration.h)
///       relocalization_sigma_t: 2.0  # RelocalizationParams [m]; likewise _sigma_r [rad], _global_after_s [s], _replace_ratio
///
/// Either section may be missing (defaults). Errors are "source:LINE: field 'NAME': why": kParseError
/// for an unknown or duplicate key, a wrong type, NaN or a `frontend:` value out of range;
/// kInvalidArgument for a `localizer:` value out of range (validateLocalizerParams, as
/// localizer_params_yaml.h documents); kIoError for an unreadable file.
/// kInvalidArgument naming the limits when the pipeline's own (max_detection_lead_s > 0; max_odometry_gap_s,
/// bridge_odometry_gap_s, max_odometry_jump_s, max_odometry_speed_mps, max_odometry_turn_rate_radps,
/// initialization.memory_m, self_calibration_after_s and self_calibration_budget_s finite and ≥ 0) are not: what PipelineCore::create checks of a configuration built in code.
Status validatePipelineLimits(const SequenceRunParams& params);

Result<SequenceRunParams> parseRunConfig(const std::string& yaml_text, const std::string& source_name);
/// Every key the `frontend:` section accepts, in the reader's order (data/config/default.yaml lists each, tested).
const std::vector<std::string>& runConfigFrontendKeys();
Result<SequenceRunParams> loadRunConfig(const std::string& path);

/// The whole configuration as the YAML parseRunConfig reads back to the same parameters: every key of both
/// sections (optional ones left out when unset; camera_switch is set in code, not written). `dualgraph run` writes
/// it to its folder as config.yaml; the defaults test compares it for data/config/default.yaml and
/// SequenceRunParams{}.
std::string runConfigYaml(const SequenceRunParams& params);

}  // namespace dualgraph
