// SPDX-License-Identifier: MIT
// The sequence replay's own input helpers (frontend/replay/sequence_run.h), named for the streaming tests.
#pragma once

#include <algorithm>
#include <vector>

#include "dualgraph/frontend/pipeline/streaming_localizer.h"
#include "dualgraph/frontend/replay/sequence_run.h"

namespace dualgraph::flighttest {

using ::dualgraph::detectionInstants;
using ::dualgraph::odometryInput;

/// The detector's output per image as a real one gives it: the sequence's detection instants and, for the images
/// without gates, an empty instant ("done up to t") at each odometry time + `shift` [s, to the camera clock], in time
/// order (a real instant before an empty one at the same stamp).
inline std::vector<DetectionInstant> withDoneMarks(const Sequence& sequence, double shift) {
  std::vector<DetectionInstant> instants = detectionInstants(sequence);
  for (const OdometrySample& sample : sequence.odometry.samples) {
    instants.emplace_back();
    instants.back().t = sample.t + shift;
  }
  std::stable_sort(instants.begin(), instants.end(),
                   [](const DetectionInstant& a, const DetectionInstant& b) { return a.t < b.t; });
  return instants;
}

}  // namespace dualgraph::flighttest
