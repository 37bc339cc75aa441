// SPDX-License-Identifier: MIT
// VertexSE2 (VERTEX_SE2): a planar pose, g2o's additive increment with the angle wrapped.
#pragma once

#include <memory>

#include "dualgraph/core/vertex.h"
#include "dualgraph/types/se2.h"

namespace dualgraph {

/// A planar pose `world_T_body` (g2o tag `VERTEX_SE2`). Tangent [δx; δy; δθ] (metres in world
/// axes, radians), additive as in g2o: (x, y, θ) ← (x + δx, y + δy, wrap(θ + δθ)), θ ∈ (−π, π].
/// File fields: `x y theta`.
class VertexSE2 final : public BaseVertex<3, SE2> {
 public:
  static constexpr const char* kTag = "VERTEX_SE2";

  explicit VertexSE2(int id = -1) : BaseVertex(id) {}

  Status read(TokenReader& in) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<VertexBase> clone() const override { return std::make_unique<VertexSE2>(*this); }

 protected:
  void oplusImpl(const Tangent& delta) override;
};

}  // namespace dualgraph
