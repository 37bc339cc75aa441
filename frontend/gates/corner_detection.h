// SPDX-License-Identifier: MIT
// The gate vocabulary of the image side: a gate's four corner pixels and one detection of them.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>

namespace dualgraph {

/// The four inner corners of a gate as they appear in the image [px], columns in the order of
/// frontend/io/FORMATS.md: top-left, top-right, bottom-right, bottom-left (a clockwise cycle in the image).
using GateCornerPixels = Eigen::Matrix<double, 2, 4>;

/// The mean length [px] of a gate's four sides in the image (the cycle above): how large it appears, which
/// decides whether its PnP fit is nearly linear (PixelNoiseEstimator).
inline double meanSidePx(const GateCornerPixels& pixels) {
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) sum += (pixels.col(i) - pixels.col((i + 1) % 4)).norm();
  return sum / 4.0;
}

/// One gate seen in one image at time `t` [s]: the pixel coordinates [px] of its four inner corners
/// as they appear in the image (frontend/io/FORMATS.md): top-left, top-right, bottom-right, bottom-left — a
/// clockwise cycle with v pointing down. `gate_id` is the map id, or -1 when unknown (the association
/// decides). `line` is the 1-based line of the file it came from, for later messages.
/// A gate partly out of the image is a partial detection: the corners the detector did not see hold NaN
/// (both coordinates; written `nan` in the CSV), the others keep their positions in the order above.
struct CornerDetection {
  double t = 0.0;
  int gate_id = -1;
  std::array<Eigen::Vector2d, 4> corners;
  int line = 0;

  /// Whether corner c (0 … 3, the order above) was detected.
  bool visible(int c) const { return std::isfinite(corners[static_cast<size_t>(c)].x()); }
  /// How many of the four corners were detected (4: a whole gate).
  int visibleCount() const {
    int count = 0;
    for (int c = 0; c < 4; ++c) count += visible(c) ? 1 : 0;
    return count;
  }
  bool complete() const { return visibleCount() == 4; }
};

}  // namespace dualgraph
