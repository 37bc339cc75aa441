// SPDX-License-Identifier: MIT
#pragma once

#include <functional>
#include <vector>

#include "core/status.h"
#include "dual_graph/localizer.h"
#include "dual_graph/localizer_params.h"
#include "frontend/gate_frontend.h"
#include "frontend/sequence_reader.h"

namespace dualgraph {

/// Everything `dualgraph run` configures.
struct SequenceRunParams {
  LocalizerParams localizer;
  GateFrontendParams frontend;
  double pose_detection_sigma_t = 0.1;   ///< covariance of detections.csv rows without one: σ [m]
  double pose_detection_sigma_r = 0.05;  ///< and [rad] (diagonal, metric [t; θ])

  /// The diagonal covariance from the two sigmas above.
  Matrix6d defaultPoseDetectionCovariance() const;
};

/// The outputs of one run over a sequence.
struct SequenceRunResult {
  /// world_T_body at every accepted odometry sample as the Localizer returned it at that moment
  /// (causal: what the drone knew then, the newest optimised keyframe composed with the VIO increment).
  std::vector<CorrectedPose> estimate;
  std::vector<CorrectedPose> keyframes;       ///< the keyframes' final estimates
  std::vector<KeyframeStats> stats;           ///< one row per main-graph optimisation
  LocalizerCounters localizer_counters;
  GateFrontendCounters frontend_counters;
  int detections_before_odometry = 0;         ///< earlier than the first odometry sample: not usable
  int detections_after_odometry = 0;          ///< later than the last odometry sample: not usable
  int observations_rejected = 0;              ///< refused by the Localizer (see localizer_counters.last_error)
  double wall_seconds = 0.0;                  ///< whole run
};

/// Called after every odometry sample with (samples done, samples in total); may be empty.
using RunProgress = std::function<void(size_t done, size_t total)>;

/// Runs the frontend and the Localizer over a sequence in time order, as onboard: each odometry
/// sample is added; then every detection with a time stamp up to that sample's, grouped by instant,
/// goes through the GateFrontend at the corrected pose of its instant (map_T_odom · odom_T_body(t),
/// odometry interpolated) and its observations to the Localizer; `finish` at the end. Errors only for
/// invalid parameters or a sequence without odometry; bad samples and detections are counted.
Result<SequenceRunResult> runSequence(const Sequence& sequence, const SequenceRunParams& params,
                                      const RunProgress& progress = {});

}  // namespace dualgraph
