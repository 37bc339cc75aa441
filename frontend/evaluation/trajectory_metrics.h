// SPDX-License-Identifier: MIT
// Trajectory accuracy: an estimate against ground truth by time stamp — association (trajectory_association.h),
// SE(3) / Sim(3) / 4-DoF / origin / no alignment, ATE (position and rotation) and RPE (relative_pose_error.h).
// One library for `dualgraph run` and `dualgraph eval`; no I/O, no OpenCV.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/evaluation/relative_pose_error.h"
#include "dualgraph/frontend/evaluation/trajectory_association.h"
#include "dualgraph/frontend/io/trajectory_io.h"
#include "dualgraph/dual_graph/measurements.h"

namespace dualgraph {

/// How the estimate frame is related to world before the absolute errors are taken.
enum class TrajectoryAlignment {
  kSE3,     ///< Umeyama without scale: rotation + translation minimising Σ|p_gt − (R p_est + t)|² (evo `-a`)
  kFourDof, ///< translation + yaw about world z (gravity known, as for VIO), same least squares
  kNone,    ///< world_T_estimate = identity (the world frame is known, as in simulation; evo's default)
  kSim3,    ///< Umeyama with scale: minimising Σ|p_gt − (s R p_est + t)|² (evo `-as`)
  kOrigin,  ///< the first associated estimate pose made equal to its ground truth: gt_0 · est_0⁻¹ (evo `--align_origin`)
};
/// "se3", "4dof", "none", "sim3" or "origin".
const char* trajectoryAlignmentName(TrajectoryAlignment alignment);
/// The inverse of trajectoryAlignmentName; kInvalidArgument naming the text otherwise.
Result<TrajectoryAlignment> parseTrajectoryAlignment(const std::string& name);

/// An alignment's result: p_world = scale · R · p_est + t with world_T_estimate = [R | t]; rotations are
/// mapped by R alone. scale is 1 except for kSim3.
struct AlignmentTransform {
  Eigen::Isometry3d world_T_estimate = Eigen::Isometry3d::Identity();  ///< [R | t] [m]
  double scale = 1.0;                                                   ///< s (dimensionless)

  /// world_T_body of an estimate pose: rotation R·R_est, position s·R·p_est + t.
  Eigen::Isometry3d apply(const Eigen::Isometry3d& estimate_T_body) const;

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// The transform minimising Σ|p_gt − (s·R·p_est + t)|² over the associated positions: kSE3 in closed form
/// (Umeyama 1991 without scale: SVD of the cross-covariance, reflection turned into a rotation with
/// diag(1, 1, det(U V^T))), kSim3 the same with Umeyama's scale s = tr(D S) / σ²_est, kFourDof in closed form
/// (yaw = atan2 of the 2-D cross-covariance after centering, z by the mean), kOrigin gt_0 · est_0⁻¹ of the
/// first associated pair (no least squares), kNone the identity. kFailedPrecondition with fewer than 3
/// associated poses for kSE3/kSim3/kFourDof, or for kSim3 when the estimate's positions do not spread (σ² = 0).
/// With collinear positions (a straight flight) the rotation about that line is not determined by the
/// positions; the SVD then picks one, which leaves the position ATE at its minimum but makes the rotation
/// ATE arbitrary about that axis.
Result<AlignmentTransform> alignTrajectory(const TrajectoryAssociation& association, TrajectoryAlignment alignment);

/// What evaluateTrajectory does.
struct TrajectoryMetricsParams {
  TrajectoryAlignment alignment = TrajectoryAlignment::kSE3;  ///< for ate_m, ate_rot_deg, ate_stats, the RPE's scale
  double max_gap_s = 0.1;                         ///< association gap [s], see associateByTime
  double max_dt_s = 0.0;  ///< > 0: associateByNearestStamp within max_dt_s [s] instead (max_gap_s unused)
  bool evo_association = false;  ///< with max_dt_s > 0: associateAsEvo (pairs from the sparser trajectory) instead
  std::vector<double> rpe_distances_m{1.0, 10.0};  ///< RPE windows Δ [m]
  std::vector<long> rpe_frames;                    ///< RPE windows Δ [associated poses] (evo's default: 1)
  RpePairing rpe_pairing = RpePairing::kEveryPose;  ///< the pairs of every RPE window
};

/// Accuracy of an estimate against ground truth. Position ATE: RMSE over the associated poses of
/// |p_gt − (scale · R · p_est + t)| [m]. Rotation ATE: RMSE of the geodesic angle of
/// R_gt⁻¹ · (world_T_estimate · estimate_T_body)_R [deg].
struct TrajectoryMetrics {
  TrajectoryAlignment alignment = TrajectoryAlignment::kSE3;        ///< the one asked for
  Eigen::Isometry3d world_T_estimate = Eigen::Isometry3d::Identity();  ///< from that alignment [m]
  double scale = 1.0;            ///< that alignment's scale (kSim3; 1 otherwise)
  double ate_m = 0.0;            ///< position ATE with that alignment [m]
  double ate_rot_deg = 0.0;      ///< rotation ATE with that alignment [deg]
  double ate_se3_m = 0.0;        ///< position ATE after SE(3) alignment [m]; NaN below 3 poses
  double ate_4dof_m = 0.0;       ///< position ATE after 4-DoF alignment [m]; NaN below 3 poses
  double ate_unaligned_m = 0.0;  ///< position ATE without alignment [m]
  ErrorStatistics ate_stats;     ///< the position errors with the alignment asked for (rmse = ate_m) [m]
  std::vector<RelativePoseError> rpe;  ///< one per TrajectoryMetricsParams::rpe_distances_m, same order
  std::vector<RelativePoseError> rpe_frames;  ///< one per TrajectoryMetricsParams::rpe_frames, same order
  long estimate_poses = 0;       ///< poses in the estimate
  long associated = 0;           ///< pairs (the ATE's sample count)
  bool paired_from_ground_truth = false;  ///< see TrajectoryAssociation: the counters below count GT poses
  long paired_from_poses = 0;    ///< poses of the trajectory paired from (estimate_poses unless from the GT)
  long before_span = 0;          ///< see TrajectoryAssociation
  long after_span = 0;
  long beyond_gap = 0;

  long unassociated() const { return before_span + after_span + beyond_gap; }
};

/// Aligns and measures an association already made (associateByTime or associateByNearestStamp) of an estimate
/// of `estimate_poses` poses; `params.max_gap_s`, `max_dt_s` and `evo_association` are not used. Errors of
/// alignTrajectory, relativePoseError and relativePoseErrorFrames.
Result<TrajectoryMetrics> evaluateAssociation(const TrajectoryAssociation& association, size_t estimate_poses,
                                              const TrajectoryMetricsParams& params = {});

/// Associates (associateByNearestStamp when params.max_dt_s > 0, associateAsEvo if params.evo_association too,
/// else associateByTime), then evaluateAssociation.
/// Errors: those of the association, alignTrajectory (too few associated poses) and relativePoseError (a bad Δ).
Result<TrajectoryMetrics> evaluateTrajectory(const StampedPoses& world_T_body_gt, const StampedPoses& estimate_T_body,
                                             const TrajectoryMetricsParams& params = {});

}  // namespace dualgraph
