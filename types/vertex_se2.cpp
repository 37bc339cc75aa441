// SPDX-License-Identifier: MIT
#include "dualgraph/types/vertex_se2.h"

#include "dualgraph/types/g2o_text.h"

namespace dualgraph {

Status VertexSE2::read(TokenReader& in) {
  double x = 0.0, y = 0.0, theta = 0.0;
  DG_RETURN_IF_ERROR(in.readDouble(x, "x"));
  DG_RETURN_IF_ERROR(in.readDouble(y, "y"));
  DG_RETURN_IF_ERROR(in.readDouble(theta, "theta"));
  estimate_ = SE2(x, y, theta);
  return Status();
}

void VertexSE2::write(std::ostream& out) const {
  const Eigen::Vector3d v = estimate_.toVector();
  writeNumbers(out, v.data(), 3);
}

void VertexSE2::oplusImpl(const Tangent& delta) {
  estimate_ = SE2(estimate_.x() + delta.x(), estimate_.y() + delta.y(), estimate_.angle() + delta.z());
}

}  // namespace dualgraph
