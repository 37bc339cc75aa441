// SPDX-License-Identifier: MIT
// EdgeSE3 (EDGE_SE3:QUAT): the relative pose between two VertexSE3, g2o's error, analytic Jacobians.
#pragma once

#include <memory>

#include <Eigen/Geometry>

#include "dualgraph/core/edge.h"
#include "dualgraph/types/g2o_text.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {

/// Relative pose between two VertexSE3 (g2o tag `EDGE_SE3:QUAT`), e.g. odometry or a loop
/// closure. Vertices: slot 0 `world_T_i`, slot 1 `world_T_j`; measurement Z = `i_T_j`.
/// Residual (g2o's, exactly): e = g2oChart(Z⁻¹ · world_T_i⁻¹ · world_T_j) = [t; q.vec] of the
/// error pose with the quaternion's sign chosen so that w ≥ 0, order [t; q.vec].
/// Information Ω (6×6, [t; q.vec] order) is in g2o units: m⁻² for t and (q.vec)⁻² ≈ 4 rad⁻²
/// for the rotation; convert a metric [t; θ] information with informationMetricToG2o().
/// File fields after the ids: `x y z qx qy qz qw` (quaternion normalised on read, as g2o does)
/// and the 21 upper-triangular entries of Ω. Analytic Jacobians in closed form from the error
/// (computeError keeps the error pose's rotation and quaternion w for them).
class EdgeSE3 final : public BaseEdge<6, Eigen::Isometry3d, VertexSE3, VertexSE3> {
 public:
  static constexpr const char* kTag = "EDGE_SE3:QUAT";

  EdgeSE3() { setMeasurement(Eigen::Isometry3d::Identity()); }

  /// Stores Z = `i_T_j` and caches Z⁻¹.
  void setMeasurement(const Eigen::Isometry3d& i_T_j) override;
  const Eigen::Isometry3d& inverseMeasurement() const { return j_T_i_measured_; }

  void computeError() override;
  void prefetch() const override;
  Status read(TokenReader& in, const ParameterContainer& parameters) override;
  void write(std::ostream& out) const override;
  std::unique_ptr<EdgeBase> clone() const override { return std::make_unique<EdgeSE3>(*this); }

 protected:
  void linearizeOplus() override;

 private:
  Eigen::Isometry3d j_T_i_measured_ = Eigen::Isometry3d::Identity();
  /// Of the error pose E = Z⁻¹ · world_T_i⁻¹ · world_T_j at the last computeError: its rotation
  /// block and the w (≥ 0) of its unit quaternion, whose vector part is error_.tail<3>().
  Eigen::Matrix3d error_rotation_ = Eigen::Matrix3d::Identity();
  double error_w_ = 1.0;
  G2oPoseText text_{QuaternionReading::kNormalise};
};

}  // namespace dualgraph
