// SPDX-License-Identifier: MIT
// A sequence's records as the onboard pipeline takes them: detection instants and odometry inputs.
#pragma once

#include <cstddef>
#include <vector>

#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/pipeline/detection_instant.h"
#include "dualgraph/frontend/pipeline/pipeline_report.h"

namespace dualgraph {

/// The sequence's detections as a detector delivers them: one instant per stamp (camera clock), in file order.
std::vector<DetectionInstant> detectionInstants(const Sequence& sequence);
/// Odometry sample `k` (< samples.size()) as a VIO publishes it: with its absolute covariance when the log has
/// them (converted inside the pipeline), else with the relative one it carries.
OdometryInput odometryInput(const Sequence& sequence, size_t k);

}  // namespace dualgraph
