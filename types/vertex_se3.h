// SPDX-License-Identifier: MIT
// VertexSE3 (VERTEX_SE3:QUAT): a 3-D pose with g2o's right [δt; δq] increment.
#pragma once

#include <memory>

#include <Eigen/Geometry>

#include "dualgraph/core/vertex.h"
#include "dualgraph/types/g2o_text.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

/// A 3-D pose `world_T_body` (g2o tag `VERTEX_SE3:QUAT`): maps points from the body frame to the
/// world frame. Tangent: g2o's 6-vector [δt; δq] (δq ≈ δθ/2, see se3_math.h), applied on the
/// right: x ← x · g2oIncrement(δ), so δt is in metres along the body axes.
/// File fields: `x y z qx qy qz qw` (Hamilton quaternion). As in g2o the quaternion is used as
/// written when it is within 1e-3 of unit norm (keeps χ² equal to g2o's), normalised otherwise;
/// a zero-norm quaternion is an error. The rotation is re-orthonormalised every 1000 increments.
class VertexSE3 final : public BaseVertex<6, Eigen::Isometry3d> {
 public:
  static constexpr const char* kTag = "VERTEX_SE3:QUAT";
  /// Increments between two re-orthonormalisations of the rotation block.
  static constexpr int kOrthonormaliseEvery = 1000;

  explicit VertexSE3(int id = -1) : BaseVertex(id) { estimate_.setIdentity(); }

  /// Sets the estimate and restarts the count towards the next re-orthonormalisation, leaving the vertex
  /// as a new one with that estimate would be (for vertices reused between graphs).
  void reset(const Eigen::Isometry3d& world_T_body) {
    estimate_ = world_T_body;
    increments_since_orthonormalise_ = 0;
  }

  Status read(TokenReader& in) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<VertexBase> clone() const override { return std::make_unique<VertexSE3>(*this); }

 protected:
  void oplusImpl(const Tangent& delta) override;

 private:
  int increments_since_orthonormalise_ = 0;
  G2oPoseText text_{QuaternionReading::kAsWrittenNearUnit};
};

}  // namespace dualgraph
