// SPDX-License-Identifier: MIT
#include "dual_graph/measurements.h"

#include "solvers/block_diagonal_factor.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>

namespace dualgraph {

GateObservation GateObservation::pose(double t, int gate_id, const Eigen::Isometry3d& body_T_gate,
                                      const Matrix6d& covariance) {
  GateObservation observation;
  observation.t = t;
  observation.gate_id = gate_id;
  observation.kind = ObservationKind::kPose;
  observation.body_T_gate = body_T_gate;
  observation.pose_covariance = covariance;
  observation.p_body = body_T_gate.translation();
  return observation;
}

GateObservation GateObservation::position(double t, int gate_id, const Eigen::Vector3d& p_body,
                                          const Eigen::Matrix3d& covariance) {
  GateObservation observation;
  observation.t = t;
  observation.gate_id = gate_id;
  observation.kind = ObservationKind::kPosition;
  observation.p_body = p_body;
  observation.body_T_gate.translation() = p_body;
  observation.position_covariance = covariance;
  return observation;
}

Eigen::Matrix3d GateObservation::centreCovarianceInBody() const {
  if (kind == ObservationKind::kPosition) return position_covariance;
  // body_T_gate · exp([ρ; θ]) moves the centre by R_body_gate · ρ to first order.
  const Eigen::Matrix3d rotation = body_T_gate.linear();
  return rotation * pose_covariance.topLeftCorner<3, 3>() * rotation.transpose();
}

std::string formatTimestamp(double t) {
  std::ostringstream text;
  text.precision(17);
  text << t;
  return text.str();
}

namespace {

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
  const double scale = m.cwiseAbs().maxCoeff();
  if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-9 * std::max(scale, 1e-300)) {
    return Status(StatusCode::kInvalidArgument, what + " is not symmetric");
  }
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

Status checkRigidTransform(const Eigen::Isometry3d& pose, const std::string& what) {
  if (!pose.matrix().allFinite()) return Status(StatusCode::kInvalidArgument, what + " has a non-finite entry");
  const Eigen::Matrix3d rotation = pose.linear();
  const double orthogonality = (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthogonality > 1e-6 || rotation.determinant() <= 0.0) {
    return Status(StatusCode::kInvalidArgument, what + " has a rotation that is not orthonormal");
  }
  return Status();
}

Status validateOdometrySample(const OdometrySample& sample) {
  const std::string where = "odometry sample at t=" + std::to_string(sample.t) + ": ";
  if (!std::isfinite(sample.t)) return Status(StatusCode::kInvalidArgument, "odometry sample: time stamp is not finite");
  DG_RETURN_IF_ERROR(checkRigidTransform(sample.odom_T_body, where + "odom_T_body"));
  if (sample.relative_covariance) {
    DG_RETURN_IF_ERROR(checkCovariance(*sample.relative_covariance, where + "relative_covariance"));
  }
  return Status();
}

Status validateGateObservation(const GateObservation& observation) {
  if (!std::isfinite(observation.t)) return Status(StatusCode::kInvalidArgument, "gate observation: time stamp is not finite");
  const std::string where =
      "gate observation of gate " + std::to_string(observation.gate_id) + " at t=" + std::to_string(observation.t) + ": ";
  if (observation.gate_id < 0) return Status(StatusCode::kInvalidArgument, where + "gate_id must be >= 0");
  if (observation.kind == ObservationKind::kPose) {
    DG_RETURN_IF_ERROR(checkRigidTransform(observation.body_T_gate, where + "body_T_gate"));
    return checkCovariance(observation.pose_covariance, where + "pose_covariance");
  }
  if (!observation.p_body.allFinite()) return Status(StatusCode::kInvalidArgument, where + "p_body has a non-finite entry");
  return checkCovariance(observation.position_covariance, where + "position_covariance");
}

}  // namespace dualgraph
