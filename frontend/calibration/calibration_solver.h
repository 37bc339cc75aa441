// SPDX-License-Identifier: MIT
// solveCameraCalibration: clock offset, mount rotation and the VIO frame's drift from gate corners (robust LM).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/calibration/gate_corner_matching.h"
#include "dualgraph/frontend/calibration/vio_drift_track.h"
#include "dualgraph/frontend/gates/camera_model.h"

namespace dualgraph {

/// What solveCameraCalibration estimates and how.
struct CalibrationSolverParams {
  /// true: the drift track's knots are estimated together with the camera (the VIO's drift cannot then
  /// absorb a calibration error); false: they stay as given (the trajectory of a run held fixed).
  bool refine_trajectory = true;
  /// Prior between consecutive knots, a random walk per √s of knot spacing: offset [m/√s] and yaw [rad/√s].
  /// Weak on purpose (many times a racing VIO's drift): it only carries the track across knots without
  /// detections.
  double knot_sigma_offset = 0.5;
  double knot_sigma_yaw = 0.05;
  /// true: each map gate seen gets a correction (offset, yaw about the world z axis through its centre) with a
  /// Gaussian prior of the map's stated accuracy below: a surveyed gate is centimetres off, and over a few gates
  /// that error would otherwise go into the mount rotation (5 cm at 5 m is 0.6°).
  bool refine_gates = true;
  double gate_sigma_position = 0.05;  ///< [m] per axis
  double gate_sigma_yaw = 0.026;      ///< [rad] (1.5°)
  /// Which of the camera's parts are unknowns; a part not estimated is held at its given value (its σ then 0): the
  /// step-down of a calibration that cannot carry both (SelfCalibrator). At least one must be estimated.
  bool estimate_time_offset = true;
  bool estimate_mount = true;
  int max_iterations = 50;            ///< Levenberg–Marquardt steps per robust pass
  int robust_passes = 2;              ///< each pass re-estimates the Cauchy scale from the residuals, ≥ 1
  double min_robust_sigma_px = 0.1;   ///< floor of the estimated corner noise [px]
  double time_step = 5e-4;            ///< central-difference step of ∂pixel/∂δ [s]
};

/// The correction of one map gate (CalibrationSolverParams::refine_gates): its centre moved by `offset` [m, world],
/// then turned by `yaw` [rad] about the world z axis.
struct GateCorrection {
  int gate_id = -1;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  double yaw = 0.0;
};

/// The estimate and how well it explains the corners.
///
/// Model of one corner of one matched detection stamped t: with τ = t − δ,
///   pixel = π(K, body_R_camera⁻¹ · (world_T_body(τ)⁻¹ · p_world − body_t_camera)),
///   world_T_body(τ) from the odometry under the drift correction's knots (VioDriftTrack),
/// residual r = pixel − observed [px], Cauchy loss ρ(‖r‖²) = c² log(1 + ‖r‖²/c²) with c = 2.385 σ̂ and σ̂ the
/// corner noise per coordinate estimated as median ‖r‖ / 1.1774 (robust_passes times). Unknowns: δ [s], a
/// right rotation ω of body_R_camera (body_R_camera · Exp(ω), [rad]), with refine_trajectory the knots, with
/// refine_gates a correction per gate (Gaussian priors: the knots' random walk, the gates' stated accuracy).
/// body_t_camera (the mount's translation) is not estimated: a centimetre of it moves a gate 5 m away by ≈ 0.6 px,
/// and the drift offsets take up most of that. Jacobians analytic except ∂/∂δ (central difference through the
/// odometry's interpolation).
struct CalibrationSolution {
  double time_offset = 0.0;  ///< δ [s] (CameraModel::time_offset)
  Eigen::Matrix3d body_R_camera = Eigen::Matrix3d::Identity();
  DriftKnots knots;                   ///< after the solve (as given when not refined)
  std::vector<GateCorrection> gates;  ///< per gate seen, by id (zero when not refined)
  /// 1σ from σ̂²(JᵀWJ)⁻¹, knots and gates marginalised [s] (formal: the drift between knots is not modelled)
  double time_offset_sigma = 0.0;
  Eigen::Vector3d rotation_sigma = Eigen::Vector3d::Zero();  ///< 1σ of ω per body-camera axis [rad]
  double rms_px = 0.0;                                       ///< RMS corner residual over every corner used [px]
  double inlier_rms_px = 0.0;                                ///< over the corners within 3c
  double robust_sigma_px = 0.0;                              ///< σ̂ of the last pass [px]
  int detections = 0;                                        ///< matches with a pose (inside the odometry)
  int corners = 0;                                           ///< corners in front of the camera
  int inlier_corners = 0;
  int iterations = 0;      ///< LM steps over all passes
  bool converged = false;  ///< the last pass's steps fell below 1e-7 (s, rad, m) before max_iterations
};

/// Minimises the robust reprojection cost above from (time_offset, camera.body_T_camera, knots) by
/// Levenberg–Marquardt on the dense normal equations (δ, ω, every ψ_k and c_k, 4 per gate: 4 + 4K + 4G unknowns).
/// kInvalidArgument for invalid parameters or an invalid camera, kFailedPrecondition for fewer than 8 matches
/// inside the odometry, kNumericalError when the normal equations are singular (e.g. every match at one instant).
Result<CalibrationSolution> solveCameraCalibration(const std::vector<GateCornerMatch>& matches,
                                                   const std::vector<OdometrySample>& odometry,
                                                   const CameraModel& camera, double time_offset,
                                                   const DriftKnots& knots, const CalibrationSolverParams& params = {});

}  // namespace dualgraph
