// SPDX-License-Identifier: MIT
#include "dualgraph/types/se2.h"

#include <cmath>

namespace dualgraph {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double normalizeAngle(double angle) {
  if (angle > -kPi && angle <= kPi) return angle;
  // std::remainder is exact and lands in [−π, π]; move the lower end to the upper one.
  double wrapped = std::remainder(angle, 2.0 * kPi);
  if (wrapped <= -kPi) wrapped += 2.0 * kPi;
  return wrapped;
}

Eigen::Matrix2d SE2::rotation() const {
  const double c = std::cos(theta_);
  const double s = std::sin(theta_);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

SE2 SE2::inverse() const {
  SE2 b_T_a;
  b_T_a.theta_ = normalizeAngle(-theta_);
  b_T_a.translation_ = -(b_T_a.rotation() * translation_);
  return b_T_a;
}

SE2 SE2::operator*(const SE2& b_T_c) const {
  SE2 a_T_c;
  a_T_c.translation_ = translation_ + rotation() * b_T_c.translation_;
  a_T_c.theta_ = normalizeAngle(theta_ + b_T_c.theta_);
  return a_T_c;
}

Eigen::Vector2d SE2::operator*(const Eigen::Vector2d& p_b) const { return translation_ + rotation() * p_b; }

}  // namespace dualgraph
