// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/sequence_input.h"

namespace dualgraph {

std::vector<DetectionInstant> detectionInstants(const Sequence& sequence) {
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

OdometryInput odometryInput(const Sequence& sequence, size_t k) {
  const OdometrySample& sample = sequence.odometry.samples[k];
  OdometryInput input;
  input.t = sample.t;
  input.odom_T_body = sample.odom_T_body;
  if (sequence.odometry.absolute_covariances.size() == sequence.odometry.samples.size()) {
    input.absolute_covariance = sequence.odometry.absolute_covariances[k];
  } else {
    input.relative_covariance = sample.relative_covariance;
  }
  return input;
}

}  // namespace dualgraph
