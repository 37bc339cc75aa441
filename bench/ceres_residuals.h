// SPDX-License-Identifier: MIT
// The Ceres peer's residuals and manifold, written here from the g2o error definitions our types
// implement (core/README.md), so the Ceres cost is exactly ½ Σ ρ(eᵀΩe) = ½ χ² of the same graph:
// residual r = U e with Ω = UᵀU (U the upper Cholesky factor), e as in g2o:
//   EDGE_SE3:QUAT   e = [t; q.vec] of Z⁻¹ · Xi⁻¹ · Xj, quaternion normalised, sign so that w ≥ 0
//   EDGE_SE3_PRIOR  e = [t; q.vec] of Z⁻¹ · X · body_T_sensor
//   EDGE_SE3_TRACKXYZ  e = (X · body_T_sensor)⁻¹ · p − m;   EDGE_POINTXYZ_PRIOR  e = p − m
//   EDGE_SE2        e = [x; y; θ] of Z⁻¹ · Xi⁻¹ · Xj, θ wrapped into (−π, π]
// Pose parameter blocks hold [tx ty tz qx qy qz qw] (Eigen's quaternion storage order) and move on
// G2oPoseManifold, the same right increment as VertexSE3 (x ← x · g2oIncrement([δt; δq])), so both
// solvers see the same tangent space. Jacobians come from Ceres' automatic differentiation, the way a
// Ceres user writes a pose graph. SE2 blocks [x y θ] and points [x y z] are Euclidean, as their
// vertices' increments are additive.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace dualgraph::bench {

inline double scalarPart(double value) { return value; }
template <int N>
double scalarPart(const ceres::Jet<double, N>& value) {
  return value.a;
}

/// [t; q.vec] of the pose (t, q) as g2o's chart: q normalised, its sign flipped when w < 0.
template <typename T>
Eigen::Matrix<T, 6, 1> g2oChartOf(const Eigen::Matrix<T, 3, 1>& t, const Eigen::Quaternion<T>& q) {
  using std::sqrt;
  T scale = T(1.0) / sqrt(q.squaredNorm());
  if (q.w() < T(0.0)) scale = -scale;
  Eigen::Matrix<T, 6, 1> e;
  e.template head<3>() = t;
  e.template tail<3>() = scale * q.vec();
  return e;
}

/// g2o's pose increment on a 7-vector [t; q(x y z w)], on the right: t ← t + R δt, q ← q ⊗ (√(1−|δq|²), δq).
class G2oPoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  /// 7×6 at δ = 0: [[R, 0], [0, B]] with B = d(q ⊗ (1, δq))/dδq, whose columns are orthonormal.
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  /// 6×7: the transpose of PlusJacobian (its left inverse, as PᵀP = I for a unit quaternion).
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

/// EDGE_SE3:QUAT between blocks xi and xj.
class RelativePoseResidual {
 public:
  RelativePoseResidual(const Eigen::Isometry3d& i_T_j, const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : j_T_i_(i_T_j.inverse()), q_j_i_(Eigen::Quaterniond(j_T_i_.linear()).normalized()),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* xi, const T* xj, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_i(xi), t_j(xj);
    const Eigen::Map<const Eigen::Quaternion<T>> q_i(xi + 3), q_j(xj + 3);
    const Eigen::Quaternion<T> q_i_inverse = q_i.conjugate();
    const Eigen::Quaternion<T> q_zinv = q_j_i_.cast<T>();
    // E = Z⁻¹ · (Xi⁻¹ · Xj)
    const Eigen::Matrix<T, 3, 1> t_ij = q_i_inverse * (t_j - t_i);
    const Eigen::Quaternion<T> q_e = q_zinv * (q_i_inverse * q_j);
    const Eigen::Matrix<T, 3, 1> t_e = q_zinv * t_ij + j_T_i_.translation().cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = sqrt_information_.cast<T>() * g2oChartOf<T>(t_e, q_e);
    return true;
  }

 private:
  Eigen::Isometry3d j_T_i_;
  Eigen::Quaterniond q_j_i_;
  Eigen::Matrix<double, 6, 6> sqrt_information_;
};

/// EDGE_SE3_PRIOR on block x.
class PosePriorResidual {
 public:
  PosePriorResidual(const Eigen::Isometry3d& world_T_sensor, const Eigen::Isometry3d& body_T_sensor,
                    const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : sensor_T_world_(world_T_sensor.inverse()),
        q_sensor_world_(Eigen::Quaterniond(sensor_T_world_.linear()).normalized()),
        body_T_sensor_(body_T_sensor),
        q_body_sensor_(Eigen::Quaterniond(body_T_sensor.linear()).normalized()),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* x, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(x);
    const Eigen::Map<const Eigen::Quaternion<T>> q(x + 3);
    const Eigen::Quaternion<T> q_zinv = q_sensor_world_.cast<T>();
    // E = Z⁻¹ · X · body_T_sensor
    const Eigen::Matrix<T, 3, 1> t_world_sensor = q * body_T_sensor_.translation().cast<T>() + t;
    const Eigen::Quaternion<T> q_e = q_zinv * (q * q_body_sensor_.cast<T>());
    const Eigen::Matrix<T, 3, 1> t_e = q_zinv * t_world_sensor + sensor_T_world_.translation().cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = sqrt_information_.cast<T>() * g2oChartOf<T>(t_e, q_e);
    return true;
  }

 private:
  Eigen::Isometry3d sensor_T_world_;
  Eigen::Quaterniond q_sensor_world_;
  Eigen::Isometry3d body_T_sensor_;
  Eigen::Quaterniond q_body_sensor_;
  Eigen::Matrix<double, 6, 6> sqrt_information_;
};

/// EDGE_SE3_TRACKXYZ: pose block x, point block p.
class PointObservationResidual {
 public:
  PointObservationResidual(const Eigen::Vector3d& p_sensor, const Eigen::Isometry3d& body_T_sensor,
                           const Eigen::Matrix3d& sqrt_information)
      : p_sensor_(p_sensor), sensor_T_body_(body_T_sensor.inverse()),
        q_sensor_body_(Eigen::Quaterniond(sensor_T_body_.linear()).normalized()), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* x, const T* p, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(x), p_world(p);
    const Eigen::Map<const Eigen::Quaternion<T>> q(x + 3);
    const Eigen::Matrix<T, 3, 1> p_body = q.conjugate() * (p_world - t);
    const Eigen::Matrix<T, 3, 1> p_in_sensor = q_sensor_body_.cast<T>() * p_body + sensor_T_body_.translation().cast<T>();
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.cast<T>() * (p_in_sensor - p_sensor_.cast<T>());
    return true;
  }

 private:
  Eigen::Vector3d p_sensor_;
  Eigen::Isometry3d sensor_T_body_;
  Eigen::Quaterniond q_sensor_body_;
  Eigen::Matrix3d sqrt_information_;
};

/// EDGE_POINTXYZ_PRIOR on point block p.
class PointPriorResidual {
 public:
  PointPriorResidual(const Eigen::Vector3d& p_world, const Eigen::Matrix3d& sqrt_information)
      : p_world_(p_world), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* p, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> point(p);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.cast<T>() * (point - p_world_.cast<T>());
    return true;
  }

 private:
  Eigen::Vector3d p_world_;
  Eigen::Matrix3d sqrt_information_;
};

/// EDGE_SE2 between blocks [x y θ].
class RelativePose2dResidual {
 public:
  RelativePose2dResidual(const Eigen::Vector3d& i_T_j, const Eigen::Matrix3d& sqrt_information)
      : z_(i_T_j), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* xi, const T* xj, T* residual) const {
    using std::cos;
    using std::sin;
    // Xi⁻¹ · Xj, then Z⁻¹ · that.
    const T dx = xj[0] - xi[0], dy = xj[1] - xi[1];
    const T ci = cos(xi[2]), si = sin(xi[2]);
    const T x_ij = ci * dx + si * dy, y_ij = -si * dx + ci * dy;
    const double cz = std::cos(z_.z()), sz = std::sin(z_.z());
    const T ex = cz * (x_ij - z_.x()) + sz * (y_ij - z_.y());
    const T ey = -sz * (x_ij - z_.x()) + cz * (y_ij - z_.y());
    const T theta = xj[2] - xi[2] - z_.z();
    // Wrap into (−π, π] by a constant multiple of 2π (no derivative).
    const double turns = std::ceil((scalarPart(theta) - M_PI) / (2.0 * M_PI));
    const Eigen::Matrix<T, 3, 1> e(ex, ey, theta - T(2.0 * M_PI * turns));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

 private:
  Eigen::Vector3d z_;  ///< [x y θ] of i_T_j
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace dualgraph::bench
