// SPDX-License-Identifier: MIT
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {

Status VertexSE3::read(TokenReader& in) {
  Eigen::Isometry3d world_T_body;
  DG_RETURN_IF_ERROR(text_.read(in, world_T_body));
  estimate_ = world_T_body;
  return Status();
}

void VertexSE3::write(std::ostream& out) const { text_.write(out, estimate_); }

void VertexSE3::oplusImpl(const Tangent& delta) {
  estimate_ = estimate_ * g2oIncrement(delta);
  // Products of many rotations drift away from SO(3) by round-off; g2o corrects them
  // periodically with the same first-order projection.
  if (++increments_since_orthonormalise_ >= kOrthonormaliseEvery) {
    increments_since_orthonormalise_ = 0;
    Eigen::Matrix3d rotation = estimate_.linear();
    approximateNearestRotation(rotation);
    estimate_.linear() = rotation;
  }
}

}  // namespace dualgraph
