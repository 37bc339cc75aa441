// SPDX-License-Identifier: MIT
// Test helper: a gate's four corner pixels as a camera sees it (the PnP tests' noise-free input).
#pragma once

#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/gate_pnp.h"

namespace dualgraph::testing {

/// The corner pixels (tl, tr, br, bl) of a gate of side `size` [m] at camera_T_gate, seen from `side`; false if a
/// corner does not project (behind the camera, outside the image).
inline bool projectCorners(const CameraModel& camera, const Eigen::Isometry3d& camera_T_gate, GateSide side,
                           GateCornerPixels& pixels, double size = 1.5) {
  const Eigen::Matrix<double, 3, 4> corners = gateCornersInGateFrame(size, side);
  for (int i = 0; i < 4; ++i) {
    const Projection projection = camera.project(camera_T_gate * Eigen::Vector3d(corners.col(i)));
    if (!projection.valid()) return false;
    pixels.col(i) = projection.pixel;
  }
  return true;
}

}  // namespace dualgraph::testing
