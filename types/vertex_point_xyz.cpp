// SPDX-License-Identifier: MIT
#include "dualgraph/types/vertex_point_xyz.h"

#include "dualgraph/types/g2o_text.h"

namespace dualgraph {

Status VertexPointXYZ::read(TokenReader& in) {
  Eigen::Vector3d p_world;
  DG_RETURN_IF_ERROR(in.readDouble(p_world.x(), "x"));
  DG_RETURN_IF_ERROR(in.readDouble(p_world.y(), "y"));
  DG_RETURN_IF_ERROR(in.readDouble(p_world.z(), "z"));
  estimate_ = p_world;
  return Status();
}

void VertexPointXYZ::write(std::ostream& out) const { writeNumbers(out, estimate_.data(), 3); }

}  // namespace dualgraph
