// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/odometry_input.h"

#include <algorithm>

#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

Status validateOdometryInput(const OdometryInput& input) {
  DG_RETURN_IF_ERROR(validateOdometrySample(OdometrySample{input.t, input.odom_T_body, input.relative_covariance}));
  const std::optional<Matrix6d> known = knownAbsoluteCovariance(input);
  if (!known) return Status();
  // Every sample of a VIO passes here: first the check without heap or message (finite, symmetric as checkCovariance
  // judges it, well conditioned), then checkCovariance for its verdict and message.
  Matrix6d inverse;
  const double scale = known->cwiseAbs().maxCoeff();
  if (known->allFinite() && (*known - known->transpose()).cwiseAbs().maxCoeff() <= 1e-9 * std::max(scale, 1e-300) &&
      inverseOfWellConditionedCovariance<6>(*known, inverse)) {
    return Status();
  }
  return checkCovariance(*known, "odometry sample at t=" + formatTimestamp(input.t) + ": absolute_covariance");
}

std::optional<Matrix6d> knownAbsoluteCovariance(const OdometryInput& input) {
  if (!input.absolute_covariance || isUnknownCovariance(*input.absolute_covariance)) return std::nullopt;
  return input.absolute_covariance;
}

}  // namespace dualgraph
