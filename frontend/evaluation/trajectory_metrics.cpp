// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/evaluation/trajectory_metrics.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
namespace {

constexpr double kRadToDeg = 180.0 / EIGEN_PI;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A value for messages, 6 significant digits.
std::string formatValue(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  return buffer;
}

/// "[first, last] s" of a non-empty trajectory, for messages.
std::string spanText(const StampedPoses& poses) {
  return "[" + formatTimestamp(poses.front().first) + ", " + formatTimestamp(poses.back().first) + "] s";
}

/// Finite stamps in strictly increasing order and finite rigid poses; `what` names the trajectory.
Status validateTrajectory(const StampedPoses& poses, const std::string& what) {
  if (poses.empty()) return Status(StatusCode::kInvalidArgument, what + " is empty");
  for (size_t i = 0; i < poses.size(); ++i) {
    const std::string where = what + ": pose " + std::to_string(i);
    const double t = poses[i].first;
    if (!std::isfinite(t)) return Status(StatusCode::kInvalidArgument, where + ": time stamp is not finite");
    DG_RETURN_IF_ERROR(checkRigidTransform(poses[i].second, where + " (t = " + formatTimestamp(t) + " s)"));
    if (i > 0 && !(t > poses[i - 1].first)) {
      return Status(StatusCode::kInvalidArgument, where + ": time stamp " + formatTimestamp(t) +
                                                      " s does not increase (previous " +
                                                      formatTimestamp(poses[i - 1].first) + " s)");
    }
  }
  return Status();
}

/// Translation linear, rotation by slerp (shortest arc), alpha ∈ [0, 1].
Eigen::Isometry3d interpolateLinearSlerp(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double alpha) {
  const Eigen::Quaterniond q_a(a.linear());
  const Eigen::Quaterniond q_b(b.linear());
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = q_a.slerp(alpha, q_b).normalized().toRotationMatrix();
  out.translation() = (1.0 - alpha) * a.translation() + alpha * b.translation();
  return out;
}

/// Position RMSE [m] and rotation RMSE [deg] of world_T_estimate · estimate_T_body against the GT.
std::pair<double, double> absoluteErrors(const TrajectoryAssociation& association,
                                         const Eigen::Isometry3d& world_T_estimate) {
  double sum_position = 0.0;
  double sum_rotation = 0.0;
  for (size_t k = 0; k < association.size(); ++k) {
    const Eigen::Isometry3d& world_T_body_gt = association.world_T_body_gt[k].second;
    const Eigen::Isometry3d world_T_body_est = world_T_estimate * association.estimate_T_body[k].second;
    sum_position += (world_T_body_gt.translation() - world_T_body_est.translation()).squaredNorm();
    const double angle = so3Log(world_T_body_gt.linear().transpose() * world_T_body_est.linear()).norm();
    sum_rotation += angle * angle;
  }
  const double n = static_cast<double>(association.size());
  return {std::sqrt(sum_position / n), std::sqrt(sum_rotation / n) * kRadToDeg};
}

ErrorStatistics positionErrorStatistics(const TrajectoryAssociation& association, const Eigen::Isometry3d& world_T_estimate) {
  std::vector<double> errors(association.size());
  for (size_t k = 0; k < association.size(); ++k) {
    errors[k] = (association.world_T_body_gt[k].second.translation() -
                 world_T_estimate * association.estimate_T_body[k].second.translation()).norm();
  }
  ErrorStatistics s;
  if (errors.empty()) return s;
  const double n = static_cast<double>(errors.size());
  double sum = 0.0, sum_squares = 0.0;
  for (const double e : errors) {
    sum += e;
    sum_squares += e * e;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_squares / n);
  double deviation = 0.0;
  for (const double e : errors) deviation += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(deviation / n);
  std::sort(errors.begin(), errors.end());
  const size_t middle = errors.size() / 2;
  s.median = errors.size() % 2 == 1 ? errors[middle] : 0.5 * (errors[middle - 1] + errors[middle]);
  s.min = errors.front();
  s.max = errors.back();
  return s;
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

/// Closed-form rotation of the alignment: Umeyama (SE(3)) or yaw about z (4-DoF).
Eigen::Matrix3d alignmentRotation(const TrajectoryAssociation& association, TrajectoryAlignment alignment,
                                  const Eigen::Vector3d& mean_gt, const Eigen::Vector3d& mean_est) {
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
  return svd.matrixU() * signs.asDiagonal() * svd.matrixV().transpose();
}

}  // namespace

const char* trajectoryAlignmentName(TrajectoryAlignment alignment) {
  switch (alignment) {
    case TrajectoryAlignment::kSE3: return "se3";
    case TrajectoryAlignment::kFourDof: return "4dof";
    case TrajectoryAlignment::kNone: return "none";
  }
  return "unknown";
}

Result<TrajectoryAlignment> parseTrajectoryAlignment(const std::string& name) {
  for (const TrajectoryAlignment alignment :
       {TrajectoryAlignment::kSE3, TrajectoryAlignment::kFourDof, TrajectoryAlignment::kNone}) {
    if (name == trajectoryAlignmentName(alignment)) return alignment;
  }
  return Status(StatusCode::kInvalidArgument, "unknown alignment '" + name + "' (se3, 4dof or none)");
}

Result<TrajectoryAssociation> associateByTime(const StampedPoses& world_T_body_gt,
                                              const StampedPoses& estimate_T_body, double max_gap_s) {
  DG_RETURN_IF_ERROR(validateTrajectory(world_T_body_gt, "ground truth"));
  DG_RETURN_IF_ERROR(validateTrajectory(estimate_T_body, "estimate"));
  if (!(std::isfinite(max_gap_s) && max_gap_s > 0.0)) {
    return Status(StatusCode::kInvalidArgument, "maximum gap " + formatValue(max_gap_s) + " s must be positive and finite");
  }
  const double t_first = world_T_body_gt.front().first;
  const double t_last = world_T_body_gt.back().first;
  TrajectoryAssociation association;
  for (size_t i = 0; i < estimate_T_body.size(); ++i) {
    const double t = estimate_T_body[i].first;
    if (t < t_first) {
      ++association.before_span;
      continue;
    }
    if (t > t_last) {
      ++association.after_span;
      continue;
    }
    // The GT samples k0 ≤ k1 around t: t(k0) ≤ t ≤ t(k1), k0 = k1 only at the last sample.
    const auto after = std::upper_bound(world_T_body_gt.begin(), world_T_body_gt.end(), t,
                                        [](double value, const auto& sample) { return value < sample.first; });
    const size_t k1 = after == world_T_body_gt.end() ? world_T_body_gt.size() - 1 : after - world_T_body_gt.begin();
    const size_t k0 = after == world_T_body_gt.end() ? k1 : k1 - 1;
    const double t0 = world_T_body_gt[k0].first;
    const double t1 = world_T_body_gt[k1].first;
    if (std::min(t - t0, t1 - t) > max_gap_s) {
      ++association.beyond_gap;
      continue;
    }
    const double alpha = k1 == k0 ? 0.0 : (t - t0) / (t1 - t0);
    association.estimate_index.push_back(i);
    association.world_T_body_gt.emplace_back(
        t, interpolateLinearSlerp(world_T_body_gt[k0].second, world_T_body_gt[k1].second, alpha));
    association.estimate_T_body.push_back(estimate_T_body[i]);
  }
  if (association.before_span + association.after_span == static_cast<long>(estimate_T_body.size())) {
    return Status(StatusCode::kFailedPrecondition, "the estimate " + spanText(estimate_T_body) +
                                                       " does not overlap the ground truth " +
                                                       spanText(world_T_body_gt) + " in time");
  }
  if (association.size() == 0) {
    return Status(StatusCode::kFailedPrecondition,
                  "no estimate pose has a ground-truth sample within the maximum gap of " +
                      formatValue(max_gap_s) + " s (" + std::to_string(association.beyond_gap) +
                      " inside the ground truth's span)");
  }
  return association;
}

Result<Eigen::Isometry3d> alignTrajectory(const TrajectoryAssociation& association, TrajectoryAlignment alignment) {
  if (alignment == TrajectoryAlignment::kNone) return Eigen::Isometry3d::Identity();
  if (association.size() < 3) {
    return Status(StatusCode::kFailedPrecondition,
                  std::string(trajectoryAlignmentName(alignment)) + " alignment needs at least 3 associated poses, got " +
                      std::to_string(association.size()));
  }
  const auto [mean_gt, mean_est] = meanPositions(association);
  Eigen::Isometry3d world_T_estimate = Eigen::Isometry3d::Identity();
  world_T_estimate.linear() = alignmentRotation(association, alignment, mean_gt, mean_est);
  world_T_estimate.translation() = mean_gt - world_T_estimate.linear() * mean_est;
  return world_T_estimate;
}

Result<RelativePoseError> relativePoseError(const TrajectoryAssociation& association, double distance_m) {
  if (!(std::isfinite(distance_m) && distance_m > 0.0)) {
    return Status(StatusCode::kInvalidArgument,
                  "RPE distance " + formatValue(distance_m) + " m must be positive and finite");
  }
  // Path length along the GT from the first associated pose. A relative tolerance keeps round-off in
  // the sum from skipping the sample that reaches Δ exactly.
  std::vector<double> path_m(association.size(), 0.0);
  for (size_t k = 1; k < association.size(); ++k) {
    path_m[k] = path_m[k - 1] + (association.world_T_body_gt[k].second.translation() -
                                 association.world_T_body_gt[k - 1].second.translation())
                                    .norm();
  }
  const double reach_m = distance_m * (1.0 - 1e-9);
  RelativePoseError rpe;
  rpe.distance_m = distance_m;
  double sum_translation = 0.0;
  double sum_rotation = 0.0;
  for (size_t i = 0; i + 1 < association.size(); ++i) {
    const auto reached = std::lower_bound(path_m.begin() + i + 1, path_m.end(), path_m[i] + reach_m);
    if (reached == path_m.end()) break;  // the rest of the path is shorter than Δ, for every later i too
    const size_t j = reached - path_m.begin();
    const Eigen::Isometry3d gt_i_T_j =
        association.world_T_body_gt[i].second.inverse() * association.world_T_body_gt[j].second;
    const Eigen::Isometry3d est_i_T_j =
        association.estimate_T_body[i].second.inverse() * association.estimate_T_body[j].second;
    const Eigen::Isometry3d error = gt_i_T_j.inverse() * est_i_T_j;
    sum_translation += error.translation().squaredNorm();
    const double angle = so3Log(error.linear()).norm();
    sum_rotation += angle * angle;
    ++rpe.pairs;
  }
  const double n = static_cast<double>(rpe.pairs);
  rpe.translation_rmse_m = rpe.pairs > 0 ? std::sqrt(sum_translation / n) : kNaN;
  rpe.rotation_rmse_deg = rpe.pairs > 0 ? std::sqrt(sum_rotation / n) * kRadToDeg : kNaN;
  return rpe;
}

Result<TrajectoryMetrics> evaluateTrajectory(const StampedPoses& world_T_body_gt, const StampedPoses& estimate_T_body,
                                             const TrajectoryMetricsParams& params) {
  const auto association = associateByTime(world_T_body_gt, estimate_T_body, params.max_gap_s);
  if (!association.ok()) return association.status();
  const auto world_T_estimate = alignTrajectory(*association, params.alignment);
  if (!world_T_estimate.ok()) return world_T_estimate.status();

  TrajectoryMetrics metrics;
  metrics.alignment = params.alignment;
  metrics.world_T_estimate = *world_T_estimate;
  std::tie(metrics.ate_m, metrics.ate_rot_deg) = absoluteErrors(*association, *world_T_estimate);
  metrics.ate_stats = positionErrorStatistics(*association, *world_T_estimate);
  const auto se3 = alignTrajectory(*association, TrajectoryAlignment::kSE3);
  const auto four_dof = alignTrajectory(*association, TrajectoryAlignment::kFourDof);
  metrics.ate_se3_m = se3.ok() ? absoluteErrors(*association, *se3).first : kNaN;
  metrics.ate_4dof_m = four_dof.ok() ? absoluteErrors(*association, *four_dof).first : kNaN;
  metrics.ate_unaligned_m = absoluteErrors(*association, Eigen::Isometry3d::Identity()).first;
  for (const double distance_m : params.rpe_distances_m) {
    const auto rpe = relativePoseError(*association, distance_m);
    if (!rpe.ok()) return rpe.status();
    metrics.rpe.push_back(*rpe);
  }
  metrics.estimate_poses = static_cast<long>(estimate_T_body.size());
  metrics.associated = static_cast<long>(association->size());
  metrics.before_span = association->before_span;
  metrics.after_span = association->after_span;
  metrics.beyond_gap = association->beyond_gap;
  return metrics;
}

}  // namespace dualgraph
