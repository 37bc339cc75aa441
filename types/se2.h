// SPDX-License-Identifier: MIT
// SE2, the planar rigid transform of VertexSE2 and EdgeSE2, and angle wrapping into (−π, π].
#pragma once

#include <Eigen/Core>

namespace dualgraph {

/// The angle wrapped into (−π, π]; angles already in range are returned unchanged (bit-exact).
double normalizeAngle(double angle);

/// A planar rigid transform `a_T_b` (rotation angle θ in radians, translation in metres):
/// maps points from frame b to frame a as p_a = R(θ) p_b + t. The angle is always kept in (−π, π].
/// This is the value type of VertexSE2 / EdgeSE2 (g2o's SE2).
class SE2 {
 public:
  SE2() = default;
  SE2(double x, double y, double theta) : translation_(x, y), theta_(normalizeAngle(theta)) {}
  /// From [x; y; θ].
  static SE2 fromVector(const Eigen::Vector3d& v) { return SE2(v.x(), v.y(), v.z()); }

  const Eigen::Vector2d& translation() const { return translation_; }
  double x() const { return translation_.x(); }
  double y() const { return translation_.y(); }
  double angle() const { return theta_; }
  /// R(θ) = [[cos θ, −sin θ], [sin θ, cos θ]].
  Eigen::Matrix2d rotation() const;
  /// [x; y; θ].
  Eigen::Vector3d toVector() const { return Eigen::Vector3d(x(), y(), theta_); }

  /// `b_T_a` from `a_T_b`.
  SE2 inverse() const;
  /// `a_T_c` = `a_T_b` · `b_T_c`.
  SE2 operator*(const SE2& b_T_c) const;
  /// p_a = `a_T_b` · p_b.
  Eigen::Vector2d operator*(const Eigen::Vector2d& p_b) const;

 private:
  Eigen::Vector2d translation_ = Eigen::Vector2d::Zero();
  double theta_ = 0.0;
};

}  // namespace dualgraph
