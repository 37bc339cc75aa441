// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/odometry_input.h"

#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

Status validateOdometryInput(const OdometryInput& input) {
  DG_RETURN_IF_ERROR(validateOdometrySample(OdometrySample{input.t, input.odom_T_body, input.relative_covariance}));
  const std::optional<Matrix6d> known = knownAbsoluteCovariance(input);
  return known ? checkCovariance(*known, "odometry sample at t=" + formatTimestamp(input.t) + ": absolute_covariance")
               : Status();
}

std::optional<Matrix6d> knownAbsoluteCovariance(const OdometryInput& input) {
  if (!input.absolute_covariance || isUnknownCovariance(*input.absolute_covariance)) return std::nullopt;
  return input.absolute_covariance;
}

}  // namespace dualgraph
