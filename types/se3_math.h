// SPDX-License-Identifier: MIT
// SO(3)/SE(3) maths: quaternions, exp/log, Jacobians, adjoint, g2o's [t; q.vec] chart and units.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dualgraph {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// ---------------------------------------------------------------------------------------------
// Quaternions. Hamilton convention, stored by Eigen as [x y z w]. Eigen's four-scalar
// constructor takes (w, x, y, z); build quaternions only through these helpers so the order is
// always spelled out at the call site.
// ---------------------------------------------------------------------------------------------

/// The quaternion x·i + y·j + z·k + w (not normalised).
Eigen::Quaterniond quatFromXyzw(double x, double y, double z, double w);
/// The quaternion w + x·i + y·j + z·k (not normalised).
Eigen::Quaterniond quatFromWxyz(double w, double x, double y, double z);
/// Left product matrix in [w; x y z] order: (a ⊗ b) = quatLeftMatrix(a) · b.
Eigen::Matrix4d quatLeftMatrix(const Eigen::Quaterniond& a);
/// Right product matrix in [w; x y z] order: (a ⊗ b) = quatRightMatrix(b) · a.
Eigen::Matrix4d quatRightMatrix(const Eigen::Quaterniond& b);

// ---------------------------------------------------------------------------------------------
// SO(3) and SE(3) with the exponential map. Tangent order [ρ; θ]: translation first, then the
// rotation vector in radians; perturbations are on the right, T ⊞ ξ = T · exp(ξ).
// ---------------------------------------------------------------------------------------------

/// [v]×, so that skew(a) · b = a × b.
Eigen::Matrix3d skew(const Eigen::Vector3d& v);
/// The heading of a rotation's x axis about z [rad], atan2(R₁₀, R₀₀): a gravity-aligned frame's yaw, a gate normal's.
inline double headingOf(const Eigen::Matrix3d& rotation) { return std::atan2(rotation(1, 0), rotation(0, 0)); }
/// A gravity-aligned pose: Rz(yaw) [rad] and `translation` [m].
inline Eigen::Isometry3d gravityAligned(double yaw, const Eigen::Vector3d& translation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}
/// Rodrigues' formula; exact to round-off for any |θ|, including 0.
Eigen::Matrix3d so3Exp(const Eigen::Vector3d& theta);
/// The rotation vector of R with |θ| ∈ [0, π]; stable near 0 and near π (via the quaternion).
Eigen::Vector3d so3Log(const Eigen::Matrix3d& rotation);
/// Right Jacobian Jr(θ): exp(θ + δ) ≈ exp(θ) · exp(Jr(θ) δ).
Eigen::Matrix3d so3RightJacobian(const Eigen::Vector3d& theta);
/// Jr(θ)⁻¹ in closed form; valid for |θ| < 2π.
Eigen::Matrix3d so3RightJacobianInverse(const Eigen::Vector3d& theta);
/// Left Jacobian Jl(θ) = Jr(−θ), the "V" matrix of SE(3)'s exponential.
Eigen::Matrix3d so3LeftJacobian(const Eigen::Vector3d& theta);
/// Jl(θ)⁻¹; valid for |θ| < 2π.
Eigen::Matrix3d so3LeftJacobianInverse(const Eigen::Vector3d& theta);

/// exp of ξ = [ρ; θ]: rotation exp(θ), translation Jl(θ) ρ.
Eigen::Isometry3d se3Exp(const Vector6d& xi);
/// Inverse of se3Exp with |θ| ∈ [0, π].
Vector6d se3Log(const Eigen::Isometry3d& pose);
/// Adjoint in [t; θ] order, so that T · exp(ξ) · T⁻¹ = exp(Ad(T) ξ): [[R, [t]× R], [0, R]].
Matrix6d se3Adjoint(const Eigen::Isometry3d& pose);
/// T ⊞ ξ in the chart the SE(3) edges measure their error in (g2o's [t; q] chart in metric units,
/// translation and rotation apart): translation t + R ρ, rotation R exp(θ). Equal to T · exp(ξ) to first
/// order; unlike it, the translation does not turn with θ (Jl(θ) ρ), which matters when |θ| is large
/// (a far gate's uncertain tilt). The chart of every metric [t; θ] covariance the graph consumes.
Eigen::Isometry3d se3BoxPlus(const Eigen::Isometry3d& pose, const Vector6d& xi);
/// ξ with se3BoxPlus(a, ξ) = b: [Rₐᵀ (t_b − t_a); log(Rₐᵀ R_b)], |θ| ∈ [0, π].
Vector6d se3BoxMinus(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

// ---------------------------------------------------------------------------------------------
// g2o's compact-quaternion chart of SE(3), used by VERTEX_SE3:QUAT / EDGE_SE3:QUAT.
// A 6-vector [t; q.vec] stands for the pose with translation t and rotation quaternion
// (w = √(1 − |q.vec|²), q.vec). The rotation part is ≈ θ/2, not θ: see the unit helpers below.
// ---------------------------------------------------------------------------------------------

/// g2o's increment ("fromVectorMQT"): translation v.head(3), rotation quaternion
/// (√(1 − |qv|²), qv) with qv = v.tail(3); identity rotation when |qv| > 1.
Eigen::Isometry3d g2oIncrement(const Vector6d& v);
/// g2o's chart ("toVectorMQT"): [t; q.vec] with q the rotation's unit quaternion, sign chosen so
/// that w ≥ 0.
Vector6d g2oChart(const Eigen::Isometry3d& pose);
/// The same, also giving that quaternion's w (≥ 0), which the SE(3) edges' Jacobians use.
/// Inline (below): it is in every χ² evaluation of the SE(3) edges.
inline Vector6d g2oChart(const Eigen::Isometry3d& pose, double& w);
/// d g2oChart(A · g2oIncrement(δ) · B) / dδ at δ = 0, a 6×6 matrix (rows [t; q.vec], columns
/// [δt; δq]). The shared building block of every analytic Jacobian of the SE(3) edges.
Matrix6d g2oChartJacobianOfProduct(const Eigen::Isometry3d& A, const Eigen::Isometry3d& B);
/// The same with the rotations' unit quaternions given (hot paths cache them).
Matrix6d g2oChartJacobianOfProduct(const Eigen::Isometry3d& A, const Eigen::Quaterniond& q_a,
                                   const Eigen::Vector3d& t_b, const Eigen::Quaterniond& q_b);
/// Unit quaternion of a rotation matrix's upper-left 3×3 block as g2o extracts it, normalised,
/// sign not changed (w may be negative).
inline Eigen::Quaterniond quatFromRotation(const Eigen::Matrix3d& rotation);
/// g2o's cheap re-orthonormalisation R ← R − ½ R (RᵀR − I), applied periodically to poses that
/// accumulate many increments so their rotation does not drift away from SO(3).
void approximateNearestRotation(Eigen::Matrix3d& rotation);

// ---------------------------------------------------------------------------------------------
// The θ/2 unit trap. g2o's SE(3) rotation error is q.vec ≈ θ/2 (θ in radians), so with
// D = diag(1, 1, 1, 2, 2, 2) in [t; θ] order: a metric information Ω becomes D Ω D in g2o units
// and a metric covariance Σ becomes D⁻¹ Σ D⁻¹. Every metric covariance that enters a g2o-unit
// edge goes through these helpers.
// ---------------------------------------------------------------------------------------------

/// Ω_g2o = D Ω_metric D (rotation rows/columns ×2, rotation block ×4).
Matrix6d informationMetricToG2o(const Matrix6d& information_metric);
/// Σ_g2o = D⁻¹ Σ_metric D⁻¹ (rotation rows/columns ÷2, rotation block ÷4).
Matrix6d covarianceMetricToG2o(const Matrix6d& covariance_metric);
/// Ω_metric = D⁻¹ Ω_g2o D⁻¹.
Matrix6d informationG2oToMetric(const Matrix6d& information_g2o);
/// Σ_metric = D Σ_g2o D.
Matrix6d covarianceG2oToMetric(const Matrix6d& covariance_g2o);

// ---------------------------------------------------------------------------------------------
// Inline definitions (hot paths).
// ---------------------------------------------------------------------------------------------

inline Eigen::Quaterniond quatFromRotation(const Eigen::Matrix3d& rotation) {
  // For a rotation, (1 + tr R, R21 − R12, R02 − R20, R10 − R01) = 4w · (w, x, y, z), and likewise with
  // 4x, 4y or 4z for the other three rows of the classic construction: the largest of the four
  // multipliers is picked as Eigen's Quaternion(Matrix3) picks it (trace > 0, else the largest diagonal
  // entry), and one normalisation gives the unit quaternion (one square root and one division, where
  // constructing and then normalising took two of each on this hot path).
  const Eigen::Matrix3d& r = rotation;
  const double trace = r.trace();
  Eigen::Vector4d v;  // (w, x, y, z)
  if (trace > 0.0) {
    v << 1.0 + trace, r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1);
  } else {
    int i = 0;
    if (r(1, 1) > r(0, 0)) i = 1;
    if (r(2, 2) > r(i, i)) i = 2;
    if (i == 0) {
      v << r(2, 1) - r(1, 2), 1.0 + r(0, 0) - r(1, 1) - r(2, 2), r(0, 1) + r(1, 0), r(0, 2) + r(2, 0);
    } else if (i == 1) {
      v << r(0, 2) - r(2, 0), r(0, 1) + r(1, 0), 1.0 + r(1, 1) - r(0, 0) - r(2, 2), r(1, 2) + r(2, 1);
    } else {
      v << r(1, 0) - r(0, 1), r(0, 2) + r(2, 0), r(1, 2) + r(2, 1), 1.0 + r(2, 2) - r(0, 0) - r(1, 1);
    }
  }
  v /= v.norm();
  return Eigen::Quaterniond(v[0], v[1], v[2], v[3]);
}

inline Vector6d g2oChart(const Eigen::Isometry3d& pose, double& w) {
  Eigen::Quaterniond q = quatFromRotation(pose.linear());
  if (q.w() < 0.0) q.coeffs() *= -1.0;
  w = q.w();
  Vector6d v;
  v.head<3>() = pose.translation();
  v.tail<3>() = q.vec();
  return v;
}

}  // namespace dualgraph
