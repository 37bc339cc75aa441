// SPDX-License-Identifier: MIT
#include "dual_graph/se3_uncertainty.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <utility>

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

namespace {

/// The inverse of a symmetric positive definite matrix by LLT (fixed-size for N = 6, 3: no heap in the
/// factorisation); kNotPositiveDefinite when the factorisation fails.
template <int N>
Result<Eigen::MatrixXd> inverseSpd(const Eigen::MatrixXd& symmetric) {
  using Matrix = Eigen::Matrix<double, N, N>;
  const Eigen::LLT<Matrix> llt{Matrix(symmetric)};
  if (llt.info() != Eigen::Success) return Status(StatusCode::kNotPositiveDefinite, "Cholesky failed");
  return Eigen::MatrixXd(llt.solve(Matrix::Identity(symmetric.rows(), symmetric.cols())));
}

}  // namespace

template <int N>
bool informationFromWellConditionedCovariance(const Eigen::Matrix<double, N, N>& covariance,
                                              Eigen::Matrix<double, N, N>& information) {
  using Matrix = Eigen::Matrix<double, N, N>;
  const Matrix symmetric = 0.5 * (covariance + covariance.transpose());
  Matrix inverse;
  if (!inverseOfWellConditionedCovariance<N>(symmetric, inverse)) return false;
  const Matrix candidate = 0.5 * (inverse + inverse.transpose());  // as informationFromCovariance symmetrises it
  if (!candidate.allFinite()) return false;
  information = candidate;
  return true;
}
template bool informationFromWellConditionedCovariance<6>(const Matrix6d&, Matrix6d&);
template bool informationFromWellConditionedCovariance<3>(const Eigen::Matrix3d&, Eigen::Matrix3d&);

Result<Eigen::MatrixXd> informationFromCovariance(const Eigen::MatrixXd& covariance, const std::string& what) {
  const Eigen::MatrixXd symmetric = 0.5 * (covariance + covariance.transpose());
  Eigen::MatrixXd checked_inverse;  // the check's own Cholesky inverse, when it computed one
  DG_RETURN_IF_ERROR(checkCovariance(symmetric, what, &checked_inverse));
  Result<Eigen::MatrixXd> inverse = checked_inverse.size() > 0 ? Result<Eigen::MatrixXd>(std::move(checked_inverse))
                                    : symmetric.rows() == 6    ? inverseSpd<6>(symmetric)
                                    : symmetric.rows() == 3    ? inverseSpd<3>(symmetric)
                                                               : inverseSpd<Eigen::Dynamic>(symmetric);
  if (!inverse.ok()) {
    return Status(StatusCode::kNotPositiveDefinite, what + " is not positive definite (Cholesky failed)");
  }
  Eigen::MatrixXd information = 0.5 * (*inverse + inverse->transpose());
  if (!information.allFinite()) return Status(StatusCode::kNumericalError, what + ": its inverse is not finite");
  return information;
}

}  // namespace dualgraph
