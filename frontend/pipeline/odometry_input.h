// SPDX-License-Identifier: MIT
// OdometryInput: one VIO sample as the streaming pipeline takes it, and the checks it must pass.
#pragma once

#include <optional>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/measurements.h"

namespace dualgraph {

/// One odometry sample as a VIO publishes it: time t [s] on the odometry clock, odom_T_body (body in the VIO's
/// odometry frame, unit quaternion / rotation), and optionally the covariance of that pose itself (6×6, metric
/// [t; θ] in m², rad², a right perturbation in the body frame, as OpenVINS reports it) — converted into the
/// increment's covariance sample by sample (RelativeCovarianceStream). All zero or partly zero (rows a VIO leaves at 0
/// while it starts, isUnknownCovariance) means unknown, as none (counted); otherwise it must be a covariance (finite,
/// symmetric, positive definite) or the sample is refused. Without one, `relative_covariance` is used when set (a log
/// converted already), else LocalizerParams' per-metre model. A plain value.
struct OdometryInput {
  double t = 0.0;
  Eigen::Isometry3d odom_T_body = Eigen::Isometry3d::Identity();
  std::optional<Matrix6d> absolute_covariance;
  std::optional<Matrix6d> relative_covariance;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// validateOdometrySample for the sample's t, pose and relative covariance, and its absolute covariance: none, or
/// unknown (isUnknownCovariance), or a covariance (checkCovariance); kInvalidArgument / kNotPositiveDefinite naming it.
Status validateOdometryInput(const OdometryInput& input);
/// The input's absolute covariance when it has a known one: none when absent or all or partly zero
/// (isUnknownCovariance); kInvalidArgument / kNotPositiveDefinite naming it when it is not a covariance. Checked
/// without heap or message first (every sample of a VIO passes here).
Result<std::optional<Matrix6d>> knownAbsoluteCovariance(const OdometryInput& input);

}  // namespace dualgraph
