// SPDX-License-Identifier: MIT
// Types defined outside the library, the way a user adds their own: a 2-D point, a relative
// displacement edge with analytic Jacobians, a range edge relying on the numeric fallback, and a
// prior. Used by the core tests, which depend on core only.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <iomanip>
#include <ostream>

#include "dualgraph/core/edge.h"
#include "dualgraph/core/vertex.h"

namespace dualgraph::testing {

/// A point in the plane (metres); tangent = the point itself, additive increment.
class VertexPoint2 : public BaseVertex<2, Eigen::Vector2d> {
 public:
  using BaseVertex::BaseVertex;
  Status read(TokenReader& in) override { return in.readVector<2>(estimate_, "xy"); }
  void write(std::ostream& out) const override {
    out << std::setprecision(17) << estimate_.x() << ' ' << estimate_.y();
  }

 protected:
  void oplusImpl(const Tangent& delta) override { estimate_ += delta; }
};

/// e = (p_j − p_i) − z (metres); Ω in m⁻². Analytic Jacobians −I and I.
class EdgePoint2Relative : public BaseEdge<2, Eigen::Vector2d, VertexPoint2, VertexPoint2> {
 public:
  void computeError() override { error_ = vertexAs<1>()->estimate() - vertexAs<0>()->estimate() - measurement_; }
  Status read(TokenReader& in, const ParameterContainer&) override {
    DG_RETURN_IF_ERROR(in.readVector<2>(measurement_, "measurement"));
    return in.readUpperTriangle<2>(information_, "information");
  }
  void write(std::ostream& out) const override {
    out << std::setprecision(17) << measurement_.x() << ' ' << measurement_.y() << ' ' << information_(0, 0)
        << ' ' << information_(0, 1) << ' ' << information_(1, 1);
  }

 protected:
  void linearizeOplus() override {
    jacobianOplus<0>() = -Eigen::Matrix2d::Identity();
    jacobianOplus<1>() = Eigen::Matrix2d::Identity();
  }
};

/// e = |p_j − p_i| − z (metres), 1-D; no analytic Jacobians (central differences).
class EdgePoint2Range : public BaseEdge<1, double, VertexPoint2, VertexPoint2> {
 public:
  void computeError() override {
    error_[0] = (vertexAs<1>()->estimate() - vertexAs<0>()->estimate()).norm() - measurement_;
  }
  Status read(TokenReader& in, const ParameterContainer&) override {
    DG_RETURN_IF_ERROR(in.readDouble(measurement_, "range"));
    return in.readDouble(information_(0, 0), "information");
  }
  void write(std::ostream& out) const override {
    out << std::setprecision(17) << measurement_ << ' ' << information_(0, 0);
  }
};

/// e = p − z (metres), unary.
class EdgePoint2Prior : public BaseEdge<2, Eigen::Vector2d, VertexPoint2> {
 public:
  void computeError() override { error_ = vertexAs<0>()->estimate() - measurement_; }
  Status read(TokenReader& in, const ParameterContainer&) override {
    DG_RETURN_IF_ERROR(in.readVector<2>(measurement_, "measurement"));
    return in.readUpperTriangle<2>(information_, "information");
  }
  void write(std::ostream& out) const override {
    out << std::setprecision(17) << measurement_.x() << ' ' << measurement_.y() << ' ' << information_(0, 0)
        << ' ' << information_(0, 1) << ' ' << information_(1, 1);
  }

 protected:
  void linearizeOplus() override { jacobianOplus<0>().setIdentity(); }
};

}  // namespace dualgraph::testing
