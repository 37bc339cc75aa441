// SPDX-License-Identifier: MIT
// DetectionInstant: the gate detections of one image (corners) or one detector output (poses), as they arrive.
#pragma once

#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/frontend/gates/corner_detection.h"

namespace dualgraph {

/// The detections of one instant: either corner detections of one image (a camera is needed) or gate pose
/// detections (body_T_gate with covariance). Every detection carries the instant's stamp `t` [s]. Given to the
/// pipeline on the camera's clock; the pipeline moves it to the odometry's clock (t − CameraModel::time_offset)
/// when it hands the instant over. A plain value: no thread-safety of its own.
struct DetectionInstant {
  double t = 0.0;                            ///< [s]
  std::vector<CornerDetection> corners;      ///< a corner detector's output
  std::vector<GateObservation> poses;        ///< a pose detector's output
  size_t size() const { return corners.size() + poses.size(); }
  /// A copy with every stamp moved by −offset [s].
  DetectionInstant shifted(double offset) const {
    DetectionInstant moved = *this;
    moved.t -= offset;
    for (CornerDetection& detection : moved.corners) detection.t -= offset;
    for (GateObservation& detection : moved.poses) detection.t -= offset;
    return moved;
  }
};

/// The checks of an instant that need no pipeline state, made once where it enters (StreamingLocalizer, PipelineCore):
/// finite values (an unseen corner is NaN, NaN), one detector per instant, every detection at the instant's stamp,
/// valid pose detections. kInvalidArgument naming what is wrong.
Status validateDetectionInstant(const DetectionInstant& instant);

}  // namespace dualgraph
