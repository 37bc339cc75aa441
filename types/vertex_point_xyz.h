// SPDX-License-Identifier: MIT
// VertexPointXYZ (VERTEX_TRACKXYZ): a 3-D point (e.g. a landmark) in metres, additive increment.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "dualgraph/core/vertex.h"

namespace dualgraph {

/// A 3-D point `p_world` in metres (g2o tag `VERTEX_TRACKXYZ`, g2o's VertexPointXYZ), e.g. a
/// landmark. Tangent: [δx δy δz] in world axes, additive: p ← p + δ. File fields: `x y z`.
class VertexPointXYZ final : public BaseVertex<3, Eigen::Vector3d> {
 public:
  static constexpr const char* kTag = "VERTEX_TRACKXYZ";

  explicit VertexPointXYZ(int id = -1) : BaseVertex(id) { estimate_.setZero(); }

  Status read(TokenReader& in) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<VertexBase> clone() const override { return std::make_unique<VertexPointXYZ>(*this); }

 protected:
  void oplusImpl(const Tangent& delta) override { estimate_ += delta; }
};

}  // namespace dualgraph
