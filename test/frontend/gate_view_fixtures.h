// SPDX-License-Identifier: MIT
// Shared by the frontend gate tests: the exact, labelled corner detection of a gate seen from a known pose.
#pragma once

#include <array>

#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/corner_detection.h"
#include "dualgraph/frontend/gates/gate_pnp.h"
#include "dualgraph/frontend/gates/partial_gate.h"

namespace dualgraph::testing {

/// The four corners of a `size` m gate at `world_T_gate` as `camera` on a body at `world_T_body` sees them without
/// noise, labelled as frontend/io/FORMATS.md says (cornerLabelOrder), at time `t` [s], no detector id.
inline CornerDetection exactCornerDetection(const CameraModel& camera, const Eigen::Isometry3d& world_T_body,
                                            const Eigen::Isometry3d& world_T_gate, double size, double t) {
  const Eigen::Isometry3d camera_T_gate = (world_T_body * camera.body_T_camera).inverse() * world_T_gate;
  const Eigen::Matrix<double, 3, 4> p_gate = gateCornersInGateFrame(size);
  GateCornerPixels pixels;
  for (int i = 0; i < 4; ++i) pixels.col(i) = camera.project(camera_T_gate * Eigen::Vector3d(p_gate.col(i))).pixel;
  const std::array<int, 4> order = cornerLabelOrder(pixels);
  CornerDetection detection;
  detection.t = t;
  for (size_t i = 0; i < 4; ++i) detection.corners[i] = pixels.col(order[i]);
  return detection;
}

}  // namespace dualgraph::testing
