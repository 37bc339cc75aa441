// SPDX-License-Identifier: MIT
#include "dualgraph/types/se3_math.h"

#include <cmath>

namespace dualgraph {
namespace {

// Below these angles the closed forms lose digits to cancellation; their Taylor series (with the
// terms kept below) are exact to round-off there.
constexpr double kSmallAngleExp = 1e-4;
constexpr double kSmallAngleJacobian = 1e-3;
constexpr double kSmallAngleJacobianInverse = 1e-2;
constexpr double kSmallQuaternionVector = 1e-6;

/// (1 − cos θ)/θ² and (θ − sin θ)/θ³, the coefficients of [θ]× and [θ]×² in Jl(θ).
void leftJacobianCoefficients(double angle, double& b, double& c) {
  const double a2 = angle * angle;
  if (angle < kSmallAngleJacobian) {
    b = 0.5 - a2 / 24.0 + a2 * a2 / 720.0;
    c = 1.0 / 6.0 - a2 / 120.0 + a2 * a2 / 5040.0;
    return;
  }
  const double half_sine = std::sin(0.5 * angle);
  b = 2.0 * half_sine * half_sine / a2;
  c = (angle - std::sin(angle)) / (a2 * angle);
}

/// 1/θ² − (1 + cos θ)/(2θ sin θ), the coefficient of [θ]×² in Jr(θ)⁻¹ and Jl(θ)⁻¹.
double inverseJacobianCoefficient(double angle) {
  const double a2 = angle * angle;
  if (angle < kSmallAngleJacobianInverse) return 1.0 / 12.0 + a2 / 720.0 + a2 * a2 / 30240.0;
  // (1 + cos θ)/sin θ = cot(θ/2), which stays well conditioned up to θ = π.
  return 1.0 / a2 - std::cos(0.5 * angle) / (2.0 * angle * std::sin(0.5 * angle));
}

/// D · M · D with D = diag(s_t, s_t, s_t, s_r, s_r, s_r).
Matrix6d scaleBlocks(const Matrix6d& m, double s_t, double s_r) {
  Vector6d d;
  d << s_t, s_t, s_t, s_r, s_r, s_r;
  return d.asDiagonal() * m * d.asDiagonal();
}

}  // namespace

Eigen::Quaterniond quatFromXyzw(double x, double y, double z, double w) {
  return Eigen::Quaterniond(w, x, y, z);
}

Eigen::Quaterniond quatFromWxyz(double w, double x, double y, double z) {
  return Eigen::Quaterniond(w, x, y, z);
}

Eigen::Matrix4d quatLeftMatrix(const Eigen::Quaterniond& a) {
  Eigen::Matrix4d m;
  m(0, 0) = a.w();
  m.block<1, 3>(0, 1) = -a.vec().transpose();
  m.block<3, 1>(1, 0) = a.vec();
  m.block<3, 3>(1, 1) = a.w() * Eigen::Matrix3d::Identity() + skew(a.vec());
  return m;
}

Eigen::Matrix4d quatRightMatrix(const Eigen::Quaterniond& b) {
  Eigen::Matrix4d m;
  m(0, 0) = b.w();
  m.block<1, 3>(0, 1) = -b.vec().transpose();
  m.block<3, 1>(1, 0) = b.vec();
  m.block<3, 3>(1, 1) = b.w() * Eigen::Matrix3d::Identity() - skew(b.vec());
  return m;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(),
       v.z(), 0.0, -v.x(),
       -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Matrix3d so3Exp(const Eigen::Vector3d& theta) {
  const double a2 = theta.squaredNorm();
  const double angle = std::sqrt(a2);
  double sinc = 0.0;     // sin θ / θ
  double cosc = 0.0;     // (1 − cos θ) / θ²
  if (angle < kSmallAngleExp) {
    sinc = 1.0 - a2 / 6.0;
    cosc = 0.5 - a2 / 24.0;
  } else {
    const double half_sine = std::sin(0.5 * angle);
    sinc = std::sin(angle) / angle;
    cosc = 2.0 * half_sine * half_sine / a2;
  }
  const Eigen::Matrix3d k = skew(theta);
  return Eigen::Matrix3d::Identity() + sinc * k + cosc * k * k;
}

Eigen::Vector3d so3Log(const Eigen::Matrix3d& rotation) {
  Eigen::Quaterniond q = quatFromRotation(rotation);
  if (q.w() < 0.0) q.coeffs() *= -1.0;
  const double n = q.vec().norm();
  // θ = 2 atan2(|v|, w) · v/|v|; for tiny |v| the series of 2 atan2(n, w)/n avoids 0/0.
  const double scale = n < kSmallQuaternionVector
                           ? 2.0 / q.w() * (1.0 - n * n / (3.0 * q.w() * q.w()))
                           : 2.0 * std::atan2(n, q.w()) / n;
  return scale * q.vec();
}

Eigen::Matrix3d so3RightJacobian(const Eigen::Vector3d& theta) {
  double b = 0.0, c = 0.0;
  leftJacobianCoefficients(theta.norm(), b, c);
  const Eigen::Matrix3d k = skew(theta);
  return Eigen::Matrix3d::Identity() - b * k + c * k * k;
}

Eigen::Matrix3d so3RightJacobianInverse(const Eigen::Vector3d& theta) {
  const Eigen::Matrix3d k = skew(theta);
  return Eigen::Matrix3d::Identity() + 0.5 * k + inverseJacobianCoefficient(theta.norm()) * k * k;
}

Eigen::Matrix3d so3LeftJacobian(const Eigen::Vector3d& theta) { return so3RightJacobian(-theta); }

Eigen::Matrix3d so3LeftJacobianInverse(const Eigen::Vector3d& theta) {
  return so3RightJacobianInverse(-theta);
}

Eigen::Isometry3d se3Exp(const Vector6d& xi) {
  const Eigen::Vector3d theta = xi.tail<3>();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = so3Exp(theta);
  pose.translation() = so3LeftJacobian(theta) * xi.head<3>();
  return pose;
}

Vector6d se3Log(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d theta = so3Log(pose.linear());
  Vector6d xi;
  xi.head<3>() = so3LeftJacobianInverse(theta) * pose.translation();
  xi.tail<3>() = theta;
  return xi;
}

Matrix6d se3Adjoint(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d rotation = pose.linear();
  Matrix6d adjoint = Matrix6d::Zero();
  adjoint.topLeftCorner<3, 3>() = rotation;
  adjoint.topRightCorner<3, 3>() = skew(pose.translation()) * rotation;
  adjoint.bottomRightCorner<3, 3>() = rotation;
  return adjoint;
}

Eigen::Isometry3d se3BoxPlus(const Eigen::Isometry3d& pose, const Vector6d& xi) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translation() = pose.translation() + pose.linear() * xi.head<3>();
  result.linear() = pose.linear() * so3Exp(xi.tail<3>());
  return result;
}

Vector6d se3BoxMinus(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  Vector6d xi;
  xi.head<3>() = a.linear().transpose() * (b.translation() - a.translation());
  xi.tail<3>() = so3Log(a.linear().transpose() * b.linear());
  return xi;
}

Eigen::Isometry3d g2oIncrement(const Vector6d& v) {
  Eigen::Isometry3d increment = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d qv = v.tail<3>();
  const double w2 = 1.0 - qv.squaredNorm();
  if (w2 >= 0.0) increment.linear() = quatFromWxyz(std::sqrt(w2), qv.x(), qv.y(), qv.z()).toRotationMatrix();
  increment.translation() = v.head<3>();
  return increment;
}

Vector6d g2oChart(const Eigen::Isometry3d& pose) {
  double w = 0.0;
  return g2oChart(pose, w);
}

Matrix6d g2oChartJacobianOfProduct(const Eigen::Isometry3d& A, const Eigen::Isometry3d& B) {
  // E(δ) = A · Δ(δ) · B with Δ = (R_δ, δt), R_δ ≈ I + 2[δq]×:
  //   t_E = t_A + R_A (δt + R_δ t_B)  →  ∂/∂δt = R_A,  ∂/∂δq = −2 R_A [t_B]×
  //   q_E = q_A ⊗ (1, δq) ⊗ q_B = L(q_A) R(q_B) (1, δq)  →  ∂vec/∂δq = (L(q_A) R(q_B))[1:4, 1:4],
  // times the sign that the chart applies to make w_E ≥ 0. Normalisation does not contribute
  // at first order because q_A ⊗ (0, u) ⊗ q_B is orthogonal to q_A ⊗ q_B.
  return g2oChartJacobianOfProduct(A, quatFromRotation(A.linear()), B.translation(),
                                   quatFromRotation(B.linear()));
}

Matrix6d g2oChartJacobianOfProduct(const Eigen::Isometry3d& A, const Eigen::Quaterniond& q_a,
                                   const Eigen::Vector3d& t_b, const Eigen::Quaterniond& q_b) {
  const Eigen::Matrix3d rotation_a = A.linear();
  const double sign = (q_a * q_b).w() >= 0.0 ? 1.0 : -1.0;
  const Eigen::Matrix4d product = quatLeftMatrix(q_a) * quatRightMatrix(q_b);
  Matrix6d J = Matrix6d::Zero();
  J.topLeftCorner<3, 3>() = rotation_a;
  J.topRightCorner<3, 3>() = -2.0 * rotation_a * skew(t_b);
  J.bottomRightCorner<3, 3>() = sign * product.bottomRightCorner<3, 3>();
  return J;
}

void approximateNearestRotation(Eigen::Matrix3d& rotation) {
  const Eigen::Matrix3d excess = rotation.transpose() * rotation - Eigen::Matrix3d::Identity();
  rotation -= 0.5 * rotation * excess;
}

Matrix6d informationMetricToG2o(const Matrix6d& information_metric) {
  return scaleBlocks(information_metric, 1.0, 2.0);
}

Matrix6d covarianceMetricToG2o(const Matrix6d& covariance_metric) {
  return scaleBlocks(covariance_metric, 1.0, 0.5);
}

Matrix6d informationG2oToMetric(const Matrix6d& information_g2o) {
  return scaleBlocks(information_g2o, 1.0, 0.5);
}

Matrix6d covarianceG2oToMetric(const Matrix6d& covariance_g2o) {
  return scaleBlocks(covariance_g2o, 1.0, 2.0);
}

}  // namespace dualgraph
