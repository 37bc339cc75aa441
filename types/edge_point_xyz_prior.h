// SPDX-License-Identifier: MIT
// EdgePointXYZPrior (EDGE_POINTXYZ_PRIOR): an absolute position prior on a 3-D point.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "dualgraph/core/edge.h"
#include "dualgraph/types/vertex_point_xyz.h"

namespace dualgraph {

/// Absolute position prior on one VertexPointXYZ `p_world` (g2o tag `EDGE_POINTXYZ_PRIOR`,
/// g2o's EdgeXYZPrior). Measurement m = expected `p_world` in metres. Residual: e = p_world − m.
/// Information Ω (3×3) in m⁻², world axes. File fields after the id: `mx my mz` + 6
/// upper-triangular Ω entries. Jacobian: the identity.
class EdgePointXYZPrior final : public BaseEdge<3, Eigen::Vector3d, VertexPointXYZ> {
 public:
  static constexpr const char* kTag = "EDGE_POINTXYZ_PRIOR";

  EdgePointXYZPrior() { measurement_.setZero(); }

  void computeError() override { error_ = vertexAs<0>()->estimate() - measurement_; }
  Status read(TokenReader& in, const ParameterContainer& parameters) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<EdgeBase> clone() const override { return std::make_unique<EdgePointXYZPrior>(*this); }

 protected:
  void linearizeOplus() override { jacobianOplus<0>().setIdentity(); }
};

}  // namespace dualgraph
