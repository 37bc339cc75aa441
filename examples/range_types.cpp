// SPDX-License-Identifier: MIT
#include "range_types.h"

#include <iomanip>
#include <limits>

namespace beacons {

dualgraph::Status VertexPoint2D::read(dualgraph::TokenReader& in) { return in.readVector<2>(estimate_, "xy"); }

void VertexPoint2D::write(std::ostream& out) const {
  out << std::setprecision(std::numeric_limits<double>::max_digits10) << estimate_.x() << ' ' << estimate_.y();
}

void EdgeRange2D::computeError() {
  error_[0] = (vertexAs<1>()->estimate() - vertexAs<0>()->estimate()).norm() - measurement_;
}

void EdgeRange2D::linearizeOplus() {
  const Eigen::Vector2d d = vertexAs<1>()->estimate() - vertexAs<0>()->estimate();
  const double range = d.norm();
  // Coincident points: the direction is undefined; any unit vector keeps H finite.
  const Eigen::Vector2d u = range > 1e-12 ? Eigen::Vector2d(d / range) : Eigen::Vector2d::UnitX();
  jacobianOplus<0>() = -u.transpose();
  jacobianOplus<1>() = u.transpose();
}

dualgraph::Status EdgeRange2D::read(dualgraph::TokenReader& in, const dualgraph::ParameterContainer&) {
  DG_RETURN_IF_ERROR(in.readDouble(measurement_, "range"));
  return in.readDouble(information_(0, 0), "information");
}

void EdgeRange2D::write(std::ostream& out) const {
  out << std::setprecision(std::numeric_limits<double>::max_digits10) << measurement_ << ' ' << information_(0, 0);
}

dualgraph::Status registerRangeTypes(dualgraph::TypeRegistry& registry) {
  DG_RETURN_IF_ERROR(registry.registerVertex<VertexPoint2D>(VertexPoint2D::kTag));
  return registry.registerEdge<EdgeRange2D>(EdgeRange2D::kTag);
}

}  // namespace beacons
