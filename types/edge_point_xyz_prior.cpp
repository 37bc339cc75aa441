// SPDX-License-Identifier: MIT
#include "dualgraph/types/edge_point_xyz_prior.h"

#include "dualgraph/types/g2o_text.h"

namespace dualgraph {

Status EdgePointXYZPrior::read(TokenReader& in, const ParameterContainer& /*parameters*/) {
  Eigen::Vector3d p_world;
  DG_RETURN_IF_ERROR(in.readDouble(p_world.x(), "mx"));
  DG_RETURN_IF_ERROR(in.readDouble(p_world.y(), "my"));
  DG_RETURN_IF_ERROR(in.readDouble(p_world.z(), "mz"));
  InformationMatrix information;
  DG_RETURN_IF_ERROR(in.readUpperTriangle<3>(information, "information"));
  setMeasurement(p_world);
  information_ = information;
  return Status();
}

void EdgePointXYZPrior::write(std::ostream& out) const {
  writeNumbers(out, measurement_.data(), 3);
  out << ' ';
  writeUpperTriangle<3>(out, information_);
}

}  // namespace dualgraph
