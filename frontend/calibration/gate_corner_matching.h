// SPDX-License-Identifier: MIT
// matchGateCorners: corner detections paired with the map gate corners they show, by reprojection.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/calibration/vio_drift_track.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/corner_detection.h"
#include "dualgraph/frontend/gates/track.h"

namespace dualgraph {

/// One detection paired with a map gate: observed corner `pixels[i]` [px] shows the map corner `p_world[i]`
/// [m, world frame]. `t` is the detection's own stamp (camera clock) [s].
struct GateCornerMatch {
  double t = 0.0;
  int gate_id = -1;
  std::array<Eigen::Vector2d, 4> pixels;
  std::array<Eigen::Vector3d, 4> p_world;
  double rms_px = 0.0;  ///< RMS corner distance at matching [px]
};

/// What matchGateCorners did with the detections (each counted once).
struct GateCornerMatchCounts {
  int detections = 0;
  int partial = 0;           ///< fewer than four corners seen (calibration uses whole gates only)
  int outside_odometry = 0;  ///< t − time_offset outside the odometry's span
  int no_gate_in_view = 0;   ///< no map gate has all four corners in front of the camera
  int too_far = 0;           ///< the nearest projected gate is farther than max_rms_px
  int matched = 0;
};

/// Pairs each corner detection with a map gate and its corners by reprojection: at τ = t − time_offset the
/// camera is track.worldTBody(τ) · body_T_camera; every map gate's four corners
/// (world_T_gate · gateCornersInGateFrame) are projected, and the detection's corners (tl, tr, br, bl as
/// detected) are compared with them under each of the square's eight symmetries (four turns, two sides: a
/// gate seen from behind mirrors its corners), so neither the detector's id nor its corner order is trusted.
/// The gate and symmetry with the least RMS pixel distance win when that RMS is ≤ max_rms_px. In the
/// detections' order; no errors (a detection that cannot be placed is counted).
std::vector<GateCornerMatch> matchGateCorners(const std::vector<CornerDetection>& detections, const Track& map,
                                              const CameraModel& camera, double time_offset, const VioDriftTrack& track,
                                              double max_rms_px, GateCornerMatchCounts* counts = nullptr);

}  // namespace dualgraph
