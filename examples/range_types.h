// SPDX-License-Identifier: MIT
// A user's own vertex and edge types, defined outside the library exactly as the README's "add your own
// edge type" steps describe: a planar point and a range (distance) measurement between two of them.
#pragma once

#include <Eigen/Core>
#include <ostream>

#include "dualgraph/core/edge.h"
#include "dualgraph/core/status.h"
#include "dualgraph/core/type_registry.h"
#include "dualgraph/core/vertex.h"

namespace beacons {

/// A point `p_world` in the plane [m] (tag `VERTEX_POINT2D`): a beacon or a receiver. Tangent
/// [δx; δy] in world axes [m], additive: p ← p + δ. File fields: `x y`.
class VertexPoint2D final : public dualgraph::BaseVertex<2, Eigen::Vector2d> {
 public:
  static constexpr const char* kTag = "VERTEX_POINT2D";

  explicit VertexPoint2D(int id = -1) : BaseVertex(id) { estimate_.setZero(); }

  dualgraph::Status read(dualgraph::TokenReader& in) override;
  void write(std::ostream& out) const override;

 protected:
  void oplusImpl(const Tangent& delta) override { estimate_ += delta; }
};

/// A measured distance r [m] between two VertexPoint2D (tag `EDGE_RANGE2D`), slot 0 `p_i`, slot 1 `p_j`.
/// Residual e = |p_j − p_i| − r (1-D, metres); information Ω = 1/σ² in m⁻². Analytic Jacobians
/// ∓uᵀ with u the unit vector from p_i to p_j. File fields after the two ids: `r information`.
class EdgeRange2D final : public dualgraph::BaseEdge<1, double, VertexPoint2D, VertexPoint2D> {
 public:
  static constexpr const char* kTag = "EDGE_RANGE2D";

  void computeError() override;
  dualgraph::Status read(dualgraph::TokenReader& in, const dualgraph::ParameterContainer& parameters) override;
  void write(std::ostream& out) const override;

 protected:
  void linearizeOplus() override;
};

/// Registers both types under their tags (AlreadyExists when either is registered already).
dualgraph::Status registerRangeTypes(dualgraph::TypeRegistry& registry);

}  // namespace beacons
