// SPDX-License-Identifier: MIT
#include "frontend/sequence_run.h"

#include <chrono>
#include <optional>

#include "dual_graph/odometry_history.h"

namespace dualgraph {
namespace {

/// The sequence's detections (corners or poses) in time order, handed out one instant at a time, their stamps
/// moved to the odometry's clock (t − time_offset, CameraModel::time_offset).
class DetectionFeed {
 public:
  DetectionFeed(const Sequence& sequence, double time_offset)
      : sequence_(sequence),
        size_(sequence.has_corners ? sequence.corners.size() : sequence.pose_detections.size()),
        time_offset_(time_offset) {}

  bool done() const { return next_ >= size_; }
  size_t remaining() const { return size_ - next_; }
  /// Time of the next detection on the odometry's clock (not done()).
  double nextTime() const { return stampAt(next_) - time_offset_; }
  /// Skips the next instant's detections; returns how many.
  size_t skipInstant() {
    const size_t begin = next_;
    next_ = instantEnd();
    return next_ - begin;
  }
  /// The next instant's detections through PnP alone (pose detections as they are), detector ids kept.
  Result<std::vector<GateObservation>> solveInstant(const GateFrontend& frontend) {
    if (sequence_.has_corners) return frontend.solveCorners(nextCorners());
    return nextPoses();
  }
  /// The next instant's detections through the frontend at `world_T_body`.
  Result<std::vector<GateObservation>> processInstant(GateFrontend& frontend, const Eigen::Isometry3d& world_T_body) {
    if (sequence_.has_corners) return frontend.processCorners(nextCorners(), world_T_body);
    return frontend.processPoses(nextPoses(), world_T_body);
  }

 private:
  double stampAt(size_t i) const { return sequence_.has_corners ? sequence_.corners[i].t : sequence_.pose_detections[i].t; }
  size_t instantEnd() const {
    size_t end = next_ + 1;
    while (end < size_ && stampAt(end) == stampAt(next_)) ++end;
    return end;
  }
  /// The next instant's corner detections (has_corners), on the odometry's clock; advances.
  std::vector<CornerDetection> nextCorners() {
    const size_t begin = next_;
    next_ = instantEnd();
    std::vector<CornerDetection> instant(sequence_.corners.begin() + static_cast<long>(begin),
                                         sequence_.corners.begin() + static_cast<long>(next_));
    for (CornerDetection& detection : instant) detection.t -= time_offset_;
    return instant;
  }
  /// The next instant's pose detections, likewise.
  std::vector<GateObservation> nextPoses() {
    const size_t begin = next_;
    next_ = instantEnd();
    std::vector<GateObservation> instant(sequence_.pose_detections.begin() + static_cast<long>(begin),
                                         sequence_.pose_detections.begin() + static_cast<long>(next_));
    for (GateObservation& detection : instant) detection.t -= time_offset_;
    return instant;
  }

  const Sequence& sequence_;
  const size_t size_;
  const double time_offset_;
  size_t next_ = 0;
};

/// Hands every instant up to `until` [s] to the frontend and its observations to the Localizer, the pose of
/// an instant interpolated between `before` and `after` (instants older than `before` cannot be placed:
/// counted as rejected). `withhold`: the instants are passed over instead (the VIO's frame is unknown).
Status handDetectionsUpTo(double until, const OdometrySample& before, const OdometrySample& after, DetectionFeed& feed,
                          GateFrontend& frontend, Localizer& localizer, bool withhold, SequenceRunResult& result) {
  while (!feed.done() && feed.nextTime() <= until) {
    const double t = feed.nextTime();
    if (withhold) {
      feed.skipInstant();
      continue;
    }
    if (t < before.t) {
      result.observations_rejected += static_cast<int>(feed.skipInstant());
      continue;
    }
    const Eigen::Isometry3d world_T_body = localizer.mapTOdom() * interpolateOdometry(before, after, t);
    Result<std::vector<GateObservation>> observations = feed.processInstant(frontend, world_T_body);
    if (!observations.ok()) return observations.status();
    for (const GateObservation& observation : *observations) {
      if (!localizer.addObservation(observation).ok()) ++result.observations_rejected;
    }
  }
  return Status();
}

/// runSequenceWith's loop; `withhold`: no detection reaches the frontend (those outside the odometry's span
/// are still counted as such).
Result<SequenceRunResult> runLoop(Localizer& localizer, GateFrontend& frontend, const Sequence& sequence,
                                  const RunProgress& progress, bool withhold, double time_offset) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<OdometrySample>& samples = sequence.odometry.samples;
  if (samples.empty()) return Status(StatusCode::kInvalidArgument, sequence.dir + ": no odometry samples");
  SequenceRunResult result;
  DetectionFeed feed(sequence, time_offset);
  while (!feed.done() && feed.nextTime() < samples.front().t) {
    result.detections_before_odometry += static_cast<int>(feed.skipInstant());
  }
  std::optional<OdometrySample> newest;  // the newest sample the Localizer accepted
  for (size_t k = 0; k < samples.size(); ++k) {
    const OdometrySample& sample = samples[k];
    // The detections this sample covers go first: if it closes a keyframe interval, they are in it.
    if (newest && localizer.checkOdometry(sample).ok()) {
      DG_RETURN_IF_ERROR(handDetectionsUpTo(sample.t, *newest, sample, feed, frontend, localizer, withhold, result));
    }
    Result<CorrectedPose> corrected = localizer.addOdometry(sample);
    if (corrected.ok()) {
      result.estimate.push_back(*corrected);
      if (!newest) {  // the first accepted sample: the detections at its own instant (earlier ones cannot be placed)
        DG_RETURN_IF_ERROR(handDetectionsUpTo(sample.t, sample, sample, feed, frontend, localizer, withhold, result));
      }
      newest = sample;
    }
    if (progress) progress(k + 1, samples.size());
  }
  result.detections_after_odometry = static_cast<int>(feed.remaining());
  DG_RETURN_IF_ERROR(localizer.finish());
  result.keyframes = localizer.keyframeTrajectory();
  result.stats = localizer.keyframeStats();
  result.localizer_counters = localizer.counters();
  result.frontend_counters = frontend.counters();
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace

double detectionTimeOffset(const Sequence& sequence, const SequenceRunParams& params) {
  if (params.time_offset) return *params.time_offset;
  return sequence.camera ? sequence.camera->time_offset : 0.0;
}

FrameInitialization findOdometryFrame(const Sequence& sequence, const SequenceRunParams& params,
                                      const GateFrontend& frontend) {
  FrameInitializerParams search = params.initialization;
  if (params.localizer.initial_world_T_body) {
    search.start_world_T_body = params.localizer.initial_world_T_body;
    search.start_sigma_t = params.localizer.initial_sigma_t;
    search.start_sigma_r = params.localizer.initial_sigma_r;
  }
  FrameInitializer initializer(search, frontend.map());
  const std::vector<OdometrySample>& samples = sequence.odometry.samples;
  if (samples.empty()) return initializer.state();
  initializer.setStartOdometry(samples.front().odom_T_body);
  DetectionFeed feed(sequence, detectionTimeOffset(sequence, params));
  size_t placed = 0, skipped = 0;
  while (!feed.done() && !initializer.state().locked) {
    const double t = feed.nextTime();
    Result<Eigen::Isometry3d> odom_T_body = odometryPoseAt(samples, t);
    if (!odom_T_body.ok()) {
      skipped += feed.skipInstant();
      continue;
    }
    Result<std::vector<GateObservation>> observations = feed.solveInstant(frontend);
    if (!observations.ok()) continue;
    placed += observations->size();
    initializer.add(t, *odom_T_body, *observations);
  }
  FrameInitialization found = initializer.state();
  if (!found.locked && placed == 0) {
    found.why_not = "none of the detections could be used: " + std::to_string(skipped) +
                    " outside the odometry's time span, the others refused by PnP";
  }
  return found;
}

Result<SequenceRunResult> runSequence(const Sequence& sequence, const SequenceRunParams& params,
                                      const RunProgress& progress) {
  if (sequence.odometry.samples.empty()) return Status(StatusCode::kInvalidArgument, sequence.dir + ": no odometry samples");
  auto known_map = sequence.map.gateMap();
  if (!known_map.ok()) return Status(known_map.status().code(), sequence.dir + ": " + known_map.status().message());
  GateFrontendParams frontend_params = params.frontend;
  frontend_params.mapping = params.localizer.mapping;
  auto frontend = GateFrontend::create(frontend_params, sequence.map, sequence.camera);
  if (!frontend.ok()) return frontend.status();
  LocalizerParams localizer_params = params.localizer;
  std::optional<FrameInitialization> initialization;
  if (params.auto_initialize && !params.localizer.mapping) {
    initialization = findOdometryFrame(sequence, params, *frontend);
    if (initialization->locked) localizer_params.initial_world_T_odom = initialization->world_T_odom;
  }
  auto localizer = Localizer::create(localizer_params, params.localizer.mapping ? GateMap{} : *known_map);
  if (!localizer.ok()) return localizer.status();
  // No frame, no detection: associating them in a wrong frame would give a plausible wrong answer.
  const bool withhold = initialization && !initialization->locked;
  Result<SequenceRunResult> result = runLoop(**localizer, *frontend, sequence, progress, withhold, detectionTimeOffset(sequence, params));
  if (result.ok()) result->initialization = initialization;
  return result;
}

Result<SequenceRunResult> runSequenceWith(Localizer& localizer, GateFrontend& frontend, const Sequence& sequence,
                                          const RunProgress& progress) {
  const double time_offset = sequence.camera ? sequence.camera->time_offset : 0.0;
  return runLoop(localizer, frontend, sequence, progress, false, time_offset);
}

}  // namespace dualgraph
