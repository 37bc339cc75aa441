// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/odometry_input.h"

#include <algorithm>

#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

Status validateOdometryInput(const OdometryInput& input) {
  DG_RETURN_IF_ERROR(validateOdometrySample(OdometrySample{input.t, input.odom_T_body, input.relative_covariance}));
  return knownAbsoluteCovariance(input).status();
}

Result<std::optional<Matrix6d>> knownAbsoluteCovariance(const OdometryInput& input) {
  if (!input.absolute_covariance || isUnknownCovariance(*input.absolute_covariance)) {
    return std::optional<Matrix6d>();
  }
  const Matrix6d& covariance = *input.absolute_covariance;
  // First the check without heap or message, then checkCovariance for its verdict and message.
  if (surelyValidCovariance<6>(covariance)) return input.absolute_covariance;
  DG_RETURN_IF_ERROR(checkCovariance(covariance, "odometry sample at t=" + formatTimestamp(input.t) + ": absolute_covariance"));
  return input.absolute_covariance;
}

}  // namespace dualgraph
