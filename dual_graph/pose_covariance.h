// SPDX-License-Identifier: MIT
// PoseCovarianceTracker: the covariance of the corrected pose, from the newest keyframe's marginal and the odometry.
#pragma once

#include <optional>

#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/main_graph.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/dual_graph/odometry_history.h"

namespace dualgraph {

/// The covariance of world_T_body at the newest odometry sample, metric [t; θ] (m², rad²), a right perturbation in
/// the body frame: restarted at each main-graph update from the newest keyframe's marginal composed with the
/// odometry's covariance since it, then carried sample by sample by each increment's covariance (the sample's own,
/// or the per-metre model; under the model's scale), first order (composeRelativeCovariance). Threads: one thread
/// at a time per instance (the Localizer's).
class PoseCovarianceTracker {
 public:
  void reset() { covariance_.reset(); }
  /// After an update: `keyframe_marginal` of the keyframe at keyframe_odom_T_body, `since` the odometry covariance
  /// from it to `newest`.
  void restart(const Matrix6d& keyframe_marginal, const Eigen::Isometry3d& keyframe_odom_T_body,
               const OdometrySample& newest, const Matrix6d& since);
  /// After a main-graph update: restarted from the newest keyframe's marginal in `main` and the odometry since it in
  /// `history` (reset when either cannot be had: a failed factorisation, say). Returns its wall time [ms].
  double refresh(MainGraph& main, const OdometryHistory& history, const OdometryNoiseModel& model);
  /// A sample after `previous` (the newest one before it); nothing before the first restart.
  void advance(const OdometrySample& previous, const OdometrySample& sample, const OdometryNoiseModel& model);
  /// The covariance at time t when it was carried to exactly that sample.
  std::optional<Matrix6d> at(double t) const { return covariance_ && t_ == t ? covariance_ : std::nullopt; }

 private:
  std::optional<Matrix6d> covariance_;
  double t_ = 0.0;
};

}  // namespace dualgraph
