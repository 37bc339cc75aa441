// SPDX-License-Identifier: MIT
// runSequence: the run loop, a sequence's odometry and detections through the frontend into the Localizer.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/pipeline/pipeline_report.h"

namespace dualgraph {

/// The outputs of one run over a sequence.
struct SequenceRunResult {
  /// world_T_body at every accepted odometry sample as the Localizer returned it at that moment
  /// (causal: what the drone knew then, the newest optimised keyframe composed with the VIO increment),
  /// with its tracking state (initialising samples are no map pose).
  std::vector<CorrectedPose> estimate;
  std::vector<CorrectedPose> keyframes;       ///< the keyframes' final estimates
  std::vector<KeyframeStats> stats;           ///< one row per main-graph optimisation
  LocalizerCounters localizer_counters;
  GateFrontendCounters frontend_counters;
  int detections_before_odometry = 0;         ///< earlier than the first odometry sample: not usable
  int detections_after_odometry = 0;          ///< later than the last odometry sample: not usable
  /// While initialising: given to the frame search alone (PnP), not to the frontend's association or the
  /// Localizer (the frame they need was not known yet).
  int detections_frame_search_only = 0;
  int observations_rejected = 0;              ///< refused by the Localizer (see localizer_counters.last_error)
  /// Checks of the frame in use, started while tracking when detections kept failing beside used ones
  /// (Localizer::frameSuspicious), and how many of them found a clearly better frame and relocalised.
  int frame_checks = 0;
  int frame_checks_replaced = 0;
  /// With `auto_initialize`: how the first search found the VIO's frame (or why not: then no detection was
  /// used and every sample stayed initialising). The Localizer was relocalised at `initialization.world_T_odom`.
  std::optional<FrameInitialization> initialization;
  /// Self-calibration (SequenceRunParams::self_calibration_after_s): what it did, or why not.
  SelfCalibrationReport self_calibration;
  PipelineCounters pipeline_counters;         ///< the pipeline's refusals by reason (the ints above among them)
  double wall_seconds = 0.0;                  ///< whole run
  /// With params.camera_switch: the odometry sample's time [s] at which the run switched to that camera.
  std::optional<double> camera_switched_at;
};

/// Called after every odometry sample with (samples done, samples in total); may be empty.
using RunProgress = std::function<void(size_t done, size_t total)>;

/// Runs the frontend and the Localizer over a sequence in time order, as onboard. For each odometry
/// sample the Localizer would accept, the detections that have arrived by its time stamp come first (those
/// stamped up to it less LocalizerParams::detection_latency: a detector's output reaches the Localizer that
/// late), grouped by instant: each instant goes through the GateFrontend at its corrected pose
/// map_T_odom · odom_T_body(t) (odometry interpolated between the accepted samples around t,
/// `odometryPoseAt`) and its observations go to the Localizer, which holds them until the sample arrives; then
/// the sample itself. So a sample that closes a keyframe interval finds that interval's detections collected
/// (none is refused as too late: with a latency, the keyframe waits as long). The instants still on their
/// way when the odometry ends are handed over before `finish`. `finish` at the end. Errors only for invalid parameters or a sequence without
/// odometry; bad samples and detections are counted. With `params.auto_initialize` (outside mapping mode) the
/// Localizer starts initialising: each instant goes to a FrameInitializer instead (PnP alone) until it locks,
/// then the Localizer is given the frame (`relocalize`) and tracks; when it never locks the run uses no
/// detection and says why in `initialization`. Whenever the Localizer turns lost (its TrackingMonitor, fed the
/// frontend's unmatched detections), a new search starts with the estimate as its coarse start pose
/// (params.relocalization) and relocalises it on lock, unless gates fit again first.
Result<SequenceRunResult> runSequence(const Sequence& sequence, const SequenceRunParams& params,
                                      const RunProgress& progress = {});

/// The camera-to-VIO clock offset a run uses [s]: params.time_offset when set, else the sequence camera's
/// CameraModel::time_offset, else 0. Every detection stamped t is used at t − this.
double detectionTimeOffset(const Sequence& sequence, const SequenceRunParams& params);

/// The same loop with a Localizer and a GateFrontend the caller made and keeps (to read the main graph
/// afterwards, as the benchmarks do); `localizer` gets `finish`. runSequence is this after creating both.
/// The detections are moved by the sequence camera's time_offset.
Result<SequenceRunResult> runSequenceWith(Localizer& localizer, GateFrontend& frontend, const Sequence& sequence,
                                          const RunProgress& progress = {});

}  // namespace dualgraph
