// SPDX-License-Identifier: MIT
#include "frontend/gate_pnp_posterior.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace dualgraph::pnp_detail {
namespace {

// The lattice covers ± kHalfWidth standard deviations of each tilt with kNodesPerSide nodes on each side
// of the centre (spacing 4σ/3: the trapezoid rule's relative error on a Gaussian is 2 exp(−2π²σ²/h²) ≈ 3e-5).
// The mean NEES of test/frontend/simulator_sensors_test.cpp moves by < 0.01 between this and ±5σ at σ/2.
constexpr double kHalfWidth = 4.0;
constexpr int kNodesPerSide = 3;
constexpr int kMaxNodesAcross = 41;      // along the axis towards the other tilt, at most
constexpr double kMaxSigma = 0.35;       // [rad]: a Laplace standard deviation above this is capped
constexpr double kOtherTiltLogRatio = 30.0;  // the other tilt joins the lattice when ΔSSR / 2σ² ≤ this
constexpr int kRefits = 2;               // Gauss–Newton steps on the four other coordinates per node

}  // namespace

bool residuals(const Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const GateCornerPixels& pixels,
               const CameraModel& camera, Vector8d& r) {
  for (int i = 0; i < 4; ++i) {
    const Projection projection = camera.project(camera_T_gate * Eigen::Vector3d(p_gate.col(i)));
    if (!projection.in_front) return false;
    r.segment<2>(2 * i) = projection.pixel - pixels.col(i);
  }
  return true;
}

bool tiltPosteriorCovariance(const TiltPosteriorInput& input, const Corners3& p_gate, const GateCornerPixels& pixels,
                             const CameraModel& camera, double pixel_sigma, Matrix6d& covariance) {
  const Eigen::Isometry3d& pose = input.camera_T_gate;
  const double sigma2 = pixel_sigma * pixel_sigma;
  // Coordinates y = [translation (3); roll about the line of sight; tilt α; tilt β], ε = E y.
  const Eigen::Vector3d sight = (pose.linear().transpose() * pose.translation()).normalized();  // gate frame
  const Matrix6d H = input.jacobian.transpose() * input.jacobian;  // [px² per unit²]
  Eigen::Vector3d a = sight.unitOrthogonal();
  double other_alpha = 0.0;  // where the other tilt lies along a [rad]
  const bool with_other = input.other_tilt != nullptr &&
                          (input.other_ssr - input.ssr) / (2.0 * sigma2) <= kOtherTiltLogRatio;
  if (with_other) {
    const Eigen::Vector3d theta = se3BoxMinus(pose, *input.other_tilt).tail<3>();
    const Eigen::Vector3d tilt = theta - theta.dot(sight) * sight;
    if (tilt.norm() > 1e-9) a = tilt.normalized(), other_alpha = tilt.norm();
  }
  if (other_alpha == 0.0) {  // no other tilt: a along the widest tilt direction
    const Eigen::Vector3d b0 = sight.cross(a);
    Matrix6d E0 = Matrix6d::Identity();  // any completion; only the tilt marginal is read
    E0.block<3, 3>(3, 3) << sight, a, b0;
    const Eigen::Matrix2d tilt_cov = (E0.transpose() * H * E0).ldlt().solve(Matrix6d::Identity()).bottomRightCorner<2, 2>();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(tilt_cov);
    const Eigen::Vector2d widest = eigen.eigenvectors().col(1);
    a = (widest.x() * a + widest.y() * b0).normalized();
  }
  const Eigen::Vector3d b = sight.cross(a);
  Matrix6d E = Matrix6d::Zero();
  E.topLeftCorner<3, 3>().setIdentity();
  E.block<3, 3>(3, 3) << sight, a, b;
  const Matrix6d Hy = E.transpose() * H * E;
  const Eigen::LDLT<Matrix6d> Hy_ldlt(Hy);
  const Matrix6d Sy = Hy_ldlt.solve(Matrix6d::Identity());  // [unit² per px²]; times σ² is the Laplace covariance
  const Eigen::Matrix2d St = sigma2 * Sy.bottomRightCorner<2, 2>();
  if (!(St(0, 0) > 0.0) || !St.allFinite()) return false;
  const double sigma_alpha = std::min(std::sqrt(St(0, 0)), kMaxSigma);
  const double slope = St(1, 0) / St(0, 0);  // E[β | α] = slope α
  const double sigma_beta = std::min(std::sqrt(std::max(St(1, 1) - St(1, 0) * slope, 0.0)), kMaxSigma);
  if (!(sigma_beta > 0.0)) return false;

  const double lo = std::min(0.0, other_alpha) - kHalfWidth * sigma_alpha;
  const double hi = std::max(0.0, other_alpha) + kHalfWidth * sigma_alpha;
  const double h_alpha = std::max(sigma_alpha * kHalfWidth / kNodesPerSide, (hi - lo) / (kMaxNodesAcross - 1));
  const int n_alpha = static_cast<int>(std::ceil((hi - lo) / h_alpha - 1e-9)) + 1;
  const double h_beta = sigma_beta * kHalfWidth / kNodesPerSide;

  // The other four given the tilt: linear prediction −Hoo⁻¹ Hot τ, then chord Gauss–Newton steps with
  // the Jacobian at the returned pose; their conditional covariance σ² Hoo⁻¹.
  const Eigen::Matrix<double, 8, 4> J_other = input.jacobian * E.leftCols<4>();
  const Eigen::Matrix4d H_other = J_other.transpose() * J_other;
  const Eigen::LDLT<Eigen::Matrix4d> H_other_ldlt(H_other);
  const Eigen::Matrix<double, 4, 8> step_map = H_other_ldlt.solve(J_other.transpose());
  const Eigen::Matrix<double, 4, 2> predict = -H_other_ldlt.solve(Hy.topRightCorner<4, 2>());
  if (!step_map.allFinite() || !predict.allFinite()) return false;

  double weight_sum = 0.0;
  Matrix6d moment = Matrix6d::Zero();
  for (int i = 0; i < n_alpha; ++i) {
    const double alpha = lo + i * h_alpha;
    for (int j = -kNodesPerSide; j <= kNodesPerSide; ++j) {
      Vector6d y;
      y.tail<2>() << alpha, slope * alpha + j * h_beta;
      y.head<4>() = predict * y.tail<2>();
      Vector8d r;
      bool in_front = true;
      for (int it = 0; it < kRefits && in_front; ++it) {
        in_front = residuals(se3BoxPlus(pose, E * y), p_gate, pixels, camera, r);
        if (in_front) y.head<4>() -= step_map * r;
      }
      if (!in_front || !residuals(se3BoxPlus(pose, E * y), p_gate, pixels, camera, r)) continue;
      const double weight = std::exp(-std::min(700.0, (r.squaredNorm() - input.ssr) / (2.0 * sigma2)));
      const Vector6d epsilon = E * y;
      weight_sum += weight;
      moment.noalias() += weight * epsilon * epsilon.transpose();
    }
  }
  if (!(weight_sum > 0.0) || !moment.allFinite()) return false;
  Matrix6d conditional = Matrix6d::Zero();
  conditional.topLeftCorner<4, 4>() = sigma2 * H_other_ldlt.solve(Eigen::Matrix4d::Identity());
  covariance = moment / weight_sum + E * conditional * E.transpose();
  covariance = (0.5 * (covariance + covariance.transpose())).eval();
  return covariance.allFinite();
}

}  // namespace dualgraph::pnp_detail
