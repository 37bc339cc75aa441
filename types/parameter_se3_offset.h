// SPDX-License-Identifier: MIT
// ParameterSE3Offset (PARAMS_SE3OFFSET): a fixed sensor offset body_T_sensor, and its lookup.
#pragma once

#include <memory>

#include <Eigen/Geometry>

#include "dualgraph/core/parameter.h"
#include "dualgraph/types/g2o_text.h"

namespace dualgraph {

/// A fixed sensor offset `body_T_sensor` (g2o tag `PARAMS_SE3OFFSET`), shared by the edges that
/// name its id (EDGE_SE3_PRIOR, EDGE_SE3_TRACKXYZ): it maps points from the sensor frame to the
/// body frame of the VertexSE3 the edge is attached to. Not optimised, so it has no tangent space.
/// File fields after the id: `x y z qx qy qz qw` (quaternion normalised on read, as g2o does).
class ParameterSE3Offset final : public ParameterBase {
 public:
  static constexpr const char* kTag = "PARAMS_SE3OFFSET";

  explicit ParameterSE3Offset(int id = -1, const Eigen::Isometry3d& body_T_sensor = Eigen::Isometry3d::Identity())
      : ParameterBase(id), body_T_sensor_(body_T_sensor) {}

  const Eigen::Isometry3d& offset() const { return body_T_sensor_; }
  void setOffset(const Eigen::Isometry3d& body_T_sensor) { body_T_sensor_ = body_T_sensor; }

  Status read(TokenReader& in) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<ParameterBase> clone() const override { return std::make_unique<ParameterSE3Offset>(*this); }

 private:
  Eigen::Isometry3d body_T_sensor_;
  G2oPoseText text_{QuaternionReading::kNormalise};
};

/// The offset of the PARAMS_SE3OFFSET with id `parameter_id` in `parameters`; a ParseError from
/// `in` naming the id when it is missing or of another type. Used by the edges' read().
Status lookUpSE3Offset(const ParameterContainer& parameters, int parameter_id, const TokenReader& in,
                       Eigen::Isometry3d& body_T_sensor);

}  // namespace dualgraph
