// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/calibration/vio_drift_track.h"

#include <algorithm>
#include <cmath>

#include "dualgraph/dual_graph/odometry_history.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

Eigen::Matrix3d rotationAboutZ(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

KnotSegment DriftKnots::segment(double t) const {
  const int last = count() - 1;
  const double position = (t - t0) / spacing;
  if (!(position > 0.0)) return {0, 0.0};
  if (position >= last) return {last - 1, 1.0};
  const int index = std::min(static_cast<int>(position), last - 1);
  return {index, position - index};
}

double DriftKnots::yawAt(double t) const {
  const KnotSegment s = segment(t);
  return (1.0 - s.weight) * yaw[static_cast<size_t>(s.index)] + s.weight * yaw[static_cast<size_t>(s.index) + 1];
}

Eigen::Vector3d DriftKnots::offsetAt(double t) const {
  const KnotSegment s = segment(t);
  return (1.0 - s.weight) * offset[static_cast<size_t>(s.index)] + s.weight * offset[static_cast<size_t>(s.index) + 1];
}

VioDriftTrack::VioDriftTrack(const std::vector<OdometrySample>& odometry, DriftKnots knots)
    : odometry_(odometry), knots_(std::move(knots)) {
  const size_t n = odometry_.size();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  sum_.assign(n, zero);
  lower_.assign(n, zero);
  upper_.assign(n, zero);
  segment_.assign(n, 0);
  lower_total_.assign(static_cast<size_t>(std::max(knots_.count(), 1)), zero);
  upper_total_.assign(lower_total_.size(), zero);
  if (n == 0 || knots_.count() < 2) return;
  segment_[0] = knots_.segment(odometry_[0].t).index;
  for (size_t i = 1; i < n; ++i) {
    const KnotSegment s = knots_.segment(odometry_[i].t);
    const Eigen::Vector3d v = rotationAboutZ(knots_.yawAt(odometry_[i].t)) *
                              (odometry_[i].odom_T_body.translation() - odometry_[i - 1].odom_T_body.translation());
    const Eigen::Vector3d u = Eigen::Vector3d::UnitZ().cross(v);
    const bool same = s.index == segment_[i - 1];
    sum_[i] = sum_[i - 1] + v;
    lower_[i] = (same ? lower_[i - 1] : zero) + (1.0 - s.weight) * u;
    upper_[i] = (same ? upper_[i - 1] : zero) + s.weight * u;
    lower_total_[static_cast<size_t>(s.index)] += (1.0 - s.weight) * u;
    upper_total_[static_cast<size_t>(s.index)] += s.weight * u;
    segment_[i] = s.index;
  }
}

Result<DriftKnots> VioDriftTrack::constantKnots(const std::vector<OdometrySample>& odometry, double spacing,
                                                const Eigen::Isometry3d& world_T_odom) {
  if (odometry.size() < 2)
    return Status(StatusCode::kInvalidArgument, "VIO drift track: fewer than 2 odometry samples");
  const double t_begin = odometry.front().t, t_end = odometry.back().t;
  if (!std::isfinite(t_begin) || !std::isfinite(t_end) || !(t_end > t_begin)) {
    return Status(StatusCode::kInvalidArgument, "VIO drift track: empty or non-finite odometry span [" +
                                                    formatTimestamp(t_begin) + ", " + formatTimestamp(t_end) + "]");
  }
  if (!std::isfinite(spacing) || !(spacing > 0.0)) {
    return Status(StatusCode::kInvalidArgument, "VIO drift track: knot spacing must be > 0 s");
  }
  DriftKnots knots;
  knots.t0 = t_begin;
  knots.spacing = spacing;
  const int intervals = std::max(1, static_cast<int>(std::ceil((t_end - t_begin) / spacing - 1e-9)));
  const double yaw = headingOf(world_T_odom.linear());
  knots.yaw.assign(static_cast<size_t>(intervals) + 1, yaw);
  // With ψ constant the re-integrated increments add up to Rz(ψ) (p(τ) − p_0): c puts p_0 where world_T_odom does.
  const Eigen::Vector3d offset =
      world_T_odom.translation() + rotationAboutZ(yaw) * odometry.front().odom_T_body.translation();
  knots.offset.assign(knots.yaw.size(), offset);
  return knots;
}

Result<DriftKnots> VioDriftTrack::knotsFromKeyframes(const std::vector<CorrectedPose>& keyframes,
                                                     const std::vector<OdometrySample>& odometry, double spacing) {
  auto knots = constantKnots(odometry, spacing, Eigen::Isometry3d::Identity());
  if (!knots.ok()) return knots.status();
  std::vector<double> times;
  std::vector<Eigen::Vector4d, Eigen::aligned_allocator<Eigen::Vector4d>> values;  // world_T_odom as x y z ψ
  for (const CorrectedPose& keyframe : keyframes) {
    if (keyframe.state == TrackingState::kInitialising) continue;  // not in the map's frame yet
    auto odom_T_body = odometryPoseAt(odometry, keyframe.t);
    if (!odom_T_body.ok()) continue;
    const Eigen::Isometry3d world_T_odom = keyframe.world_T_body * odom_T_body->inverse();
    Eigen::Vector4d value;
    value << world_T_odom.translation(), headingOf(world_T_odom.linear());
    if (!values.empty()) value[3] = values.back()[3] + std::remainder(value[3] - values.back()[3], 2.0 * M_PI);
    times.push_back(keyframe.t);
    values.push_back(value);
  }
  if (values.empty()) {
    return Status(StatusCode::kFailedPrecondition, "VIO drift track: no keyframe inside the odometry's time span");
  }
  std::vector<Eigen::Vector4d, Eigen::aligned_allocator<Eigen::Vector4d>> at_knots;
  for (int k = 0; k < knots->count(); ++k) {
    const double t = knots->time(k);
    const auto after = std::upper_bound(times.begin(), times.end(), t);
    const size_t i = static_cast<size_t>(after - times.begin());
    if (i == 0 || i == times.size()) {
      at_knots.push_back(i == 0 ? values.front() : values.back());
    } else {
      const double weight = (t - times[i - 1]) / (times[i] - times[i - 1]);
      at_knots.push_back((1.0 - weight) * values[i - 1] + weight * values[i]);
    }
    knots->yaw[static_cast<size_t>(k)] = at_knots.back()[3];
    knots->offset[static_cast<size_t>(k)].setZero();
  }
  const VioDriftTrack unplaced(odometry, *knots);  // c = 0: the re-integrated increments alone
  for (int k = 0; k < knots->count(); ++k) {
    const double t = std::min(std::max(knots->time(k), odometry.front().t), odometry.back().t);
    const Eigen::Vector4d& value = at_knots[static_cast<size_t>(k)];
    const Eigen::Vector3d target =
        value.head<3>() + rotationAboutZ(value[3]) * odometryPoseAt(odometry, t)->translation();
    knots->offset[static_cast<size_t>(k)] = target - unplaced.worldTBody(t)->translation();
  }
  return knots;
}

Result<Eigen::Isometry3d> VioDriftTrack::worldTBody(double tau, DriftPoseJacobian* jacobian) const {
  auto odom_T_body = odometryPoseAt(odometry_, tau);
  if (!odom_T_body.ok()) return odom_T_body.status();
  const auto after = std::upper_bound(odometry_.begin(), odometry_.end(), tau,
                                      [](double value, const OdometrySample& sample) { return value < sample.t; });
  const size_t i = static_cast<size_t>(after - odometry_.begin()) - 1;
  const KnotSegment s = knots_.segment(tau);
  const Eigen::Matrix3d world_R_odom = rotationAboutZ(knots_.yawAt(tau));
  const Eigen::Vector3d partial = world_R_odom * (odom_T_body->translation() - odometry_[i].odom_T_body.translation());
  Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
  world_T_body.linear() = world_R_odom * odom_T_body->linear();
  world_T_body.translation() = knots_.offsetAt(tau) + sum_[i] + partial;
  if (jacobian != nullptr) {
    jacobian->segment = s;
    jacobian->odom_R_body = odom_T_body->linear();
    Eigen::Matrix3Xd& d = jacobian->d_position_d_yaw;
    d.setZero(3, s.index + 2);
    const int si = segment_[i];
    for (int j = 0; j <= std::min(si + 1, s.index + 1); ++j) {
      const size_t J = static_cast<size_t>(j);
      if (j < si) {
        d.col(j) = lower_total_[J] + (j >= 1 ? upper_total_[J - 1] : Eigen::Vector3d::Zero());
      } else if (j == si) {
        d.col(j) = (j >= 1 ? upper_total_[J - 1] : Eigen::Vector3d::Zero()) + lower_[i];
      } else {
        d.col(j) = upper_[i];
      }
    }
    const Eigen::Vector3d turn = Eigen::Vector3d::UnitZ().cross(partial);
    d.col(s.index) += (1.0 - s.weight) * turn;
    d.col(s.index + 1) += s.weight * turn;
  }
  return world_T_body;
}

}  // namespace dualgraph
