// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/replay/sequence_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>

#include "dualgraph/frontend/pipeline/streaming_localizer.h"

namespace dualgraph {
namespace {

/// Feeds a sequence through `pipeline` as the sensors would deliver it: before each odometry sample, the detection
/// instants that have arrived by its time (stamped, on the odometry clock, no later than the sample + half of
/// max_detection_lead_s and within that lead of the newest sample), each batch closed by an empty instant that says
/// the detector is done up to there (an on-time detector: keyframes close at once, not detection_latency later), then
/// the sample (with its absolute covariance when the log has them, converted inside the pipeline). What is left at
/// the end goes in before `finish`.
Result<SequenceRunResult> replay(StreamingLocalizer& pipeline, const Sequence& sequence, const RunProgress& progress,
                                 double lead_s) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<OdometrySample>& samples = sequence.odometry.samples;
  if (samples.empty()) return Status(StatusCode::kInvalidArgument, sequence.dir + ": no odometry samples");
  const std::vector<DetectionInstant> instants = detectionInstants(sequence);
  size_t next = 0;
  const auto feedUpTo = [&](double until) {  // instants with (stamp − offset) ≤ until
    for (; next < instants.size() && instants[next].t - pipeline.timeOffset() <= until; ++next) {
      (void)pipeline.addDetections(instants[next]);  // a refusal is counted by the pipeline
    }
    // The recording has the detector's images with gates only: the rest, up to `until`, held none (an on-time
    // detector says so with an empty instant per image; keyframes need not wait detection_latency for it).
    DetectionInstant done;
    done.t = until + pipeline.timeOffset();
    if (next == instants.size() || done.t < instants[next].t) (void)pipeline.addDetections(done);
  };
  SequenceRunResult result;
  const double margin = 0.5 * lead_s;
  for (size_t k = 0; k < samples.size(); ++k) {
    // Within the lead over the newest sample the pipeline took (after a gap, the rest arrives after this sample).
    const double newest = pipeline.snapshot().t;
    feedUpTo(std::isfinite(newest) ? std::min(samples[k].t + margin, newest + lead_s) : samples[k].t + margin);
    Result<PoseUpdate> update = pipeline.addOdometry(odometryInput(sequence, k));
    if (update.ok()) result.estimate.push_back(update->pose);
    if (progress) progress(k + 1, samples.size());
  }
  feedUpTo(samples.back().t + margin);
  size_t never_given = 0;  // beyond the lead: after the odometry's end
  for (; next < instants.size(); ++next) never_given += instants[next].size();
  Result<PipelineResults> finished = pipeline.finish();
  if (!finished.ok()) return finished.status();
  return sequenceRunResult(std::move(result.estimate), std::move(finished).value(), static_cast<int>(never_given),
                           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace

SequenceRunResult sequenceRunResult(std::vector<CorrectedPose> estimate, PipelineResults finished, int never_given,
                                    double wall_seconds) {
  SequenceRunResult result;
  const PipelineCounters& c = finished.pipeline_counters;
  result.estimate = std::move(estimate);
  result.keyframes = std::move(finished.keyframes);
  result.stats = std::move(finished.stats);
  result.localizer_counters = finished.localizer_counters;
  result.frontend_counters = finished.frontend_counters;
  result.pipeline_counters = c;
  result.pipeline_counters.detections_after_odometry += never_given;
  result.detections_before_odometry = c.detections_before_odometry;
  result.detections_after_odometry = c.detections_after_odometry + never_given;
  result.detections_frame_search_only = c.detections_frame_search_only;
  result.observations_rejected = c.observations_rejected + c.detections_unplaced;
  result.frame_checks = c.frame_checks;
  result.frame_checks_replaced = c.frame_checks_replaced;
  result.initialization = finished.initialization;
  result.camera_switched_at = finished.camera_switched_at;
  result.self_calibration = finished.self_calibration;
  result.odometry_scale = finished.odometry_scale;
  result.wall_seconds = wall_seconds;
  return result;
}

double detectionTimeOffset(const Sequence& sequence, const SequenceRunParams& params) {
  if (params.time_offset) return *params.time_offset;
  return sequence.camera ? sequence.camera->time_offset : 0.0;
}

Result<SequenceRunResult> runSequence(const Sequence& sequence, const SequenceRunParams& params,
                                      const RunProgress& progress) {
  if (sequence.odometry.samples.empty()) return Status(StatusCode::kInvalidArgument, sequence.dir + ": no odometry samples");
  if (params.camera_switch && !sequence.has_corners) {
    return Status(StatusCode::kInvalidArgument, sequence.dir + ": a camera switch needs corner detections and a camera");
  }
  auto pipeline = StreamingLocalizer::create(params, sequence.map, sequence.camera);
  if (!pipeline.ok()) return Status(pipeline.status().code(), sequence.dir + ": " + pipeline.status().message());
  return replay(**pipeline, sequence, progress, params.max_detection_lead_s);
}

Result<SequenceRunResult> runSequenceWith(Localizer& localizer, GateFrontend& frontend, const Sequence& sequence,
                                          const RunProgress& progress) {
  auto pipeline = StreamingLocalizer::borrow(localizer, frontend, detectionTimeOffset(sequence, SequenceRunParams{}));
  if (!pipeline.ok()) return pipeline.status();
  return replay(**pipeline, sequence, progress, SequenceRunParams{}.max_detection_lead_s);
}

}  // namespace dualgraph
