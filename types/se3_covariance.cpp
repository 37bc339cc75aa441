// SPDX-License-Identifier: MIT
#include "dualgraph/types/se3_covariance.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "dualgraph/core/small_cholesky.h"

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

namespace {

/// checkCovariance's symmetry test: |m − mᵀ| ≤ 1e-9 of m's largest entry, everywhere.
template <typename Matrix>
bool symmetricToRoundOff(const Matrix& m) {
  const double scale = m.cwiseAbs().maxCoeff();
  return (m - m.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * std::max(scale, 1e-300);
}

/// Smallest and largest eigenvalue of the symmetric part of `m` (N rows, or Eigen::Dynamic).
template <int N>
void eigenvalueRange(const Eigen::MatrixXd& m, double& smallest, double& largest) {
  using Matrix = Eigen::Matrix<double, N, N>;
  const Matrix symmetric = 0.5 * (m + m.transpose());
  const Eigen::SelfAdjointEigenSolver<Matrix> eigen(symmetric, Eigen::EigenvaluesOnly);
  smallest = eigen.eigenvalues().minCoeff();
  largest = eigen.eigenvalues().maxCoeff();
}

/// inverseOfWellConditionedCovariance (below) for a dynamic-size `m` of N rows: false means "not decided",
/// and the caller computes the exact eigenvalues. When true and `inverse_out` is given, S⁻¹ is stored there.
template <int N>
bool wellConditionedByNormBound(const Eigen::MatrixXd& m, Eigen::MatrixXd* inverse_out) {
  using Matrix = Eigen::Matrix<double, N, N>;
  Matrix inverse;
  if (!inverseOfWellConditionedCovariance<N>(Matrix(m), inverse)) return false;
  if (inverse_out != nullptr) *inverse_out = inverse;
  return true;
}

}  // namespace

/// checkCovariance's norm bound: ‖S‖∞ · ‖S⁻¹‖∞ < 1e11 for the
/// symmetric part S of `m` means that S is positive definite (its Cholesky succeeded) and λ_min / λ_max ≥
/// 1 / (‖S‖∞ ‖S⁻¹‖∞) > 1e-11, since every eigenvalue is bounded by any induced norm (λ_max ≤ ‖S‖∞,
/// 1/λ_min ≤ ‖S⁻¹‖∞). The factor 10 over checkCovariance's 1e-12 covers the round-off of the computed
/// inverse (relative ≈ κ·ε ≤ 1e-5 here). ≈ 5× cheaper than the eigenvalues.
template <int N>
bool inverseOfWellConditionedCovariance(const Eigen::Matrix<double, N, N>& m, Eigen::Matrix<double, N, N>& inverse) {
  using Matrix = Eigen::Matrix<double, N, N>;
  const Matrix symmetric = 0.5 * (m + m.transpose());
  // S = L Lᵀ and S⁻¹ = L⁻ᵀ L⁻¹ by BlockCholesky's diagonal-block factorisation (a 3×3 padded with an
  // identity, which leaves its factor and inverse exact): Eigen's LLT::solve goes through its dynamic-size
  // triangular kernels, which made this check most of the cost of recording a detection.
  using Block = Eigen::Matrix<double, 6, 6>;
  Block padded = Block::Identity();
  padded.template topLeftCorner<N, N>() = symmetric;
  Block l_inverse;
  double pivot = 0.0;
  if (block_factor::choleskyAndInverse(padded.data(), l_inverse.data(), pivot) >= 0) return false;
  const Matrix candidate = l_inverse.template topLeftCorner<N, N>().transpose() * l_inverse.template topLeftCorner<N, N>();
  if (!candidate.allFinite()) return false;
  const double norm = symmetric.cwiseAbs().rowwise().sum().maxCoeff();
  const double inverse_norm = candidate.cwiseAbs().rowwise().sum().maxCoeff();
  if (!(norm * inverse_norm < 1e11)) return false;
  inverse = candidate;
  return true;
}
template bool inverseOfWellConditionedCovariance<6>(const Matrix6d&, Matrix6d&);
template bool inverseOfWellConditionedCovariance<3>(const Eigen::Matrix3d&, Eigen::Matrix3d&);

Status checkCovariance(const Eigen::MatrixXd& m, const std::string& what) { return checkCovariance(m, what, nullptr); }

Status checkCovariance(const Eigen::MatrixXd& m, const std::string& what, Eigen::MatrixXd* inverse) {
  if (inverse != nullptr) inverse->resize(0, 0);
  if (m.rows() != m.cols() || m.rows() == 0) return Status(StatusCode::kInvalidArgument, what + " is not square");
  if (!m.allFinite()) return Status(StatusCode::kInvalidArgument, what + " has a non-finite entry");
  if (!symmetricToRoundOff(m)) return Status(StatusCode::kInvalidArgument, what + " is not symmetric");
  if ((m.rows() == 6 && wellConditionedByNormBound<6>(m, inverse)) ||
      (m.rows() == 3 && wellConditionedByNormBound<3>(m, inverse))) {
    return Status();
  }
  // Fixed-size solvers for the 6×6 and 3×3 covariances of the hot paths (no heap, ≈ 3× faster).
  double smallest = 0.0;
  double largest = 0.0;
  if (m.rows() == 6) {
    eigenvalueRange<6>(m, smallest, largest);
  } else if (m.rows() == 3) {
    eigenvalueRange<3>(m, smallest, largest);
  } else {
    eigenvalueRange<Eigen::Dynamic>(m, smallest, largest);
  }
  if (!(largest > 0.0) || !(smallest > 1e-12 * largest)) {
    std::ostringstream message;
    message << what << " is not positive definite (eigenvalues from " << smallest << " to " << largest << ")";
    return Status(StatusCode::kNotPositiveDefinite, message.str());
  }
  return Status();
}

namespace {

bool orthonormalRotation(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d rotation = pose.linear();
  const double orthogonality = (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  return orthogonality <= 1e-6 && rotation.determinant() > 0.0;
}

}  // namespace

Status checkRigidTransform(const Eigen::Isometry3d& pose, const std::string& what) {
  if (!pose.matrix().allFinite()) return Status(StatusCode::kInvalidArgument, what + " has a non-finite entry");
  if (!orthonormalRotation(pose)) return Status(StatusCode::kInvalidArgument, what + " has a rotation that is not orthonormal");
  return Status();
}

bool isRigidTransform(const Eigen::Isometry3d& pose) { return pose.matrix().allFinite() && orthonormalRotation(pose); }

template <int N>
bool surelyValidCovariance(const Eigen::Matrix<double, N, N>& m) {
  if (!m.allFinite() || !symmetricToRoundOff(m)) return false;  // checkCovariance's own tests
  Eigen::Matrix<double, N, N> inverse;
  return inverseOfWellConditionedCovariance<N>(m, inverse);
}
template bool surelyValidCovariance<6>(const Matrix6d&);
template bool surelyValidCovariance<3>(const Eigen::Matrix3d&);

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

Result<Matrix6d> poseInformationFromMetricCovariance(const Matrix6d& covariance_metric, const std::string& what) {
  Matrix6d information;
  DG_RETURN_IF_ERROR(informationFromFixedCovariance<6>(covariance_metric, [&] { return what; }, information));
  return informationMetricToG2o(information);
}

Result<Eigen::Matrix3d> pointInformationFromCovariance(const Eigen::Matrix3d& covariance, const std::string& what) {
  Eigen::Matrix3d information;
  DG_RETURN_IF_ERROR(informationFromFixedCovariance<3>(covariance, [&] { return what; }, information));
  return information;
}

}  // namespace dualgraph
