// SPDX-License-Identifier: MIT
// A sequence's detections as the instants a detector would deliver, and the odometry as a VIO would.
#pragma once

#include <vector>

#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/pipeline/streaming_localizer.h"

namespace dualgraph::flighttest {

/// The sequence's detections grouped by stamp (camera clock), in time order.
inline std::vector<DetectionInstant> detectionInstants(const Sequence& sequence) {
  std::vector<DetectionInstant> instants;
  const size_t count = sequence.has_corners ? sequence.corners.size() : sequence.pose_detections.size();
  for (size_t i = 0; i < count; ++i) {
    const double t = sequence.has_corners ? sequence.corners[i].t : sequence.pose_detections[i].t;
    if (instants.empty() || instants.back().t != t) {
      instants.emplace_back();
      instants.back().t = t;
    }
    if (sequence.has_corners) {
      instants.back().corners.push_back(sequence.corners[i]);
    } else {
      instants.back().poses.push_back(sequence.pose_detections[i]);
    }
  }
  return instants;
}

/// Odometry sample `k` as a VIO publishes it (with its absolute covariance when the log has them).
inline OdometryInput odometryInput(const Sequence& sequence, size_t k) {
  OdometryInput input;
  input.t = sequence.odometry.samples[k].t;
  input.odom_T_body = sequence.odometry.samples[k].odom_T_body;
  if (sequence.odometry.absolute_covariances.size() == sequence.odometry.samples.size()) {
    input.absolute_covariance = sequence.odometry.absolute_covariances[k];
  }
  return input;
}

}  // namespace dualgraph::flighttest
