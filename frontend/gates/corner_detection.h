// SPDX-License-Identifier: MIT
// The gate vocabulary of the image side: a gate's four corner pixels and one detection of them.
#pragma once

#include <Eigen/Core>
#include <array>

namespace dualgraph {

/// The four inner corners of a gate as they appear in the image [px], columns in the order of
/// DESIGN.md §6: top-left, top-right, bottom-right, bottom-left (a clockwise cycle in the image).
using GateCornerPixels = Eigen::Matrix<double, 2, 4>;

/// One gate seen in one image at time `t` [s]: the pixel coordinates [px] of its four inner corners
/// as they appear in the image (DESIGN.md §6): top-left, top-right, bottom-right, bottom-left — a
/// clockwise cycle with v pointing down. `gate_id` is the map id, or -1 when unknown (the association
/// decides). `line` is the 1-based line of the file it came from, for later messages.
struct CornerDetection {
  double t = 0.0;
  int gate_id = -1;
  std::array<Eigen::Vector2d, 4> corners;
  int line = 0;
};

}  // namespace dualgraph
