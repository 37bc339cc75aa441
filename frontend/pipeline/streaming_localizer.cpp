// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/streaming_localizer.h"

#include <algorithm>
#include <limits>

#include "dualgraph/core/stamp_tolerance.h"

namespace dualgraph {
namespace {

/// `part`'s counts added to `total` (a core finished at a clock restart); its last error kept when it has one.
void addCounts(PipelineCounters& total, const PipelineCounters& part) {
  forEachPipelineCount([&](const char*, int PipelineCounters::*field) { total.*field += part.*field; });
  if (!part.last_error.empty()) total.last_error = part.last_error;
}

}  // namespace

StreamingLocalizer::StreamingLocalizer(std::unique_ptr<PipelineCore> core, PipelineThreading threading,
                                       size_t max_queued_inputs)
    : core_(std::move(core)),
      threading_(threading),
      max_queued_inputs_(max_queued_inputs),
      clock_guard_(core_->params().max_odometry_jump_s),
      motion_guard_(core_->params().max_odometry_speed_mps, core_->params().max_odometry_turn_rate_radps) {
  snapshot_.map_T_odom = core_->localizer().mapTOdom();
  snapshot_.state = core_->localizer().trackingState();
  initial_snapshot_ = snapshot_;
  if (threading_ == PipelineThreading::kWorker) worker_ = std::thread([this] { workerLoop(); });
}

StreamingLocalizer::~StreamingLocalizer() {
  if (worker_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      stopping_ = true;
      queue_.clear();  // destroyed without finish: what was queued is dropped
    }
    queue_ready_.notify_one();
    worker_.join();
  }
}

Result<std::unique_ptr<StreamingLocalizer>> StreamingLocalizer::create(const SequenceRunParams& params,
                                                                       const Track& map,
                                                                       std::optional<CameraModel> camera,
                                                                       PipelineThreading threading,
                                                                       size_t max_queued_inputs) {
  if (max_queued_inputs == 0) return Status(StatusCode::kInvalidArgument, "pipeline: max_queued_inputs must be > 0");
  auto core = PipelineCore::create(params, map, camera);
  if (!core.ok()) return core.status();
  std::unique_ptr<StreamingLocalizer> pipeline(
      new StreamingLocalizer(std::move(core).value(), threading, max_queued_inputs));
  pipeline->origin_ = Origin{map, std::move(camera)};
  return pipeline;
}

Result<std::unique_ptr<StreamingLocalizer>> StreamingLocalizer::borrow(Localizer& localizer, GateFrontend& frontend,
                                                                       double time_offset) {
  auto core = PipelineCore::borrow(localizer, frontend, time_offset);
  if (!core.ok()) return core.status();
  return std::unique_ptr<StreamingLocalizer>(
      new StreamingLocalizer(std::move(core).value(), PipelineThreading::kCallerThread, kDefaultMaxQueuedInputs));
}

void StreamingLocalizer::publish(const PoseUpdate& update) {
  const Localizer& localizer = core_->localizer();
  PipelineSnapshot next;
  next.t = update.pose.t;
  next.map_T_odom = localizer.mapTOdom();
  next.world_T_body = update.pose.world_T_body;
  next.state = update.pose.state;
  next.covariance = update.pose.covariance;
  next.updates = static_cast<long>(localizer.keyframeStats().size());
  const std::optional<double> held_from = localizer.oldestOdometryTime();
  if (held_from) next.placeable_from_t = *held_from + core_->timeOffset();
  next.detections_too_late = static_cast<long>(carried_.detections_unplaced) + core_->counters().detections_unplaced +
                             detections_late_on_submit_.load();
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  if (core_generation_ < announced_generation_) {  // the worker's flight before a restart already announced
    ++snapshot_.samples;
    return;
  }
  next.samples = snapshot_.samples + 1;
  next.last_gate_update_t = snapshot_.last_gate_update_t;
  for (const KeyframeStats& done : update.report.updates) {
    if (done.gate_edges_added > 0) next.last_gate_update_t = std::max(next.last_gate_update_t, done.t);
  }
  snapshot_ = next;
  if (threading_ == PipelineThreading::kWorker) last_report_ = update.report;
}

void StreamingLocalizer::announceRestart() {
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  ++announced_generation_;
  const long samples = snapshot_.samples;
  snapshot_ = initial_snapshot_;
  snapshot_.samples = samples;
  last_report_ = UpdateReport{};
}

void StreamingLocalizer::countRefused() {
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  ++snapshot_.samples;
}

void StreamingLocalizer::countMalformedOdometry() {
  ++invalid_on_submit_;
  countRefused();
}

void StreamingLocalizer::countMalformedDetections(int detections) {
  if (detections > 0) detections_invalid_on_submit_ += detections;
}

PipelineSnapshot StreamingLocalizer::snapshot() const {
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  return snapshot_;
}

Status StreamingLocalizer::addDetections(const DetectionInstant& instant) {
  if (threading_ == PipelineThreading::kCallerThread) {
    std::lock_guard<std::mutex> lock(work_mutex_);
    return core_->addDetections(instant);
  }
  const Status valid = validateDetectionInstant(instant);  // an empty one too: it marks the detector done up to t
  if (!valid.ok()) {  // counted as the core counts it in caller-thread mode
    detections_invalid_on_submit_ += static_cast<int>(instant.size());
    return valid;
  }
  double placeable_from_t = -std::numeric_limits<double>::infinity();
  {
    std::lock_guard<std::mutex> lock(snapshot_mutex_);
    placeable_from_t = snapshot_.placeable_from_t;
  }
  if (instant.size() > 0 && clearlyBefore(instant.t, placeable_from_t)) {
    detections_late_on_submit_ += static_cast<int>(instant.size());
    return Status(StatusCode::kFailedPrecondition,
                  "detection instant at t=" + formatTimestamp(instant.t) + " (camera clock) arrived after the odometry " +
                      "at its time was used (placeable from t=" + formatTimestamp(placeable_from_t) +
                      "): localizer.detection_latency must cover the detector's delay");
  }
  Event event;
  event.detections = instant;
  bool full = false;
  const Status queued = enqueue(std::move(event), "detection instant", full);
  if (full) detections_queue_full_on_submit_ += static_cast<int>(instant.size());
  return queued;
}

Status StreamingLocalizer::enqueue(Event event, const char* what, bool& full) {
  full = false;
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (stopping_) return Status(StatusCode::kFailedPrecondition, std::string("pipeline: ") + what + " after finish");
    if (queue_.size() >= max_queued_inputs_) {
      full = true;
      return Status(StatusCode::kFailedPrecondition, "pipeline: the worker is " + std::to_string(queue_.size()) +
                                                         " inputs behind; " + what + " refused");
    }
    queue_.push_back(std::move(event));
  }
  queue_ready_.notify_one();
  return Status();
}

Result<PoseUpdate> StreamingLocalizer::addOdometry(const OdometryInput& input) {
  // What needs no pipeline state first (both modes), so an invalid sample never counts towards a new clock.
  const Status valid = validateOdometryInput(input);
  if (!valid.ok()) {
    ++invalid_on_submit_;
    countRefused();
    return valid;
  }
  const ClockCheck clock = clock_guard_.check(input.t);
  if (clock == ClockCheck::kHeld || (clock == ClockCheck::kRestart && !origin_)) {
    countRefused();
    if (clock == ClockCheck::kHeld) return clock_guard_.heldStatus();
    ++refused_on_submit_;  // not after the newest accepted sample, as the core would have said
    return Status(StatusCode::kFailedPrecondition,
                  "odometry sample at t=" + formatTimestamp(input.t) + ": the odometry clock went back and stayed " +
                      "there, and a pipeline around a borrowed Localizer cannot restart");
  }
  // A pose jump on the accepted clock (a new clock's first sample is a first sample: its pose may be anywhere).
  if (clock == ClockCheck::kOn && motion_guard_.check(input.t, input.odom_T_body) == MotionCheck::kHeld) {
    countRefused();
    return motion_guard_.heldStatus();
  }
  const bool restart = clock == ClockCheck::kRestart;
  if (threading_ == PipelineThreading::kCallerThread) {
    Result<PoseUpdate> update = [&]() -> Result<PoseUpdate> {
      std::lock_guard<std::mutex> lock(work_mutex_);
      if (restart) {
        DG_RETURN_IF_ERROR(restartCore());
        announceRestart();
      }
      Result<PoseUpdate> done = core_->addOdometry(input);
      if (done.ok()) done->report.clock_restarted = restart;
      return done;
    }();
    if (update.ok()) {
      accepted(input, clock);
      publish(*update);
    } else {
      countRefused();
    }
    return update;
  }
  // Worker mode: refused here what the core would refuse without its state, so the caller hears of it.
  if (restart) last_submitted_t_ = -std::numeric_limits<double>::infinity();
  if (!(input.t > last_submitted_t_)) {
    ++refused_on_submit_;
    countRefused();
    return Status(StatusCode::kInvalidArgument, "odometry sample at t=" + formatTimestamp(input.t) +
                                                    " is not after the previous one at t=" + formatTimestamp(last_submitted_t_));
  }
  Event event;
  event.restart = restart;
  event.odometry = input;
  bool full = false;
  const Status queued = enqueue(std::move(event), "odometry sample", full);
  if (!queued.ok()) {
    if (full) {
      ++odometry_queue_full_;
      countRefused();
    }
    return queued;
  }
  if (restart) announceRestart();  // once queued (a full queue refuses the sample; the guard then starts again)
  last_submitted_t_ = input.t;
  accepted(input, clock);
  PoseUpdate update;
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  update.pose = CorrectedPose{input.t, snapshot_.map_T_odom * input.odom_T_body, snapshot_.state, std::nullopt};
  update.report = last_report_;
  update.report.clock_restarted = restart;  // this sample's, not the worker's last
  return update;
}

void StreamingLocalizer::accepted(const OdometryInput& input, ClockCheck clock) {
  clock_guard_.accepted(input.t);
  if (clock != ClockCheck::kOn) motion_guard_.reset();  // a new clock: its first sample starts the motion again
  motion_guard_.accepted(input.t, input.odom_T_body);
}

void StreamingLocalizer::workerLoop() {
  for (;;) {
    std::deque<Event, Eigen::aligned_allocator<Event>> batch;
    {
      std::unique_lock<std::mutex> lock(queue_mutex_);
      queue_ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty() && stopping_) return;
      batch.swap(queue_);
    }
    for (const Event& event : batch) {
      if (event.odometry) {
        Result<PoseUpdate> update = [&]() -> Result<PoseUpdate> {
          if (event.restart) DG_RETURN_IF_ERROR(restartCore());
          Result<PoseUpdate> done = core_->addOdometry(*event.odometry);  // refusals are counted by the core
          if (done.ok()) done->report.clock_restarted = false;  // told to the caller when it submitted the sample
          return done;
        }();
        if (update.ok()) {
          publish(*update);
        } else {
          countRefused();
        }
      } else {
        (void)core_->addDetections(event.detections);  // likewise
      }
    }
  }
}

Status StreamingLocalizer::restartCore() {
  // The camera in use carries over: a self-calibrated clock offset and mount belong to the sensors, not to the VIO's
  // clock (a looped bag, a restarted VIO). Its offset is then the camera's own, and a switch already made is done.
  SequenceRunParams params = core_->params();
  // Made in place from the camera it copies (copy-initialising the optional draws GCC 12's false
  // -Wmaybe-uninitialized on CameraModel's fields).
  std::optional<CameraModel> camera;
  if (core_->cameraSwitchedAt() && core_->frontend().camera()) {
    camera.emplace(*core_->frontend().camera());
    camera->time_offset = core_->timeOffset();
    params.time_offset.reset();
    params.camera_switch.reset();
  } else if (origin_->camera) {
    camera.emplace(*origin_->camera);
  }
  auto fresh = PipelineCore::create(params, origin_->map, std::move(camera));
  if (!fresh.ok()) return fresh.status();  // made once with the same inputs: not expected
  (void)core_->finish();  // its waiting detections counted; fails only when it never took a sample
  addCounts(carried_, core_->counters());
  ++carried_.odometry_clock_restarts;
  carried_odometry_rejected_ += core_->localizer().counters().odometry_rejected + core_->odometryRefusedBeforeLocalizer();
  core_ = std::move(fresh).value();
  ++core_generation_;
  return Status();
}

Result<PipelineResults> StreamingLocalizer::finish() {
  if (finished_) return Status(StatusCode::kFailedPrecondition, "pipeline: finish called twice");
  finished_ = true;
  if (worker_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      stopping_ = true;  // the worker drains what is queued, then stops
    }
    queue_ready_.notify_one();
    worker_.join();
  }
  std::lock_guard<std::mutex> lock(work_mutex_);
  DG_RETURN_IF_ERROR(core_->finish());
  const Localizer& localizer = core_->localizer();
  PipelineResults results;
  results.keyframes = localizer.keyframeTrajectory();
  results.stats = localizer.keyframeStats();
  results.localizer_counters = localizer.counters();
  results.frontend_counters = core_->frontend().counters();
  results.pipeline_counters = carried_;
  addCounts(results.pipeline_counters, core_->counters());  // the newest core's last error wins
  results.pipeline_counters.odometry_invalid += invalid_on_submit_;
  results.pipeline_counters.odometry_not_after_previous += refused_on_submit_;
  results.pipeline_counters.detections_invalid += detections_invalid_on_submit_.load();
  results.pipeline_counters.detections_queue_full += detections_queue_full_on_submit_.load();
  results.pipeline_counters.detections_unplaced += detections_late_on_submit_.load();
  results.pipeline_counters.odometry_queue_full += odometry_queue_full_;
  results.pipeline_counters.odometry_held_at_clock_jump = clock_guard_.held();
  results.pipeline_counters.odometry_clock_jumps = clock_guard_.jumps();
  results.pipeline_counters.odometry_held_at_pose_jump = motion_guard_.held();
  results.pipeline_counters.odometry_pose_jumps = motion_guard_.jumps();
  // Every sample the pipeline did not take, as in both modes: refused on submission, held at a clock or pose jump, or refused
  // by the core before the Localizer saw it.
  results.localizer_counters.odometry_rejected += invalid_on_submit_ + refused_on_submit_ + odometry_queue_full_ +
                                                  clock_guard_.held() + motion_guard_.held() +
                                                  core_->odometryRefusedBeforeLocalizer() + carried_odometry_rejected_;
  results.initialization = core_->initialization();
  results.camera_switched_at = core_->cameraSwitchedAt();
  results.self_calibration = core_->selfCalibration();
  results.odometry_scale = core_->odometryScale().report();
  {
    std::lock_guard<std::mutex> snapshot_lock(snapshot_mutex_);
    snapshot_.detections_too_late = results.pipeline_counters.detections_unplaced;  // the final count
  }
  return results;
}

}  // namespace dualgraph
