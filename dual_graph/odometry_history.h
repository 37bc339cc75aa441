// SPDX-License-Identifier: MIT
#pragma once

#include <deque>

#include "dual_graph/measurements.h"

namespace dualgraph {

/// How the covariance of an odometry increment is obtained (see LocalizerParams).
struct OdometryNoiseModel {
  bool use_input_covariance = true;
  double sigma_t = 0.05;       ///< [m/√m]
  double sigma_r = 0.01;       ///< [rad/√m]
  double min_distance = 0.05;  ///< [m]
};

/// The VIO samples of the current keyframe interval, in increasing time: poses at any instant between
/// the first and the newest sample (geodesic interpolation) and the covariance of the motion between
/// two instants. The caller checks time order and validity before `push`.
class OdometryHistory {
 public:
  void push(const OdometrySample& sample) { samples_.push_back(sample); }
  bool empty() const { return samples_.empty(); }
  const OdometrySample& newest() const { return samples_.back(); }
  double oldestTime() const { return samples_.front().t; }

  /// odom_T_body at `t`; kFailedPrecondition when t lies outside [oldest, newest].
  Result<Eigen::Isometry3d> poseAt(double t) const;

  /// Metric [t; θ] covariance of odom_T_body(t_a)⁻¹ · odom_T_body(t_b) (t_a ≤ t_b, both covered):
  /// the samples' own relative covariances composed with adjoints (a partial step contributes its
  /// time fraction) when every sample in (t_a, t_b] has one and the model allows it; otherwise the
  /// per-metre model on the whole increment.
  Result<Matrix6d> relativeCovariance(double t_a, double t_b, const OdometryNoiseModel& model) const;

  /// Forgets samples no longer needed to interpolate at `t` or later (keeps the last one at or before t).
  void discardBefore(double t);

 private:
  /// Index of the last sample with time ≤ t (t must be covered).
  size_t indexAtOrBefore(double t) const;
  std::deque<OdometrySample, Eigen::aligned_allocator<OdometrySample>> samples_;
};

}  // namespace dualgraph
