// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/odometry_history.h"

#include <algorithm>
#include <cmath>

#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

Eigen::Isometry3d interpolateOdometry(const OdometrySample& before, const OdometrySample& after, double t) {
  if (!(t > before.t) || !(after.t > before.t)) return before.odom_T_body;
  return interpolatePose(before.odom_T_body, after.odom_T_body, (t - before.t) / (after.t - before.t));
}

Matrix6d odometryModelCovariance(const Eigen::Isometry3d& increment, const Eigen::Vector3d& up_in_b,
                                 const OdometryNoiseModel& model) {
  const double d = std::max(translationOf(increment), model.min_distance);
  const Eigen::Matrix3d vertical = up_in_b * up_in_b.transpose();
  Matrix6d covariance = Matrix6d::Zero();
  covariance.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() * (model.sigma_t * model.sigma_t * d);
  covariance.bottomRightCorner<3, 3>() = (model.sigma_r * model.sigma_r * d) * vertical +
                                         (model.sigma_tilt * model.sigma_tilt * d) * (Eigen::Matrix3d::Identity() - vertical);
  return covariance;
}

Matrix6d scaledOdometryCovariance(const Matrix6d& base, const OdometryNoiseScale& scale) {
  Vector6d s;
  s << Eigen::Vector3d::Constant(std::sqrt(scale.translation)), Eigen::Vector3d::Constant(std::sqrt(scale.rotation));
  return s.asDiagonal() * base * s.asDiagonal();
}

size_t OdometryHistory::indexAtOrBefore(double t) const {
  const auto after = std::upper_bound(samples_.begin(), samples_.end(), t,
                                      [](double value, const OdometrySample& s) { return value < s.t; });
  return static_cast<size_t>(std::max<std::ptrdiff_t>(0, (after - samples_.begin()) - 1));
}

Result<Matrix6d> OdometryHistory::relativeCovariance(double t_a, double t_b, const OdometryNoiseModel& model) const {
  if (t_b < t_a) return Status(StatusCode::kInvalidArgument, "relativeCovariance: t_b < t_a");
  Result<Eigen::Isometry3d> pose_a = poseAt(t_a);
  if (!pose_a.ok()) return pose_a.status();
  Result<Eigen::Isometry3d> pose_b = poseAt(t_b);
  if (!pose_b.ok()) return pose_b.status();
  const size_t first = indexAtOrBefore(t_a);
  // The last sample the walk needs: the one at t_b, or the first after it.
  size_t last = indexAtOrBefore(t_b);
  if (samples_[last].t < t_b) last = std::min(last + 1, samples_.size() - 1);
  bool all_have_covariance = model.use_input_covariance && t_b > t_a;
  for (size_t k = first + 1; k <= last && all_have_covariance; ++k) {
    all_have_covariance = samples_[k].relative_covariance.has_value();
  }
  if (!all_have_covariance) {
    return scaledOdometryCovariance(
        odometryModelCovariance(pose_a->inverse() * *pose_b, pose_b->linear().transpose() * Eigen::Vector3d::UnitZ(),
                                model),
        model.scale);
  }
  // Walk the steps (k-1, k] that overlap (t_a, t_b], composing each step's share of its covariance.
  Matrix6d covariance = Matrix6d::Zero();
  Eigen::Isometry3d previous = *pose_a;
  for (size_t k = first + 1; k <= last; ++k) {
    const OdometrySample& step_end = samples_[k];
    const double step_begin_t = samples_[k - 1].t;
    const double from = std::max(step_begin_t, t_a);
    const double to = std::min(step_end.t, t_b);
    if (to <= from) continue;
    const double fraction = (to - from) / (step_end.t - step_begin_t);
    const Eigen::Isometry3d next = to == step_end.t ? step_end.odom_T_body : *pose_b;
    covariance = composeRelativeCovariance(covariance, previous.inverse() * next,
                                           fraction * *step_end.relative_covariance);
    previous = next;
  }
  return scaledOdometryCovariance(covariance, model.scale);
}

Result<Eigen::Isometry3d> OdometryHistory::poseAt(double t, const OdometrySample* next) const {
  if (next != nullptr && !samples_.empty() && t > samples_.back().t && t <= next->t) {
    return interpolateOdometry(samples_.back(), *next, t);
  }
  if (next != nullptr && samples_.empty() && t == next->t) return next->odom_T_body;
  return odometryPoseAt(samples_, t);
}

void OdometryHistory::discardBefore(double t) {
  while (samples_.size() > 1 && samples_[1].t <= t) samples_.pop_front();
}

}  // namespace dualgraph
