// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/odometry_covariance.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {

Result<std::optional<Matrix6d>> RelativeCovarianceStream::next(const Eigen::Isometry3d& odom_T_body,
                                                               const std::optional<Matrix6d>& absolute_covariance) {
  if (!(floor_ > 0.0) || !std::isfinite(floor_)) {
    return Status(StatusCode::kInvalidArgument, "relative covariance: floor must be positive and finite");
  }
  // All zero is "unknown" (ROS's convention; a VIO before its filter has a covariance): as none.
  const bool known = absolute_covariance && !absolute_covariance->isZero(0.0);
  std::optional<Matrix6d> relative;
  if (known && previous_) {
    const Eigen::Isometry3d increment = previous_->odom_T_body.inverse() * odom_T_body;
    const Matrix6d adjoint = se3Adjoint(increment.inverse());
    Matrix6d difference = *absolute_covariance - adjoint * previous_->absolute * adjoint.transpose();
    difference = 0.5 * (difference + difference.transpose()).eval();
    if (!difference.allFinite()) {
      return Status(StatusCode::kNumericalError, "non-finite covariance (absolute covariances not finite?)");
    }
    Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(difference);
    Vector6d values = eigen.eigenvalues();
    // Shrinking for real (a reset, a loop closure), not rounding or a direction that did not grow: a variance
    // lost beyond 1 % of the largest one the VIO reports now.
    if (values.minCoeff() < -kShrinkFraction * absolute_covariance->diagonal().maxCoeff()) ++shrinks_;
    const double lowest = std::max(floor_, 1e-11 * values.maxCoeff());
    for (int i = 0; i < 6; ++i) {
      if (values[i] < lowest) {
        values[i] = lowest;
        ++clamped_;
      }
    }
    const Matrix6d rebuilt = eigen.eigenvectors() * values.asDiagonal() * eigen.eigenvectors().transpose();
    relative = 0.5 * (rebuilt + rebuilt.transpose());
  }
  if (known) {
    previous_ = Previous{odom_T_body, *absolute_covariance};
  } else {
    previous_.reset();
  }
  return relative;
}

}  // namespace dualgraph
