// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/gate_pnp_posterior.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace dualgraph::pnp_detail {
namespace {

// The lattice covers ± kHalfWidth standard deviations of each tilt with kNodesPerSide nodes on each side
// of the centre (spacing 0.8σ). On a Gaussian the trapezoid rule would be exact to 1e-5 at 4σ/3 already,
// but a far near-frontal view's flat-topped tilt needs more: against an importance-sampled posterior
// (test/frontend/gate_pnp_test.cpp) 4σ/3 left one direction 15 % short, 0.8σ is within 3–9 %, and finer
// lattices do not get closer (what is left is the other four coordinates' Gaussian approximation).
constexpr double kHalfWidth = 4.0;
constexpr int kNodesPerSide = 5;
constexpr int kMaxNodesAcross = 41;      // along the axis towards the other tilt, at most
constexpr double kMaxSigma = 0.35;       // [rad]: a Laplace standard deviation above this is capped
constexpr double kOtherTiltLogRatio = 30.0;  // the other tilt joins the lattice when ΔSSR / 2σ² ≤ this
constexpr int kRefits = 2;
constexpr double kNegligibleWeight = 1e-9;  // a node's weight against the returned pose's               // Gauss–Newton steps on the four other coordinates per node

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

// The corner p_c = R p + t moves by R ε_t − R [p]× ε_θ, chained with CameraModel's analytic ∂pixel/∂p_c.
bool jacobian(const Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const CameraModel& camera,
              Matrix86d& J_r_eps) {
  const Eigen::Matrix3d& R = camera_T_gate.linear();
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d p = p_gate.col(i);
    Eigen::Matrix<double, 2, 3> d_pixel;
    if (!camera.project(camera_T_gate * p, &d_pixel).in_front) return false;
    const Eigen::Matrix<double, 2, 3> d_pixel_R = d_pixel * R;
    J_r_eps.block<2, 3>(2 * i, 0) = d_pixel_R;
    J_r_eps.block<2, 3>(2 * i, 3) = -d_pixel_R * skew(p);
  }
  return J_r_eps.allFinite();
}

namespace {

/// ∂r/∂y of the four other coordinates y = [ε_t; roll about `sight`] of se3BoxPlus(pose, ε) at the node
/// ε = (·, theta): in the returned pose's chart, where the moment is taken (the node's own chart would turn
/// a far gate's depth variance into lateral variance by the tilt). ∂p_c/∂ε_t = R, ∂p_c/∂ε_θ = −R_node [p]× J_r(θ).
bool otherJacobian(const Eigen::Isometry3d& pose, const Eigen::Isometry3d& node, const Eigen::Vector3d& theta,
                   const Eigen::Vector3d& sight, const Corners3& p_gate, const CameraModel& camera,
                   Eigen::Matrix<double, 8, 4>& J) {
  const Eigen::Vector3d roll_axis = so3RightJacobian(theta) * sight;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d p = p_gate.col(i);
    Eigen::Matrix<double, 2, 3> d_pixel;
    if (!camera.project(node * p, &d_pixel).in_front) return false;
    J.block<2, 3>(2 * i, 0) = d_pixel * pose.linear();
    J.block<2, 1>(2 * i, 3) = -d_pixel * (node.linear() * p.cross(roll_axis));
  }
  return J.allFinite();
}

}  // namespace

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
  // the Jacobian at the returned pose; their conditional covariance σ² (J_oᵀ J_o)⁻¹ with J_o at the node,
  // whose volume √det also weighs the node (the Laplace mass of the four given the tilt).
  const Eigen::Matrix<double, 8, 4> J_other = input.jacobian * E.leftCols<4>();
  const Eigen::Matrix4d H_other = J_other.transpose() * J_other;
  const Eigen::LDLT<Eigen::Matrix4d> H_other_ldlt(H_other);
  const Eigen::Matrix<double, 4, 8> step_map = H_other_ldlt.solve(J_other.transpose());
  const Eigen::Matrix<double, 4, 2> predict = -H_other_ldlt.solve(Hy.topRightCorner<4, 2>());
  if (!step_map.allFinite() || !predict.allFinite()) return false;
  const double reference_determinant = H_other_ldlt.vectorD().prod();

  double weight_sum = 0.0;
  Matrix6d moment = Matrix6d::Zero();
  // One node: its weight (0 when a corner falls behind the camera), added to the sums.
  const auto add_node = [&](double alpha, double beta) {
    Vector6d y;
    y.tail<2>() << alpha, beta;
    y.head<4>() = predict * y.tail<2>();
    Vector8d r;
    bool in_front = true;
    for (int it = 0; it < kRefits && in_front; ++it) {
      in_front = residuals(se3BoxPlus(pose, E * y), p_gate, pixels, camera, r);
      if (in_front) y.head<4>() -= step_map * r;
    }
    const Eigen::Isometry3d node = se3BoxPlus(pose, E * y);
    Eigen::Matrix<double, 8, 4> J_node_other;
    if (!in_front || !residuals(node, p_gate, pixels, camera, r) ||
        !otherJacobian(pose, node, (E * y).tail<3>(), sight, p_gate, camera, J_node_other)) {
      return 0.0;
    }
    const Eigen::LDLT<Eigen::Matrix4d> node_ldlt(J_node_other.transpose() * J_node_other);
    const double volume = std::sqrt(reference_determinant / node_ldlt.vectorD().prod());  // √det C_node / √det C₀
    if (node_ldlt.info() != Eigen::Success || !(node_ldlt.vectorD().minCoeff() > 0.0) || !std::isfinite(volume)) return 0.0;
    const double weight = volume * std::exp(-std::min(700.0, (r.squaredNorm() - input.ssr) / (2.0 * sigma2)));
    const Vector6d epsilon = E * y;
    Matrix6d conditional = Matrix6d::Zero();
    conditional.topLeftCorner<4, 4>() = sigma2 * node_ldlt.solve(Eigen::Matrix4d::Identity());
    weight_sum += weight;
    moment.noalias() += weight * (epsilon * epsilon.transpose() + E * conditional * E.transpose());
    return weight;
  };
  // Each column from its centre outwards, each side until a node's weight is negligible against the
  // returned pose's (≈ 1): given the tilt along the first axis the second is one-peaked, so what lies
  // beyond adds nothing; columns between two far-apart modes then cost three nodes instead of eleven.
  for (int i = 0; i < n_alpha; ++i) {
    const double alpha = lo + i * h_alpha;
    const double centre = slope * alpha;
    add_node(alpha, centre);
    for (int side : {1, -1}) {
      for (int j = 1; j <= kNodesPerSide; ++j) {
        if (add_node(alpha, centre + side * j * h_beta) < kNegligibleWeight) break;
      }
    }
  }
  if (!(weight_sum > 0.0) || !moment.allFinite()) return false;
  covariance = moment / weight_sum;
  covariance = (0.5 * (covariance + covariance.transpose())).eval();
  return covariance.allFinite();
}

bool twoModeMoment(const Eigen::Isometry3d& centre, const Matrix6d& centre_covariance, double centre_ssr,
                   const Eigen::Isometry3d& other, const Matrix6d& other_covariance, double other_ssr, double sigma2,
                   Matrix6d& moment) {
  // other ⊞ ε_o = centre ⊞ (δ + A ε_o) to first order.
  const Vector6d delta = se3BoxMinus(centre, other);
  Matrix6d adjoint = Matrix6d::Zero();
  adjoint.topLeftCorner<3, 3>() = centre.linear().transpose() * other.linear();
  adjoint.bottomRightCorner<3, 3>() = so3RightJacobianInverse(delta.tail<3>());
  const Matrix6d moved = adjoint * other_covariance * adjoint.transpose();
  // log(w_o / w_c), then a logistic that neither overflows nor underflows to NaN.
  const double log_ratio = -(other_ssr - centre_ssr) / (2.0 * sigma2) +
                           0.5 * std::log(std::max(1e-300, moved.determinant() / centre_covariance.determinant()));
  if (std::isnan(log_ratio)) return false;
  const double w_other =
      log_ratio > 0.0 ? 1.0 / (1.0 + std::exp(-log_ratio)) : std::exp(log_ratio) / (1.0 + std::exp(log_ratio));
  moment = (1.0 - w_other) * centre_covariance + w_other * (moved + delta * delta.transpose());
  moment = 0.5 * (moment + moment.transpose()).eval();
  return moment.allFinite();
}

}  // namespace dualgraph::pnp_detail
