// SPDX-License-Identifier: MIT
#include "dual_graph/se3_uncertainty.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "dual_graph/measurements.h"

namespace dualgraph {

Matrix6d composeRelativeCovariance(const Matrix6d& covariance_ab, const Eigen::Isometry3d& b_T_c,
                                   const Matrix6d& covariance_bc) {
  const Matrix6d adjoint = se3Adjoint(b_T_c.inverse());
  return adjoint * covariance_ab * adjoint.transpose() + covariance_bc;
}

Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double alpha) {
  if (alpha <= 0.0) return a;
  if (alpha >= 1.0) return b;
  return a * se3Exp(alpha * se3Log(a.inverse() * b));
}

double translationOf(const Eigen::Isometry3d& increment) { return increment.translation().norm(); }

double rotationAngleOf(const Eigen::Isometry3d& increment) { return so3Log(increment.linear()).norm(); }

Matrix6d odometryModelCovariance(const Eigen::Isometry3d& increment, double sigma_t, double sigma_r,
                                 double min_distance) {
  const double d = std::max(translationOf(increment), min_distance);
  Vector6d variances;
  variances << Eigen::Vector3d::Constant(sigma_t * sigma_t * d), Eigen::Vector3d::Constant(sigma_r * sigma_r * d);
  return variances.asDiagonal();
}

Result<Eigen::MatrixXd> informationFromCovariance(const Eigen::MatrixXd& covariance, const std::string& what) {
  const Eigen::MatrixXd symmetric = 0.5 * (covariance + covariance.transpose());
  DG_RETURN_IF_ERROR(checkCovariance(symmetric, what));
  const Eigen::LLT<Eigen::MatrixXd> llt(symmetric);
  if (llt.info() != Eigen::Success) {
    return Status(StatusCode::kNotPositiveDefinite, what + " is not positive definite (Cholesky failed)");
  }
  Eigen::MatrixXd information = llt.solve(Eigen::MatrixXd::Identity(symmetric.rows(), symmetric.cols()));
  information = 0.5 * (information + information.transpose());
  if (!information.allFinite()) return Status(StatusCode::kNumericalError, what + ": its inverse is not finite");
  return information;
}

}  // namespace dualgraph
