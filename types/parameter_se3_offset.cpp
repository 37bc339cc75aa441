// SPDX-License-Identifier: MIT
#include "dualgraph/types/parameter_se3_offset.h"

#include <string>

namespace dualgraph {

Status ParameterSE3Offset::read(TokenReader& in) {
  Eigen::Isometry3d body_T_sensor;
  DG_RETURN_IF_ERROR(text_.read(in, body_T_sensor));
  body_T_sensor_ = body_T_sensor;
  return Status();
}

void ParameterSE3Offset::write(std::ostream& out) const { text_.write(out, body_T_sensor_); }

Status lookUpSE3Offset(const ParameterContainer& parameters, int parameter_id, const TokenReader& in,
                       Eigen::Isometry3d& body_T_sensor) {
  const ParameterBase* parameter = parameters.find(parameter_id);
  if (parameter == nullptr) {
    return in.error("unknown parameter id " + std::to_string(parameter_id) +
                    " (field 'parameter id'; declare it with a " + ParameterSE3Offset::kTag +
                    " line before the edge)");
  }
  const auto* offset = dynamic_cast<const ParameterSE3Offset*>(parameter);
  if (offset == nullptr) {
    return in.error("parameter id " + std::to_string(parameter_id) + " is not a " +
                    ParameterSE3Offset::kTag);
  }
  body_T_sensor = offset->offset();
  return Status();
}

}  // namespace dualgraph
