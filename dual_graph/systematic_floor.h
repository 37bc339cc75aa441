// SPDX-License-Identifier: MIT
// The systematic-error floor added to a distilled gate edge's covariance: what averaging cannot remove.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {

/// The part of a gate measurement's error shared by every detection of that gate between two keyframes
/// (the PnP range bias of far gates, the corner detector's systematic offsets): a distilled edge averages
/// many detections, so its marginal covariance shrinks as 1/N while this part does not. Added to the
/// distilled covariance, in metres and radians, scaled by the range r = |p_node| from the keyframe to the gate:
/// σ_along = range_fraction · r along the line of sight, σ_across = lateral_fraction · r across it,
/// σ_rot = rotation_rad about each gate axis. All zero (the default): no floor. Plain values; thread-safe.
struct SystematicFloor {
  double range_fraction = 0.0;    ///< σ along the line of sight per metre of range [-]
  double lateral_fraction = 0.0;  ///< σ across the line of sight per metre of range [-]
  double rotation_rad = 0.0;      ///< σ of the gate's orientation [rad]

  bool active() const { return range_fraction > 0.0 || lateral_fraction > 0.0 || rotation_rad > 0.0; }
};

/// The floor's translation covariance [m²] for a gate at `p_node` (its centre in the keyframe's axes, m),
/// expressed in the axes `axes_R_node` rotates the keyframe's into (identity: the keyframe's own axes).
Eigen::Matrix3d floorTranslationCovariance(const SystematicFloor& floor, const Eigen::Vector3d& p_node,
                                           const Eigen::Matrix3d& axes_R_node);

/// Adds the floor to a distilled pose covariance in g2o units ([t; q.vec], right perturbation of
/// node_T_gate: translation in the gate's axes, rotation as half-angles).
void addFloorToPoseCovariance(const SystematicFloor& floor, const Eigen::Isometry3d& node_T_gate, Matrix6d& covariance);

}  // namespace dualgraph
