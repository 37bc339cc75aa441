// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/odometry_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dualgraph {

std::string OdometryScaleParams::minErrorProblem(double bar) const {
  if (bar >= 0.0 && bar < max_error) return "";
  char bound[32];
  std::snprintf(bound, sizeof bound, "%g", max_error);
  return std::string("must be in [0, ") + bound + ")";
}

Eigen::Isometry3d OdometryScale::rescaled(const Eigen::Isometry3d& odom_T_body) const {
  if (!report_.applied) return odom_T_body;  // the VIO as it is, to the bit
  const Knot& knot = knots_.back();
  Eigen::Isometry3d rescaled = odom_T_body;
  rescaled.translation() = knot.rescaled + knot.scale * (odom_T_body.translation() - knot.raw);
  return rescaled;
}

void OdometryScale::accept(double t, const Eigen::Isometry3d& odom_T_body) {
  if (knots_.empty()) knots_.push_back({t, odom_T_body.translation(), odom_T_body.translation(), 1.0});
  last_raw_ = odom_T_body;
  last_t_ = t;
}

Matrix6d OdometryScale::rescaled(const Matrix6d& covariance) const {
  Matrix6d rescaled = covariance;
  rescaled.topRows<3>() *= report_.scale;
  rescaled.leftCols<3>() *= report_.scale;
  return rescaled;
}

Eigen::Vector3d OdometryScale::rawPosition(double t, const Eigen::Vector3d& rescaled) const {
  auto knot = knots_.begin();
  while (std::next(knot) != knots_.end() && std::next(knot)->t <= t) ++knot;
  return knot->raw + (rescaled - knot->rescaled) / knot->scale;
}

bool OdometryScale::update(const std::vector<KeyframePair, Eigen::aligned_allocator<KeyframePair>>& keyframes,
                           double t) {
  if (!params_.enabled || keyframes.size() < 2 || knots_.empty()) return false;
  const size_t first = keyframes.size() > static_cast<size_t>(params_.window) + 1
                           ? keyframes.size() - static_cast<size_t>(params_.window) - 1
                           : 0;
  while (knots_.size() > 1 && knots_[1].t <= keyframes[first].t) knots_.pop_front();
  std::vector<Eigen::Vector3d> graph_steps;
  std::vector<Eigen::Vector3d> odometry_steps;
  for (size_t k = first; k + 1 < keyframes.size(); ++k) {
    const Eigen::Vector3d from = rawPosition(keyframes[k].t, keyframes[k].odom_T_body.translation());
    const Eigen::Vector3d to = rawPosition(keyframes[k + 1].t, keyframes[k + 1].odom_T_body.translation());
    const Eigen::Vector3d d = keyframes[k].odom_T_body.linear().transpose() * (to - from);  // raw, body k
    if (!(d.norm() >= params_.min_step)) continue;
    graph_steps.push_back((keyframes[k].world_T_body.inverse() * keyframes[k + 1].world_T_body).translation());
    odometry_steps.push_back(d);
  }
  const size_t n = graph_steps.size();
  if (n < static_cast<size_t>(std::max(params_.min_pairs, 2))) return false;
  double cross = 0.0;
  double squared = 0.0;
  for (size_t i = 0; i < n; ++i) {
    cross += graph_steps[i].dot(odometry_steps[i]);
    squared += odometry_steps[i].squaredNorm();
  }
  const double estimate = cross / squared;
  double residual = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double along = graph_steps[i].dot(odometry_steps[i].normalized());
    residual += std::pow(along - estimate * odometry_steps[i].norm(), 2);
  }
  const double sigma = std::sqrt(residual / static_cast<double>(n - 1) / squared);
  if (!std::isfinite(estimate) || !std::isfinite(sigma)) return false;
  ++report_.updates;
  report_.estimate = estimate;
  report_.sigma = sigma;
  if (!report_.applied) {
    if (std::abs(estimate - 1.0) <= std::max(params_.min_error, 3.0 * sigma)) return false;
    report_.applied = true;
    report_.applied_at_s = t;
  }
  const double scale = report_.scale;
  const double step = params_.max_change * scale;
  const double next = std::clamp(std::clamp(estimate, scale - step, scale + step), 1.0 - params_.max_error,
                                 1.0 + params_.max_error);
  if (next == scale) return false;
  const Eigen::Vector3d last_rescaled = rescaled(*last_raw_).translation();  // under the scale until now
  report_.scale = next;
  knots_.push_back({last_t_, last_raw_->translation(), last_rescaled, next});
  return true;
}

}  // namespace dualgraph
