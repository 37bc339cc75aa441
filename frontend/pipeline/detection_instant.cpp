// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/detection_instant.h"

#include <cmath>
#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph {
namespace {

bool finiteCorner(const Eigen::Vector2d& corner) {
  return (std::isfinite(corner.x()) && std::isfinite(corner.y())) || (std::isnan(corner.x()) && std::isnan(corner.y()));
}

}  // namespace

Status validateDetectionInstant(const DetectionInstant& instant) {
  const std::string what = "detection instant at t=" + formatTimestamp(instant.t);
  if (!std::isfinite(instant.t)) return Status(StatusCode::kInvalidArgument, what + ": time is not finite");
  if (!instant.corners.empty() && !instant.poses.empty()) {
    return Status(StatusCode::kInvalidArgument, what + ": corners and poses in one instant (one detector each)");
  }
  for (const CornerDetection& detection : instant.corners) {
    if (detection.t != instant.t) return Status(StatusCode::kInvalidArgument, what + ": a detection stamped otherwise");
    for (const Eigen::Vector2d& corner : detection.corners) {
      if (!finiteCorner(corner)) {
        return Status(StatusCode::kInvalidArgument, what + ": a corner of gate " + std::to_string(detection.gate_id) +
                                                        " is infinite or half NaN (an unseen corner is NaN, NaN)");
      }
    }
  }
  for (const GateObservation& detection : instant.poses) {
    if (detection.t != instant.t) return Status(StatusCode::kInvalidArgument, what + ": a detection stamped otherwise");
    const Status valid = validateGateObservation(detection);
    if (!valid.ok()) return Status(valid.code(), what + ": " + valid.message());
  }
  return Status();
}

}  // namespace dualgraph
