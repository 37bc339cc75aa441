// SPDX-License-Identifier: MIT
// Trajectory accuracy (DESIGN.md §5): an estimate against ground truth by time stamp — association
// with interpolation, SE(3) / 4-DoF / no alignment, ATE (position and rotation) and RPE over
// distance windows. One library for `dualgraph run` and `dualgraph eval`; no I/O, no OpenCV.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/io/trajectory_io.h"
#include "dualgraph/dual_graph/measurements.h"

namespace dualgraph {

/// How the estimate frame is related to world before the absolute errors are taken.
enum class TrajectoryAlignment {
  kSE3,     ///< Umeyama without scale: rotation + translation minimising Σ|p_gt − (R p_est + t)|²
  kFourDof, ///< translation + yaw about world z (gravity known, as for VIO), same least squares
  kNone,    ///< world_T_estimate = identity (the world frame is known, as in simulation)
};
/// "se3", "4dof" or "none".
const char* trajectoryAlignmentName(TrajectoryAlignment alignment);
/// The inverse of trajectoryAlignmentName; kInvalidArgument naming the text otherwise.
Result<TrajectoryAlignment> parseTrajectoryAlignment(const std::string& name);

/// Estimate poses paired with ground truth at the estimate's time stamps. The ground truth at t is
/// interpolated between the GT samples around t: translation linearly, rotation by slerp.
/// Every estimate pose is either associated or counted in exactly one of the three counters.
struct TrajectoryAssociation {
  std::vector<size_t> estimate_index;  ///< index into the estimate of each associated pose
  StampedPoses world_T_body_gt;        ///< interpolated ground truth at those stamps [s, m]
  StampedPoses estimate_T_body;        ///< the estimate poses themselves [s, m]
  long before_span = 0;  ///< estimate stamps earlier than the first GT sample
  long after_span = 0;   ///< estimate stamps later than the last GT sample
  long beyond_gap = 0;   ///< inside the GT span, but the nearest GT sample is more than max_gap_s away

  size_t size() const { return estimate_index.size(); }
  long unassociated() const { return before_span + after_span + beyond_gap; }
};

/// Pairs every estimate pose whose stamp lies inside the GT span [t_first, t_last] and has a GT sample
/// within `max_gap_s` [s] (inclusive) with the interpolated ground truth. Errors: kInvalidArgument
/// when either trajectory is empty, a stamp or pose is not finite, a rotation is not a rotation,
/// stamps do not strictly increase, or max_gap_s is not positive and finite (each naming the
/// trajectory and index); kFailedPrecondition when no estimate stamp lies inside the GT span (the
/// two spans are quoted) or none has GT within the gap.
Result<TrajectoryAssociation> associateByTime(const StampedPoses& world_T_body_gt,
                                              const StampedPoses& estimate_T_body, double max_gap_s = 0.1);

/// world_T_estimate minimising Σ|p_gt − world_T_estimate · p_est|² over the associated positions:
/// kSE3 in closed form (Umeyama 1991 without scale: SVD of the cross-covariance, reflection turned
/// into a rotation with diag(1, 1, det(U V^T))), kFourDof in closed form (yaw = atan2 of the 2-D
/// cross-covariance after centering, z by the mean), kNone the identity. kFailedPrecondition with
/// fewer than 3 associated poses for kSE3/kFourDof. With collinear positions (a straight flight) the
/// rotation about that line is not determined by the positions; the SVD then picks one, which leaves
/// the position ATE at its minimum but makes the rotation ATE arbitrary about that axis.
Result<Eigen::Isometry3d> alignTrajectory(const TrajectoryAssociation& association, TrajectoryAlignment alignment);

/// Relative pose error over a travelled-distance window Δ. Pairs (i, j), i < j over the associated
/// poses, j the first pose at which the GT path length from i (sum of the straight segments between
/// consecutive associated GT positions) reaches Δ; one pair per i, none once the rest of the path is
/// shorter than Δ (as rpg_trajectory_evaluation, but the first pose reaching Δ rather than the closest).
/// Error as TUM's RPE (Sturm et al. 2012): E = (gt_i⁻¹ gt_j)⁻¹ (est_i⁻¹ est_j), translational error
/// |t(E)| = |t(est_i⁻¹ est_j) − t(gt_i⁻¹ gt_j)| [m], rotational error the angle of R(E) [deg]; both RMSE over
/// the pairs. Alignment-free: any fixed world_T_estimate cancels. NaN RMSEs when there are no pairs.
struct RelativePoseError {
  double distance_m = 0.0;                 ///< Δ [m]
  long pairs = 0;                          ///< number of pairs (i, j)
  double translation_rmse_m = 0.0;         ///< RMSE of |t(E)| [m]
  double rotation_rmse_deg = 0.0;          ///< RMSE of angle(R(E)) [deg]
};

/// The RPE for one Δ [m] (> 0 and finite, else kInvalidArgument).
Result<RelativePoseError> relativePoseError(const TrajectoryAssociation& association, double distance_m);

/// What evaluateTrajectory does.
struct TrajectoryMetricsParams {
  TrajectoryAlignment alignment = TrajectoryAlignment::kSE3;  ///< for ate_m, ate_rot_deg, world_T_estimate
  double max_gap_s = 0.1;                         ///< association gap [s], see associateByTime
  std::vector<double> rpe_distances_m{1.0, 10.0};  ///< RPE windows Δ [m]
};

/// evo's statistics of the position errors |p_gt − world_T_estimate · p_est| over the associated poses [m]
/// (std: the population's, as numpy's default).
struct ErrorStatistics {
  double rmse = 0.0, mean = 0.0, median = 0.0, std = 0.0, min = 0.0, max = 0.0;
};

/// Accuracy of an estimate against ground truth. Position ATE: RMSE over the associated poses of
/// |p_gt − world_T_estimate · p_est| [m]. Rotation ATE: RMSE of the geodesic angle of
/// R_gt⁻¹ · (world_T_estimate · estimate_T_body)_R [deg].
struct TrajectoryMetrics {
  TrajectoryAlignment alignment = TrajectoryAlignment::kSE3;        ///< the one asked for
  Eigen::Isometry3d world_T_estimate = Eigen::Isometry3d::Identity();  ///< from that alignment [m]
  double ate_m = 0.0;            ///< position ATE with that alignment [m]
  double ate_rot_deg = 0.0;      ///< rotation ATE with that alignment [deg]
  double ate_se3_m = 0.0;        ///< position ATE after SE(3) alignment [m]; NaN below 3 poses
  double ate_4dof_m = 0.0;       ///< position ATE after 4-DoF alignment [m]; NaN below 3 poses
  double ate_unaligned_m = 0.0;  ///< position ATE without alignment [m]
  ErrorStatistics ate_stats;     ///< the position errors with the alignment asked for (rmse = ate_m) [m]
  std::vector<RelativePoseError> rpe;  ///< one per TrajectoryMetricsParams::rpe_distances_m, same order
  long estimate_poses = 0;       ///< poses in the estimate
  long associated = 0;           ///< poses with ground truth (the ATE's sample count)
  long before_span = 0;          ///< see TrajectoryAssociation
  long after_span = 0;
  long beyond_gap = 0;

  long unassociated() const { return before_span + after_span + beyond_gap; }
};

/// Associates, aligns and measures. Errors: those of associateByTime, alignTrajectory (fewer than 3
/// associated poses for kSE3/kFourDof) and relativePoseError (a bad Δ).
Result<TrajectoryMetrics> evaluateTrajectory(const StampedPoses& world_T_body_gt, const StampedPoses& estimate_T_body,
                                             const TrajectoryMetricsParams& params = {});

}  // namespace dualgraph
