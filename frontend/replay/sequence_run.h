// SPDX-License-Identifier: MIT
// runSequence: a sequence folder replayed through the onboard pipeline (StreamingLocalizer), as `dualgraph run` does.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/pipeline/detection_instant.h"
#include "dualgraph/frontend/pipeline/pipeline_report.h"
#include "dualgraph/frontend/pipeline/sequence_input.h"
#include "dualgraph/frontend/pipeline/streaming_localizer.h"

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
  OdometryScaleReport odometry_scale;         ///< the VIO's scale, estimated and applied (SequenceRunParams::odometry_scale)
  PipelineCounters pipeline_counters;         ///< the pipeline's refusals by reason (the ints above among them)
  double wall_seconds = 0.0;                  ///< whole run
  /// With params.camera_switch: the odometry sample's time [s] at which the run switched to that camera.
  std::optional<double> camera_switched_at;
};

/// Called after every odometry sample with (samples done, samples in total); may be empty.
using RunProgress = std::function<void(size_t done, size_t total)>;

/// Replays a sequence through the onboard pipeline (StreamingLocalizer, caller-thread mode: deterministic), as the
/// sensors would deliver it: before each odometry sample, the detection instants that have arrived by its time
/// (within max_detection_lead_s), then the sample with its absolute covariance when the log has them. Everything
/// the pipeline does is the drone's: detections handed over detection_latency late at the corrected pose, the frame
/// search while initialising, loss, relocalisation, frame checks, self-calibration at t_c, odometry gaps
/// (frontend/pipeline/README.md). Errors only for invalid parameters or a sequence without odometry; bad samples and
/// detections are counted (SequenceRunResult, PipelineCounters).
Result<SequenceRunResult> runSequence(const Sequence& sequence, const SequenceRunParams& params,
                                      const RunProgress& progress = {});

/// A run's result from what the pipeline gave (as runSequence assembles it, for a caller feeding a
/// StreamingLocalizer itself, e.g. `dualgraph live`): `estimate` the pose of every accepted odometry sample in order,
/// `finished` StreamingLocalizer::finish's results, `never_given` detections that came after the odometry ended
/// (counted as after it), `wall_seconds` the run's wall time [s].
SequenceRunResult sequenceRunResult(std::vector<CorrectedPose> estimate, PipelineResults finished, int never_given,
                                    double wall_seconds);

/// The camera-to-VIO clock offset a run uses [s]: params.time_offset when set, else the sequence camera's
/// CameraModel::time_offset, else 0. Every detection stamped t is used at t − this.
double detectionTimeOffset(const Sequence& sequence, const SequenceRunParams& params);

/// The same replay around a Localizer and a GateFrontend the caller made and keeps (to read the main graph
/// afterwards, as the benchmarks do; StreamingLocalizer::borrow): no frame search (the Localizer's frame is used),
/// no self-calibration; `localizer` gets `finish`. The detections are moved by the sequence camera's time_offset.
Result<SequenceRunResult> runSequenceWith(Localizer& localizer, GateFrontend& frontend, const Sequence& sequence,
                                          const RunProgress& progress = {});

}  // namespace dualgraph
