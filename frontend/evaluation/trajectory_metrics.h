// SPDX-License-Identifier: MIT
// Trajectory accuracy: an estimate against ground truth by time stamp — association (interpolated or nearest
// stamp), SE(3) / Sim(3) / 4-DoF / origin / no alignment, ATE (position and rotation) and RPE over distance
// windows. One library for `dualgraph run` and `dualgraph eval`; no I/O, no OpenCV.
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

/// evo's association: every estimate pose paired with the ground-truth sample of the nearest stamp (not
/// interpolated) when it lies within `max_dt_s` [s] (inclusive; ties to the earlier sample). evo pairs from the
/// shorter trajectory; this pairs from the estimate, the same pairs when the ground truth is the denser one.
/// Stamps outside the GT span by more than max_dt_s count as before/after the span, the others without a
/// sample that close as beyond the gap. Errors as associateByTime (max_dt_s named for the gap).
Result<TrajectoryAssociation> associateByNearestStamp(const StampedPoses& world_T_body_gt,
                                                      const StampedPoses& estimate_T_body, double max_dt_s);

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

/// Relative pose error over a travelled-distance window Δ. Pairs (i, j), i < j over the associated
/// poses, j the first pose at which the GT path length from i (sum of the straight segments between
/// consecutive associated GT positions) reaches Δ; one pair per i, none once the rest of the path is
/// shorter than Δ (as rpg_trajectory_evaluation, but the first pose reaching Δ rather than the closest).
/// Error as TUM's RPE (Sturm et al. 2012): E = (gt_i⁻¹ gt_j)⁻¹ (est_i⁻¹ est_j), translational error
/// |t(E)| = |t(est_i⁻¹ est_j) − t(gt_i⁻¹ gt_j)| [m], rotational error the angle of R(E) [deg]; both RMSE over
/// the pairs. Alignment-free: any fixed world_T_estimate cancels; a scale does not, so `scale` multiplies the
/// estimate's relative translations (kSim3's, as evo's RPE after `-as`). NaN RMSEs when there are no pairs.
struct RelativePoseError {
  double distance_m = 0.0;                 ///< Δ [m]
  long pairs = 0;                          ///< number of pairs (i, j)
  double translation_rmse_m = 0.0;         ///< RMSE of |t(E)| [m]
  double rotation_rmse_deg = 0.0;          ///< RMSE of angle(R(E)) [deg]
};

/// The RPE for one Δ [m] (> 0 and finite, else kInvalidArgument).
Result<RelativePoseError> relativePoseError(const TrajectoryAssociation& association, double distance_m,
                                            double scale = 1.0);

/// What evaluateTrajectory does.
struct TrajectoryMetricsParams {
  TrajectoryAlignment alignment = TrajectoryAlignment::kSE3;  ///< for ate_m, ate_rot_deg, ate_stats, the RPE's scale
  double max_gap_s = 0.1;                         ///< association gap [s], see associateByTime
  double max_dt_s = 0.0;  ///< > 0: associateByNearestStamp within max_dt_s [s] instead (max_gap_s unused)
  std::vector<double> rpe_distances_m{1.0, 10.0};  ///< RPE windows Δ [m]
};

/// evo's statistics of the position errors |p_gt − world_T_estimate · p_est| over the associated poses [m]
/// (std: the population's, as numpy's default).
struct ErrorStatistics {
  double rmse = 0.0, mean = 0.0, median = 0.0, std = 0.0, min = 0.0, max = 0.0;
};
/// Those statistics of any non-negative errors (all zero when `errors` is empty).
ErrorStatistics errorStatistics(std::vector<double> errors);

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
  long estimate_poses = 0;       ///< poses in the estimate
  long associated = 0;           ///< poses with ground truth (the ATE's sample count)
  long before_span = 0;          ///< see TrajectoryAssociation
  long after_span = 0;
  long beyond_gap = 0;

  long unassociated() const { return before_span + after_span + beyond_gap; }
};

/// Aligns and measures an association already made (associateByTime or associateByNearestStamp) of an estimate
/// of `estimate_poses` poses; `params.max_gap_s` and `max_dt_s` are not used. Errors of alignTrajectory and
/// relativePoseError.
Result<TrajectoryMetrics> evaluateAssociation(const TrajectoryAssociation& association, size_t estimate_poses,
                                              const TrajectoryMetricsParams& params = {});

/// Associates (associateByNearestStamp when params.max_dt_s > 0, else associateByTime), then evaluateAssociation.
/// Errors: those of the association, alignTrajectory (too few associated poses) and relativePoseError (a bad Δ).
Result<TrajectoryMetrics> evaluateTrajectory(const StampedPoses& world_T_body_gt, const StampedPoses& estimate_T_body,
                                             const TrajectoryMetricsParams& params = {});

}  // namespace dualgraph
