// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/pose_covariance.h"

#include "dualgraph/core/wall_clock.h"
#include "dualgraph/dual_graph/temporary_graph.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

void PoseCovarianceTracker::restart(const Matrix6d& keyframe_marginal, const Eigen::Isometry3d& keyframe_odom_T_body,
                                    const OdometrySample& newest, const Matrix6d& since) {
  covariance_ = composeRelativeCovariance(keyframe_marginal, keyframe_odom_T_body.inverse() * newest.odom_T_body, since);
  t_ = newest.t;
}

double PoseCovarianceTracker::refresh(MainGraph& main, const OdometryHistory& history, const OdometryNoiseModel& model) {
  const double start = nowMs();
  covariance_.reset();
  if (main.keyframes().empty() || history.empty()) return nowMs() - start;
  const size_t index = main.keyframes().size() - 1;
  const Keyframe& keyframe = main.keyframes()[index];
  Result<Matrix6d> marginal = main.keyframeCovariance(index);
  Result<Matrix6d> since = history.relativeCovariance(keyframe.t, history.newest().t, model);
  if (marginal.ok() && since.ok()) restart(*marginal, keyframe.odom_T_body, history.newest(), *since);
  return nowMs() - start;
}

void PoseCovarianceTracker::advance(const OdometrySample& previous, const OdometrySample& sample,
                                    const OdometryNoiseModel& model) {
  if (!covariance_ || !(sample.t > t_)) return;
  const Eigen::Isometry3d increment = previous.odom_T_body.inverse() * sample.odom_T_body;
  const Matrix6d step = scaledOdometryCovariance(
      sample.relative_covariance && model.use_input_covariance
          ? *sample.relative_covariance
          : odometryModelCovariance(increment, sample.odom_T_body.linear().transpose() * Eigen::Vector3d::UnitZ(), model),
      model.scale);
  covariance_ = composeRelativeCovariance(*covariance_, increment, step);
  t_ = sample.t;
}

}  // namespace dualgraph
