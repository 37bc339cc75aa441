// SPDX-License-Identifier: MIT
// Partial gates: a detection with 2–3 corners matched to a map gate by projection, as corner rays.
#pragma once

#include <array>
#include <optional>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/gate_map.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/corner_detection.h"

namespace dualgraph {

/// The frontend/io/FORMATS.md labels of four pixels [px]: `order[i]` is the column shown at label i (top-left,
/// top-right, bottom-right, bottom-left): the two upper ones (smaller v) left to right, then the two lower
/// ones right to left. The simulator labels its detections with it and the frontend its predictions.
std::array<int, 4> cornerLabelOrder(const GateCornerPixels& pixels);

/// The covariance of the undistorted normalised coordinates (x/z, y/z) of a corner seen at `normalized` with
/// pixel noise σ = `pixel_sigma` [px] per coordinate: σ² J⁻¹J⁻ᵀ, J = ∂pixel/∂(x/z, y/z) there (CameraModel's
/// analytic Jacobian). At the image centre ≈ diag(σ/fx, σ/fy)²; towards a fisheye's border several times more.
Eigen::Matrix2d rayCovariance(const CameraModel& camera, const Eigen::Vector2d& normalized, double pixel_sigma);

/// The four corners `pixels` [px] of a gate a PnP solved as rays (count 4) in the gate frame the PnP used
/// (gateCornersInGateFrame(gate_size, kFront): column i is pixel i's corner), each with rayCovariance at
/// `pixel_sigma`, on the camera's mount: what GateObservation::corner_rays carries for a full gate.
/// Errors of the camera's undistortion.
Result<GateCornerRays> solvedCornerRays(const GateCornerPixels& pixels, const CameraModel& camera, double gate_size,
                                        double pixel_sigma);

/// What matching a partial detection needs.
struct PartialGateParams {
  double gate_size = 1.5;      ///< inner side of the map's gates [m]
  double pixel_sigma = 1.0;    ///< corner noise σ [px] (the frontend's current estimate)
  double max_distance = 2.0;   ///< a corner's ray may pass at most this far from its predicted corner [m]
};

/// A partial detection matched to a map gate.
struct PartialGateMatch {
  int gate_id = -1;
  double distance_m = 0.0;      ///< the largest distance between a corner's ray and its predicted corner [m]
  GateCornerRays rays;          ///< the corners seen, in the map gate's frame, and their rays
  Eigen::Isometry3d predicted_body_T_gate = Eigen::Isometry3d::Identity();  ///< at the world_T_body given
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Matches a detection with 2–4 corners seen to the map gate whose corners, projected from `world_T_body` and
/// labelled by cornerLabelOrder, lie closest to the rays of the corners seen with the same labels: every
/// ray within `max_distance` of its predicted corner (measured at the corner's depth), the smallest mean
/// distance wins; `only_gate` restricts the candidates to one id (a detector's trusted id). Gates with a
/// corner behind the camera are not candidates. std::nullopt when no gate qualifies; kInvalidArgument for
/// fewer than 2 corners, errors of the camera's undistortion.
Result<std::optional<PartialGateMatch>> matchPartialGate(const CornerDetection& detection, const CameraModel& camera,
                                                         const GateMap& map, const Eigen::Isometry3d& world_T_body,
                                                         const PartialGateParams& params,
                                                         std::optional<int> only_gate = std::nullopt);

}  // namespace dualgraph
