// SPDX-License-Identifier: MIT
// Odometry files (TUM with optional covariances, OpenVINS traj_estimate, EuRoC CSV), relative covariances and increments.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/dual_graph/odometry_history.h"

namespace dualgraph {

/// What an odometry file holds. `samples` are in strictly increasing time with unit rotations and
/// `relative_covariance` unset; `absolute_covariances` is empty or has one entry per sample: the 6×6
/// covariance of the pose odom_T_body itself, metric [t; θ] (m², rad²), a right perturbation in the
/// body frame (odom_T_body_true = odom_T_body · exp(ε)), as VIO estimators report it. Kept apart from
/// `relative_covariance` on purpose: an absolute covariance fed to the Localizer as a relative one
/// would grow without bound. `toRelativeCovariances` makes the relative ones.
/// An all-zero entry means "unknown" (ROS's convention; OpenVINS and recorders write zeros before the filter has
/// a covariance, or a recorder writes none): that sample's increment and the next one use the Localizer's
/// per-metre model.
struct OdometryLog {
  std::vector<OdometrySample> samples;
  std::vector<Matrix6d> absolute_covariances;
  /// Rows the reader found all zero or partly zero (a zero variance in a matrix that is not positive definite)
  /// and stored as unknown (all zero).
  int unknown_covariance_rows = 0;
};

/// True for a covariance that says "unknown" rather than a wrong value: all zero, or a zero variance on the
/// diagonal of a matrix that is not positive definite (a block the filter has not estimated yet).
bool isUnknownCovariance(const Matrix6d& covariance);

/// TUM: `t tx ty tz qx qy qz qw` (t in s, translation in m, Hamilton quaternion [x y z w] of
/// odom_T_body), optionally followed by the 21 upper-triangular entries (row by row) of the absolute
/// covariance described at OdometryLog. Space- or comma-separated, `#` comments, blank lines
/// skipped. Every row must have the same form (8 or 29 fields). Also reads OpenVINS' TUM-like
/// trajectories without covariance; its 20-column layout is refused here (readOpenVinsOdometry reads it,
/// readTrajectory recognises it).
Result<OdometryLog> readTumOdometry(const std::string& path);

/// OpenVINS' `traj_estimate.txt` (ov_eval's format): `t tx ty tz qx qy qz qw Pr11 Pr12 Pr13 Pr22 Pr23 Pr33
/// Pt11 Pt12 Pt13 Pt22 Pt23 Pt33` — t [s], odom_T_body as TUM (the IMU in OpenVINS' global frame), then the
/// upper triangles of the orientation covariance Pr [rad²] and the position covariance Pt [m²]. OpenVINS'
/// orientation error is a rotation in the body (IMU) frame — its JPL error on q_GtoI is a right perturbation of
/// odom_R_body — and its position error is additive in the odometry (global) frame. Converted explicitly to
/// OdometryLog's convention (metric [t; θ], right perturbation in the body frame): Σ_tt = Rᵀ·Pt·R with R =
/// odom_R_body of that row, Σ_θθ = Pr, Σ_tθ = 0 (the file holds no cross terms). Every row has 20 fields;
/// a covariance that is not finite, symmetric and positive definite is an error naming the line.
Result<OdometryLog> readOpenVinsOdometry(const std::string& path);

/// EuRoC/ASL CSV (e.g. `state_groundtruth_estimate0/data.csv`): the first non-blank line must be the
/// header, such as
/// `#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []`
/// (columns matched by name, units in brackets ignored, any order); t in integer nanoseconds (stored
/// in seconds), quaternion w first, R = odometry frame, S = body. The other standard columns
/// (v_RS_R_*, b_w_RS_S_*, b_a_RS_S_*) are ignored; an unknown or repeated column is an error naming it.
/// No covariance.
Result<OdometryLog> readEurocOdometry(const std::string& path);

class RowReader;

/// One TUM row as readTumOdometry reads it (8 fields, or 29 with the absolute covariance): `sample` gets t [s] and
/// odom_T_body; `covariance` the row's covariance (all zero when unknown, isUnknownCovariance; otherwise checked),
/// empty for 8 fields. Errors name the row's source, line and field; the order of stamps is the caller's.
Status readTumRow(const RowReader& row, OdometrySample& sample, std::optional<Matrix6d>& covariance);

/// A trajectory file's format, as readTrajectory recognised it.
enum class TrajectoryFormat {
  kTum,            ///< 8 columns, no covariance
  kTumCovariance,  ///< 8 + the 21 absolute-covariance columns (this project's own)
  kOpenVins,       ///< OpenVINS traj_estimate.txt, 20 columns
  kEuroc,          ///< EuRoC/ASL CSV with its header
};
/// "TUM", "TUM + covariance", "OpenVINS traj_estimate", "EuRoC CSV".
const char* trajectoryFormatName(TrajectoryFormat format);

/// A trajectory or odometry file in any of the four formats, recognised from its content: a EuRoC/ASL header
/// (first non-blank line starting `#timestamp` or naming `p_RS_R_x`) is readEurocOdometry (nanoseconds, w
/// first); OpenVINS' header (a comment naming `Pr11`, unless the data rows have 8 fields: poses only, read as
/// TUM) or a first data row of 20 fields is readOpenVinsOdometry;
/// otherwise readTumOdometry (8 fields: kTum, 29: kTumCovariance). `format` (optional) says which. The
/// readers' own errors (file:line: field).
Result<OdometryLog> readTrajectory(const std::string& path, TrajectoryFormat* format = nullptr);

/// How many eigenvalues `toRelativeCovariances` had to raise to its floor (a sign that the absolute
/// covariances are not a random walk, e.g. they shrank after a loop closure or a reset).
struct RelativeCovarianceReport {
  int clamped = 0;
  int shrinks = 0;  ///< samples whose covariance really shrank (RelativeCovarianceStream::shrinks)
};

/// Fills `samples[k].relative_covariance` (k ≥ 1) from the absolute covariances: for a random-walk
/// error with increment inc = odom_T_body(k-1)⁻¹ · odom_T_body(k),
/// Σ_k = Ad(inc⁻¹) Σ_{k-1} Ad(inc⁻¹)ᵀ + Σ_rel, so Σ_rel = Σ_k − Ad(inc⁻¹) Σ_{k-1} Ad(inc⁻¹)ᵀ,
/// symmetrised, with eigenvalues raised to max(floor, 1e-11 · largest) so that `checkCovariance`
/// accepts the result. Sample 0 has no previous sample and gets none. kFailedPrecondition when the
/// log has no absolute covariances (or not one per sample), kInvalidArgument when floor ≤ 0,
/// kNumericalError naming the sample when a covariance is not finite.
Result<RelativeCovarianceReport> toRelativeCovariances(OdometryLog& log, double floor = 1e-10);

/// The increment odom_T_body(a)⁻¹ · odom_T_body(b) between samples `a` and `b` (indices, any order).
/// kInvalidArgument when an index is out of range.
Result<Eigen::Isometry3d> odometryIncrement(const std::vector<OdometrySample>& samples, size_t a, size_t b);
/// The same between two instants [s] inside the samples' time span, poses interpolated along the
/// geodesic between the neighbouring samples (`odometryPoseAt`, dual_graph/odometry_history.h); kFailedPrecondition outside it.
/// `samples` must be in increasing time (as the readers return them).
Result<Eigen::Isometry3d> odometryIncrementBetween(const std::vector<OdometrySample>& samples, double t_a, double t_b);

}  // namespace dualgraph
