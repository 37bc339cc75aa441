// SPDX-License-Identifier: MIT
// calibrateCameraOnRun: the camera-to-VIO clock offset and the camera-mount rotation from a flight so far.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/calibration/calibration_solver.h"
#include "dualgraph/frontend/gates/corner_detection.h"
#include "dualgraph/frontend/gates/track.h"
#include "dualgraph/frontend/calibration/vio_drift_track.h"
#include "dualgraph/frontend/calibration/gate_corner_matching.h"

namespace dualgraph {

/// What calibrateCamera does (frontend/calibration/README.md).
struct CalibrationParams {
  int max_iterations = 6;                ///< runs (each: run → match → solve → update), ≥ 1
  /// Stop when δ moved less than this or converged_sigma_fraction of its 1σ [s] ...
  double converged_time_offset = 1e-4;
  /// ... and the mount rotation less than this or converged_sigma_fraction of its 1σ [deg] (a part the solver
  /// holds is not judged).
  double converged_rotation_deg = 0.01;
  /// A step this share of a part's own 1σ changes nothing the estimate can tell (re-made matches move it that much).
  double converged_sigma_fraction = 0.1;
  double knot_spacing = 4.0;             ///< of the VIO's drift correction, VioDriftTrack [s]
  /// A detection matches a map gate when its corners lie within this RMS distance of the gate's projection [px].
  /// Measured on the realistic profile: a 3° mount error with 100 ms of offset still converges (fewer matches in
  /// the first run, all in the next).
  double max_match_rms_px = 30.0;
  int min_matches = 20;  ///< fewer matched detections is an error
  CalibrationSolverParams solver;
};

/// One run of the loop: the camera the run used, and what the solve made of it.
struct CalibrationIteration {
  int iteration = 0;              ///< 1-based
  double time_offset_used = 0.0;  ///< δ the run used [s]
  double time_offset = 0.0;       ///< δ after the solve [s]
  /// body_R_camera after the solve = the input camera's · Exp(mount_correction) [rad, body-camera axes]
  Eigen::Vector3d mount_correction = Eigen::Vector3d::Zero();
  double time_offset_step = 0.0;   ///< |δ after − δ used| [s]
  double rotation_step_deg = 0.0;  ///< angle between the mount rotations before and after [deg]
  double time_offset_sigma = 0.0;  ///< CalibrationSolution's formal 1σ [s]
  Eigen::Vector3d rotation_sigma = Eigen::Vector3d::Zero();         ///< [rad]
  double rms_px = 0.0, inlier_rms_px = 0.0, robust_sigma_px = 0.0;  ///< after the solve [px]
  double rms_before_px = 0.0;  ///< RMS of the matched corners at the run's trajectory, before [px]
  GateCornerMatchCounts matching;
  int corners = 0, inlier_corners = 0, solver_iterations = 0;
  int detections_used_by_run = 0;  ///< GateFrontendCounters::used of the run
  bool run_initialized = false;    ///< the run found the VIO's frame

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// The calibrated camera and how it was reached.
struct CameraCalibration {
  /// The input camera with body_T_camera's rotation corrected (its translation kept) and time_offset = δ.
  CameraModel camera;
  Eigen::Vector3d mount_correction = Eigen::Vector3d::Zero();  ///< of body_R_camera, right, [rad]
  double time_offset_sigma = 0.0;                              ///< last iteration's formal 1σ [s]
  Eigen::Vector3d rotation_sigma = Eigen::Vector3d::Zero();    ///< [rad]
  std::vector<CalibrationIteration> iterations;
  bool converged = false;  ///< the last step was within the tolerances (else max_iterations ended it)

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// kInvalidArgument naming the field of `params` out of range.
Status validateCalibrationParams(const CalibrationParams& params);

/// One match → solve → update step at `knots` (the steps of calibrateCameraOnRun and of calibrateCamera): the
/// corners matched at `camera` (its time_offset the start), solved, `record` filled and `camera` updated; the
/// solution returned (its refined knots). kFailedPrecondition (`source` named) for fewer than min_matches matches;
/// the solver's errors.
Result<CalibrationSolution> calibrationStep(const std::vector<CornerDetection>& corners, const Track& map,
                                            const std::vector<OdometrySample>& odometry, const DriftKnots& knots,
                                            const Eigen::Matrix3d& input_body_R_camera, const CalibrationParams& params,
                                            const std::string& source, CameraModel& camera, CalibrationIteration& record);
/// Whether a step moved less than the tolerances (CalibrationParams::converged_*).
bool calibrationStepConverged(const CalibrationIteration& record, const CalibrationParams& params);
/// `result` completed from its last iteration and the final `camera`.
void finishCameraCalibration(const CameraModel& camera, CameraCalibration& result);

/// calibrateCamera without runs, for a flight so far held in memory (the streaming pipeline's self-calibration):
/// `corners` (camera clock), the `odometry` and the `keyframes` the run made of it so far give the first drift
/// knots (VioDriftTrack::knotsFromKeyframes); then match → solve → update, each next match at the solve's refined
/// knots and the updated camera (no run again), until the steps are within the tolerances or max_iterations.
/// `camera.time_offset` is the start. Errors as calibrateCamera's (`source` names the flight in them).
Result<CameraCalibration> calibrateCameraOnRun(const std::vector<CornerDetection>& corners, const Track& map,
                                               const CameraModel& camera, const std::vector<OdometrySample>& odometry,
                                               const std::vector<CorrectedPose>& keyframes,
                                               const CalibrationParams& params, const std::string& source);

}  // namespace dualgraph
