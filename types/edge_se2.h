// SPDX-License-Identifier: MIT
// EdgeSE2 (EDGE_SE2): the relative planar pose between two VertexSE2, g2o's error, analytic Jacobians.
#pragma once

#include <memory>

#include "dualgraph/core/edge.h"
#include "dualgraph/types/se2.h"
#include "dualgraph/types/vertex_se2.h"

namespace dualgraph {

/// Relative planar pose between two VertexSE2 (g2o tag `EDGE_SE2`): slot 0 `world_T_i`, slot 1
/// `world_T_j`, measurement Z = `i_T_j`. Residual (g2o's): e = [x; y; θ] of
/// Z⁻¹ · (world_T_i⁻¹ · world_T_j) with θ wrapped into (−π, π].
/// Information Ω (3×3, [x y θ] order) in m⁻² and rad⁻² (the angle error is in radians, unlike
/// the θ/2 of EDGE_SE3:QUAT). File fields after the ids: `dx dy dtheta` + 6 upper-triangular Ω
/// entries. Analytic Jacobians.
class EdgeSE2 final : public BaseEdge<3, SE2, VertexSE2, VertexSE2> {
 public:
  static constexpr const char* kTag = "EDGE_SE2";

  /// Stores Z = `i_T_j` and caches Z⁻¹.
  void setMeasurement(const SE2& i_T_j) override;
  const SE2& inverseMeasurement() const { return j_T_i_measured_; }

  void computeError() override;
  Status read(TokenReader& in, const ParameterContainer& parameters) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<EdgeBase> clone() const override { return std::make_unique<EdgeSE2>(*this); }

 protected:
  void linearizeOplus() override;

 private:
  SE2 j_T_i_measured_;
};

}  // namespace dualgraph
