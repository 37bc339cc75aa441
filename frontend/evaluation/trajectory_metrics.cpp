// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/evaluation/trajectory_metrics.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
namespace {

constexpr double kRadToDeg = 180.0 / EIGEN_PI;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Position RMSE [m] and rotation RMSE [deg] of the aligned estimate against the GT.
std::pair<double, double> absoluteErrors(const TrajectoryAssociation& association, const AlignmentTransform& alignment) {
  double sum_position = 0.0;
  double sum_rotation = 0.0;
  for (size_t k = 0; k < association.size(); ++k) {
    const Eigen::Isometry3d& world_T_body_gt = association.world_T_body_gt[k].second;
    const Eigen::Isometry3d world_T_body_est = alignment.apply(association.estimate_T_body[k].second);
    sum_position += (world_T_body_gt.translation() - world_T_body_est.translation()).squaredNorm();
    const double angle = so3Log(world_T_body_gt.linear().transpose() * world_T_body_est.linear()).norm();
    sum_rotation += angle * angle;
  }
  const double n = static_cast<double>(association.size());
  return {std::sqrt(sum_position / n), std::sqrt(sum_rotation / n) * kRadToDeg};
}

ErrorStatistics positionErrorStatistics(const TrajectoryAssociation& association, const AlignmentTransform& alignment) {
  std::vector<double> errors(association.size());
  for (size_t k = 0; k < association.size(); ++k) {
    errors[k] = (association.world_T_body_gt[k].second.translation() -
                 alignment.apply(association.estimate_T_body[k].second).translation()).norm();
  }
  return errorStatistics(std::move(errors));
}

/// Means of the associated GT and estimate positions.
std::pair<Eigen::Vector3d, Eigen::Vector3d> meanPositions(const TrajectoryAssociation& association) {
  Eigen::Vector3d mean_gt = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_est = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < association.size(); ++k) {
    mean_gt += association.world_T_body_gt[k].second.translation();
    mean_est += association.estimate_T_body[k].second.translation();
  }
  const double n = static_cast<double>(association.size());
  return {mean_gt / n, mean_est / n};
}

/// Closed-form rotation of the alignment: Umeyama (SE(3), Sim(3)) or yaw about z (4-DoF); for kSim3 `scale`
/// gets Umeyama's s = tr(D S) / σ²_est (0 when the estimate's positions do not spread).
Eigen::Matrix3d alignmentRotation(const TrajectoryAssociation& association, TrajectoryAlignment alignment,
                                  const Eigen::Vector3d& mean_gt, const Eigen::Vector3d& mean_est, double& scale) {
  scale = 1.0;
  Eigen::Matrix3d cross_covariance = Eigen::Matrix3d::Zero();  // Σ (p_gt − μ_gt)(p_est − μ_est)ᵀ
  for (size_t k = 0; k < association.size(); ++k) {
    cross_covariance += (association.world_T_body_gt[k].second.translation() - mean_gt) *
                        (association.estimate_T_body[k].second.translation() - mean_est).transpose();
  }
  if (alignment == TrajectoryAlignment::kFourDof) {
    // Maximise Σ g_xyᵀ Rz(ψ) e_xy = cos ψ (Hxx + Hyy) + sin ψ (Hyx − Hxy).
    const double yaw = std::atan2(cross_covariance(1, 0) - cross_covariance(0, 1),
                                  cross_covariance(0, 0) + cross_covariance(1, 1));
    return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  // Maximise tr(R Hᵀ) over rotations: R = U diag(1, 1, det(U Vᵀ)) Vᵀ (the last sign turns a
  // reflection into the best proper rotation).
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cross_covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d signs(1.0, 1.0, (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0);
  if (alignment == TrajectoryAlignment::kSim3) {
    double spread = 0.0;  // n · σ²_est; the cross-covariance above is n · H, so the n cancels
    for (size_t k = 0; k < association.size(); ++k) {
      spread += (association.estimate_T_body[k].second.translation() - mean_est).squaredNorm();
    }
    scale = spread > 0.0 ? svd.singularValues().dot(signs) / spread : 0.0;
  }
  return svd.matrixU() * signs.asDiagonal() * svd.matrixV().transpose();
}

}  // namespace

const char* trajectoryAlignmentName(TrajectoryAlignment alignment) {
  switch (alignment) {
    case TrajectoryAlignment::kSE3: return "se3";
    case TrajectoryAlignment::kFourDof: return "4dof";
    case TrajectoryAlignment::kNone: return "none";
    case TrajectoryAlignment::kSim3: return "sim3";
    case TrajectoryAlignment::kOrigin: return "origin";
  }
  return "unknown";
}

Result<TrajectoryAlignment> parseTrajectoryAlignment(const std::string& name) {
  for (const TrajectoryAlignment alignment : {TrajectoryAlignment::kSE3, TrajectoryAlignment::kFourDof, TrajectoryAlignment::kNone,
                                              TrajectoryAlignment::kSim3, TrajectoryAlignment::kOrigin}) {
    if (name == trajectoryAlignmentName(alignment)) return alignment;
  }
  return Status(StatusCode::kInvalidArgument, "unknown alignment '" + name + "' (se3, sim3, 4dof, origin or none)");
}

Eigen::Isometry3d AlignmentTransform::apply(const Eigen::Isometry3d& estimate_T_body) const {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = world_T_estimate.linear() * estimate_T_body.linear();
  out.translation() = scale * (world_T_estimate.linear() * estimate_T_body.translation()) + world_T_estimate.translation();
  return out;
}

Result<AlignmentTransform> alignTrajectory(const TrajectoryAssociation& association, TrajectoryAlignment alignment) {
  AlignmentTransform out;
  if (alignment == TrajectoryAlignment::kNone) return out;
  if (alignment == TrajectoryAlignment::kOrigin) {
    if (association.size() == 0) return Status(StatusCode::kFailedPrecondition, "origin alignment needs an associated pose");
    out.world_T_estimate = association.world_T_body_gt.front().second * association.estimate_T_body.front().second.inverse();
    return out;
  }
  if (association.size() < 3) {
    return Status(StatusCode::kFailedPrecondition,
                  std::string(trajectoryAlignmentName(alignment)) + " alignment needs at least 3 associated poses, got " +
                      std::to_string(association.size()));
  }
  const auto [mean_gt, mean_est] = meanPositions(association);
  out.world_T_estimate.linear() = alignmentRotation(association, alignment, mean_gt, mean_est, out.scale);
  if (!(out.scale > 0.0)) {
    return Status(StatusCode::kFailedPrecondition, "sim3 alignment: the estimate's positions do not spread (no scale)");
  }
  out.world_T_estimate.translation() = mean_gt - out.scale * (out.world_T_estimate.linear() * mean_est);
  return out;
}

Result<TrajectoryMetrics> evaluateTrajectory(const StampedPoses& world_T_body_gt, const StampedPoses& estimate_T_body,
                                             const TrajectoryMetricsParams& params) {
  const auto association =
      params.max_dt_s <= 0.0   ? associateByTime(world_T_body_gt, estimate_T_body, params.max_gap_s)
      : params.evo_association ? associateAsEvo(world_T_body_gt, estimate_T_body, params.max_dt_s)
                               : associateByNearestStamp(world_T_body_gt, estimate_T_body, params.max_dt_s);
  if (!association.ok()) return association.status();
  return evaluateAssociation(*association, estimate_T_body.size(), params);
}

Result<TrajectoryMetrics> evaluateAssociation(const TrajectoryAssociation& association, size_t estimate_poses,
                                              const TrajectoryMetricsParams& params) {
  const auto alignment = alignTrajectory(association, params.alignment);
  if (!alignment.ok()) return alignment.status();

  TrajectoryMetrics metrics;
  metrics.alignment = params.alignment;
  metrics.world_T_estimate = alignment->world_T_estimate;
  metrics.scale = alignment->scale;
  std::tie(metrics.ate_m, metrics.ate_rot_deg) = absoluteErrors(association, *alignment);
  metrics.ate_stats = positionErrorStatistics(association, *alignment);
  const auto se3 = alignTrajectory(association, TrajectoryAlignment::kSE3);
  const auto four_dof = alignTrajectory(association, TrajectoryAlignment::kFourDof);
  metrics.ate_se3_m = se3.ok() ? absoluteErrors(association, *se3).first : kNaN;
  metrics.ate_4dof_m = four_dof.ok() ? absoluteErrors(association, *four_dof).first : kNaN;
  metrics.ate_unaligned_m = absoluteErrors(association, AlignmentTransform{}).first;
  for (const double distance_m : params.rpe_distances_m) {
    const auto rpe = relativePoseError(association, distance_m, alignment->scale, params.rpe_pairing);
    if (!rpe.ok()) return rpe.status();
    metrics.rpe.push_back(*rpe);
  }
  for (const long frames : params.rpe_frames) {
    const auto rpe = relativePoseErrorFrames(association, frames, alignment->scale, params.rpe_pairing);
    if (!rpe.ok()) return rpe.status();
    metrics.rpe_frames.push_back(*rpe);
  }
  metrics.estimate_poses = static_cast<long>(estimate_poses);
  metrics.associated = static_cast<long>(association.size());
  metrics.paired_from_ground_truth = association.paired_from_ground_truth;
  metrics.paired_from_poses = association.paired_from_ground_truth || association.paired_from_poses > 0
                                  ? association.paired_from_poses
                                  : metrics.estimate_poses;
  metrics.before_span = association.before_span;
  metrics.after_span = association.after_span;
  metrics.beyond_gap = association.beyond_gap;
  return metrics;
}

}  // namespace dualgraph
