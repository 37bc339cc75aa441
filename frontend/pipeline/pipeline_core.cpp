// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/pipeline_core.h"


#include <algorithm>
#include <cmath>
#include <string>

#include "dualgraph/core/stamp_tolerance.h"
#include "dualgraph/core/wall_clock.h"

namespace dualgraph {
namespace {

/// Instants waiting for the odometry that covers them (a detector ahead of a stalled VIO fills it).
constexpr size_t kMaxWaitingInstants = 4096;

/// An instant through PnP (pose detections as they are), the noise learning from it.
Result<SolvedDetections> solveInstant(GateFrontend& frontend, const DetectionInstant& instant,
                                      const Eigen::Isometry3d& odom_T_body) {
  if (instant.corners.empty()) return GateFrontend::fromPoses(instant.poses);
  const Eigen::Matrix3d odom_R_body = odom_T_body.linear();
  return frontend.solve(instant.corners, true, &odom_R_body);
}

}  // namespace

PipelineCore::PipelineCore(const SequenceRunParams& params, GateMap map)
    : params_(params), map_(std::move(map)), odometry_scale_(params.odometry_scale) {}

Result<std::unique_ptr<PipelineCore>> PipelineCore::create(const SequenceRunParams& params, const Track& map,
                                                           std::optional<CameraModel> camera) {
  if (params.camera_switch) {
    if (!camera) return Status(StatusCode::kInvalidArgument, "a camera switch needs a camera to switch from");
    const Status switched = params.camera_switch->camera.validate();
    if (!switched.ok()) return Status(switched.code(), "the camera switched to: " + switched.message());
  }
  DG_RETURN_IF_ERROR(validatePipelineLimits(params));
  auto known_map = map.gateMap();
  if (!known_map.ok()) return known_map.status();
  GateFrontendParams frontend_params = params.frontend;
  frontend_params.mapping = params.localizer.mapping;
  // Corner rays are used by the dual graph's temporary graph with SE(3) gates only; elsewhere partial gates are
  // counted and full gates go as PnP poses (mapping too: its new gates are placed from poses).
  if (params.localizer.mode != LocalizerMode::kDual || params.localizer.landmark != LandmarkModel::kPose) {
    frontend_params.partial_gates = false;
    frontend_params.full_gate_rays = false;
  }
  if (params.localizer.mapping) frontend_params.full_gate_rays = false;
  const double time_offset = params.time_offset ? *params.time_offset : (camera ? camera->time_offset : 0.0);
  auto frontend = GateFrontend::create(frontend_params, map, std::move(camera));
  if (!frontend.ok()) return frontend.status();
  const bool find_frame = params.auto_initialize && !params.localizer.mapping;
  auto localizer = Localizer::create(params.localizer, params.localizer.mapping ? GateMap{} : *known_map,
                                     find_frame ? TrackingState::kInitialising : TrackingState::kTracking);
  if (!localizer.ok()) return localizer.status();
  std::unique_ptr<PipelineCore> core(new PipelineCore(params, std::move(known_map).value()));
  core->owned_localizer_ = std::move(localizer).value();
  core->localizer_ = core->owned_localizer_.get();
  core->owned_frontend_.emplace(std::move(frontend).value());
  core->frontend_ = &*core->owned_frontend_;
  core->time_offset_ = time_offset;
  core->track_ = map;
  if (!params.localizer.mapping) core->search_.emplace(core->params_, core->map_);
  const char* why_off = !(params.self_calibration_after_s > 0.0) ? "off (frontend.self_calibration_after_s: 0)"
                        : params.localizer.mapping ? "not in mapping mode (no map to calibrate against)"
                        : !core->frontend_->camera() ? "needs corner detections and a camera (no camera given)"
                                                     : "";
  core->self_calibrator_.emplace(params.self_calibration_after_s, params.self_calibration_budget_s, time_offset, why_off);
  return core;
}

Result<std::unique_ptr<PipelineCore>> PipelineCore::borrow(Localizer& localizer, GateFrontend& frontend,
                                                           double time_offset) {
  SequenceRunParams params;
  params.localizer = localizer.params();
  params.auto_initialize = false;
  params.odometry_scale.enabled = false;  // the Localizer's odometry as its owner feeds it
  std::unique_ptr<PipelineCore> core(new PipelineCore(params, frontend.map()));
  core->localizer_ = &localizer;
  core->frontend_ = &frontend;
  core->time_offset_ = time_offset;
  return core;
}

const std::optional<FrameInitialization>& PipelineCore::initialization() const {
  static const std::optional<FrameInitialization> none;
  return search_ ? search_->initialization() : none;
}

void PipelineCore::refuse(int& counter, size_t detections) {
  counter += static_cast<int>(detections);
  report_.detections_refused += static_cast<int>(detections);
}

Status PipelineCore::addDetections(const DetectionInstant& instant) {
  if (finished_) return Status(StatusCode::kFailedPrecondition, "pipeline: detections after finish");
  if (instant.size() == 0) return markDetectorDone(instant.t);
  if (!instant.corners.empty() && !frontend_->camera()) {
    counters_.detections_invalid += static_cast<int>(instant.size());
    return Status(StatusCode::kFailedPrecondition, "detection instant at t=" + formatTimestamp(instant.t) +
                                                       ": corner detections need a camera (none was given)");
  }
  const Status valid = validateDetectionInstant(instant);
  if (!valid.ok()) {
    counters_.detections_invalid += static_cast<int>(instant.size());
    return valid;
  }
  if (instant.t < last_instant_t_) {
    counters_.detections_backwards += static_cast<int>(instant.size());
    return Status(StatusCode::kInvalidArgument, "detection instant at t=" + formatTimestamp(instant.t) +
                                                    " is older than the one before it at t=" + formatTimestamp(last_instant_t_));
  }
  const double t = instant.t - time_offset_;
  const Status ahead = checkLead(t);
  if (!ahead.ok()) {
    counters_.detections_too_far_ahead += static_cast<int>(instant.size());
    return ahead;
  }
  // Too late: the odometry at its time was already used (a keyframe interval closed over it), so it can never be placed.
  const std::optional<double> held_from = localizer_->oldestOdometryTime();
  if (held_from && first_odometry_t_ && !clearlyBefore(t, *first_odometry_t_) && clearlyBefore(t, *held_from)) {
    counters_.detections_unplaced += static_cast<int>(instant.size());
    return Status(StatusCode::kFailedPrecondition,
                  "detection instant at t=" + formatTimestamp(t) + " (odometry clock) arrived " +
                      formatNumber(newest_odometry_t_.value_or(*held_from) - t) + " s after its image, when the odometry at its time was " +
                      "used already (held from t=" + formatTimestamp(*held_from) + "): localizer.detection_latency (" +
                      formatNumber(localizer_->params().detection_latency) + " s) must cover the detector's delay");
  }
  if (waiting_.size() >= kMaxWaitingInstants) {
    counters_.detections_queue_full += static_cast<int>(instant.size());
    return Status(StatusCode::kFailedPrecondition, "pipeline: " + std::to_string(waiting_.size()) +
                                                      " detection instants wait for odometry; refused");
  }
  last_instant_t_ = detections_complete_until_ = instant.t;
  if (self_calibrator_) {
    if (!instant.poses.empty()) self_calibrator_->notePoseDetections();
    self_calibrator_->addCorners(instant.corners, time_offset_);
  }
  waiting_.push_back(instant);
  return Status();
}

Status PipelineCore::checkLead(double t) const {
  if (!newest_odometry_t_ || !elapsedMoreThan(t, *newest_odometry_t_, params_.max_detection_lead_s)) return Status();
  return Status(StatusCode::kInvalidArgument,
                "detection instant at t=" + formatTimestamp(t) + " (odometry clock) is more than " +
                    formatTimestamp(params_.max_detection_lead_s) + " s beyond the newest odometry sample at t=" +
                    formatTimestamp(*newest_odometry_t_) + " (another clock? frontend.max_detection_lead_s)");
}

Status PipelineCore::markDetectorDone(double t) {
  if (!std::isfinite(t)) return Status(StatusCode::kInvalidArgument, "empty detection instant: time is not finite");
  // Far ahead, it would hold back every later detection as "older than the one before it": refused as a detection is.
  DG_RETURN_IF_ERROR(checkLead(t - time_offset_));
  if (t >= last_instant_t_) last_instant_t_ = detections_complete_until_ = t;  // an older one says nothing new
  return Status();
}

Result<PoseUpdate> PipelineCore::addOdometry(const OdometryInput& input) {
  if (finished_) return Status(StatusCode::kFailedPrecondition, "pipeline: odometry after finish");
  Localizer& localizer = *localizer_;
  report_ = UpdateReport{};
  report_.t = input.t;
  report_.state_before = localizer.trackingState();
  const size_t updates_before = localizer.keyframeStats().size();
  const int failed_before = localizer.counters().keyframes_failed;
  const std::optional<SequenceRunParams::CameraSwitch>& camera_switch = params_.camera_switch;
  if (camera_switch && !camera_switched_at_ && input.t >= camera_switch->t) {
    switchCamera(camera_switch->camera, input.t);
  }
  OdometrySample sample{input.t, input.odom_T_body, input.relative_covariance};
  const Status valid = localizer.checkOdometry(sample);
  if (!valid.ok()) {
    ++(validateOdometrySample(sample).ok() ? counters_.odometry_not_after_previous : counters_.odometry_invalid);
    (void)localizer.addOdometry(sample);  // counted there too (LocalizerCounters::odometry_rejected)
    return valid;
  }
  Result<std::optional<Matrix6d>> known = knownAbsoluteCovariance(input);  // the Localizer never sees it
  if (!known.ok()) return refuseBeforeLocalizer(known.status());
  // From here on the odometry is the rescaled VIO's (odom', OdometryScale): everything downstream uses it.
  sample.odom_T_body = odometry_scale_.rescaled(input.odom_T_body);
  if (sample.relative_covariance) sample.relative_covariance = odometry_scale_.rescaled(*sample.relative_covariance);
  std::optional<Matrix6d> absolute_covariance = *known;
  if (absolute_covariance) absolute_covariance = odometry_scale_.rescaled(*absolute_covariance);
  if (input.absolute_covariance && !absolute_covariance) ++counters_.odometry_covariance_unknown;
  if (input.absolute_covariance || !input.relative_covariance) {
    Result<std::optional<Matrix6d>> relative = covariances_.next(sample.odom_T_body, absolute_covariance);
    if (!relative.ok()) {
      return refuseBeforeLocalizer(Status(relative.status().code(), "odometry sample at t=" +
                                                                        formatTimestamp(input.t) + ": " +
                                                                        relative.status().message()));
    }
    sample.relative_covariance = *relative;
    counters_.covariance_clamped = covariances_.clamped();
    counters_.covariance_shrinks = covariances_.shrinks();
  } else {
    covariances_.reset();
  }
  const bool first = !newest_odometry_t_;
  if (self_calibrator_ && self_calibrator_->due(input.t, localizer_->trackingState() == TrackingState::kTracking)) {
    CameraModel camera = *frontend_->camera();
    camera.time_offset = time_offset_;
    self_calibrator_->start(input.t, camera, track_, localizer_->keyframeTrajectory());
  }
  if (self_calibrator_ && self_calibrator_->answerDue(input.t)) {  // waits here for one still running
    const std::optional<CameraModel> calibrated = self_calibrator_->takeAnswer(input.t);
    if (calibrated) switchCamera(*calibrated, input.t);
  }
  const bool gap =
      !first && params_.max_odometry_gap_s > 0.0 && elapsedMoreThan(input.t, *newest_odometry_t_, params_.max_odometry_gap_s);
  if (gap) {
    gap_ = std::make_pair(*newest_odometry_t_, input.t);
    ++counters_.odometry_gaps;
    report_.odometry_gap = true;
  }
  // The detections that arrived by this sample go first: if it closes a keyframe interval, they are in it. Those a
  // late detector may still deliver wait detection_latency, unless it said it is done up to this sample's time.
  const double horizon = std::max(input.t - localizer.params().detection_latency,
                                  std::min(input.t, detections_complete_until_ - time_offset_));
  if (!first) DG_RETURN_IF_ERROR(handUpTo(horizon, &sample));
  if (first && params_.localizer.initial_world_T_body && owned_localizer_ && params_.auto_initialize &&
      !params_.localizer.mapping) {
    // Until the frame is found, the estimate is the odometry through the best guess there is: the start pose.
    LocalizerParams guessed = params_.localizer;
    guessed.initial_world_T_odom = *params_.localizer.initial_world_T_body * sample.odom_T_body.inverse();
    auto remade = Localizer::create(guessed, map_, TrackingState::kInitialising);
    if (!remade.ok()) return remade.status();
    owned_localizer_ = std::move(remade).value();
    localizer_ = owned_localizer_.get();
  }
  localizer_->observationsCompleteUntil(horizon);
  Result<CorrectedPose> corrected = localizer_->addOdometry(sample);
  if (!corrected.ok()) return corrected.status();
  odometry_scale_.accept(input.t, input.odom_T_body);
  newest_odometry_t_ = input.t;
  if (self_calibrator_) self_calibrator_->addOdometry(sample);
  if (first) {  // the first accepted sample: the detections at its own instant (earlier ones cannot be placed)
    first_odometry_t_ = input.t;
    if (search_ && params_.auto_initialize) search_->startInitial(sample.odom_T_body);
    DG_RETURN_IF_ERROR(handUpTo(horizon, nullptr));
    corrected->state = localizer_->trackingState();
  }
  const bool bridged = gap && !elapsedMoreThan(input.t, gap_->first, params_.bridge_odometry_gap_s) &&
                       localizer_->trackingState() == TrackingState::kTracking && localizer_->frameConfirmed();
  counters_.odometry_gaps_bridged += bridged ? 1 : 0;
  if (gap && !bridged) {  // the odometry across the gap may have jumped: the frame is confirmed again before it is trusted
    const Eigen::Isometry3d world_T_body = localizer_->mapTOdom() * sample.odom_T_body;
    if (localizer_->trackingState() == TrackingState::kTracking) localizer_->distrustFrame();
    if (search_) search_->restartAfterGap(input.t, world_T_body, sample.odom_T_body);
    corrected->state = localizer_->trackingState();
  }
  const std::vector<KeyframeStats>& stats = localizer_->keyframeStats();
  if (stats.size() > updates_before) updateOdometryScale(input.t);
  report_.updates.assign(stats.begin() + static_cast<long>(std::min(updates_before, stats.size())), stats.end());
  report_.keyframe_failed = localizer_->counters().keyframes_failed > failed_before;
  if (corrected->state != TrackingState::kTracking) corrected->covariance.reset();  // a gap made it lost
  report_.state = corrected->state;
  if (self_calibrator_) self_calibrator_->noteState(input.t, corrected->state == TrackingState::kTracking);
  return PoseUpdate{*corrected, report_};
}

void PipelineCore::updateOdometryScale(double t) {
  if (!params_.odometry_scale.enabled || localizer_->trackingState() != TrackingState::kTracking ||
      !localizer_->frameConfirmed()) {
    return;
  }
  const MainGraph& graph = localizer_->mainGraph();
  const size_t count = graph.keyframes().size();
  const size_t used = std::min(count, static_cast<size_t>(params_.odometry_scale.window) + 1);
  std::vector<OdometryScale::KeyframePair, Eigen::aligned_allocator<OdometryScale::KeyframePair>> keyframes;
  keyframes.reserve(used);
  for (size_t k = count - used; k < count; ++k) {
    keyframes.push_back({graph.keyframes()[k].t, graph.keyframePose(k), graph.keyframes()[k].odom_T_body});
  }
  odometry_scale_.update(keyframes, t);
}

Status PipelineCore::handUpTo(double until, const OdometrySample* next) {
  while (!waiting_.empty() && notAfter(waiting_.front().t - time_offset_, until)) {
    DetectionInstant instant = waiting_.front().shifted(time_offset_);
    if (instant.t > until) instant = instant.shifted(instant.t - until);  // a tie within kStampTolerance: this sample's
    waiting_.pop_front();
    if (!first_odometry_t_ || clearlyBefore(instant.t, *first_odometry_t_)) {
      refuse(counters_.detections_before_odometry, instant.size());
      continue;
    }
    if (gap_ && clearlyBefore(gap_->first, instant.t) && clearlyBefore(instant.t, gap_->second)) {
      refuse(counters_.detections_in_gap, instant.size());
      continue;
    }
    Result<Eigen::Isometry3d> odom_T_body = localizer_->odometryPoseAt(instant.t, next);
    if (!odom_T_body.ok()) {
      refuse(counters_.detections_unplaced, instant.size());
      continue;
    }
    ++report_.instants;
    const Status handed = handInstant(instant, *odom_T_body);
    if (!handed.ok()) {  // the instant is lost, not the sample: counted, the run goes on
      ++counters_.instants_failed;
      counters_.last_error = handed.message();
    }
  }
  return Status();
}

Status PipelineCore::searchWith(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body,
                                const SolvedDetections& solved) {
  Result<FrameSearch::Outcome> outcome = search_->add(instant, odom_T_body, solved, *localizer_);
  if (!outcome.ok()) return outcome.status();
  if (outcome->action != SearchAction::kNone) report_.search = outcome->action;
  counters_.frame_checks_replaced = search_->checksReplaced();
  for (const FrameSearch::Seen& seen : outcome->replay) {  // solved already: only associated now
    counters_.detections_frame_search_only -= static_cast<int>(seen.instant.size());
    DG_RETURN_IF_ERROR(handInstant(seen.instant, seen.odom_T_body, &seen.solved));
  }
  // The found frame is a short window's best hypothesis: the graph refines it with those detections at the next
  // sample rather than at the first keyframe the motion makes.
  if (outcome->action == SearchAction::kRelocalized) localizer_->requestKeyframe();
  return Status();
}

Status PipelineCore::handInstant(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body,
                                 const SolvedDetections* solved_before) {
  Localizer& localizer = *localizer_;
  // PnP once per instant: solved here (the noise learning from it) unless the frame search solved it before.
  Result<SolvedDetections> solved = solved_before != nullptr ? Result<SolvedDetections>(*solved_before)
                                                             : solveInstant(*frontend_, instant, odom_T_body);
  if (!solved.ok()) return solved.status();
  if (search_ && localizer.trackingState() == TrackingState::kInitialising) {
    // The frame is not known yet: the instant reaches the search alone (counted by the frontend if replayed).
    counters_.detections_frame_search_only += static_cast<int>(instant.size());
    return searchWith(instant, odom_T_body, *solved);
  }
  const Eigen::Isometry3d world_T_body = localizer.mapTOdom() * odom_T_body;
  Result<std::vector<GateObservation>> observations = frontend_->associateSolved(*solved, world_T_body);
  if (!observations.ok()) return observations.status();
  for (const GateObservation& observation : *observations) {
    if (localizer.addObservation(observation).ok()) {
      ++report_.observations_added;
    } else {
      ++counters_.observations_rejected;
      ++report_.observations_rejected;
    }
  }
  if (!frontend_->lastUnmatched().empty()) DG_RETURN_IF_ERROR(localizer.reportUnmatched(instant.t, frontend_->lastUnmatched()));
  if (!search_) return Status();
  if (localizer.trackingState() == TrackingState::kTracking) {
    const bool suspicious = search_->checksFrames() && localizer.frameSuspicious();
    if (!suspicious) {
      search_->stop();
      return Status();
    }
    if (!search_->active()) {
      search_->startCheck(instant.t, world_T_body, odom_T_body);
      ++counters_.frame_checks;
      report_.search_started = true;
    }
    return searchWith(instant, odom_T_body, *solved);
  }
  if (search_->checking()) search_->checkBecameRelocalization();
  if (!localizer.frameConfirmed() && !search_->searchingAnywhere()) {
    // Lost in a frame no gate confirmed (a given frame the detections contradict): the estimate is no guide, so
    // the search (a check's, or none yet) goes over the whole map at once.
    search_->startRelocalizationAnywhere(odom_T_body);
    ++counters_.unconfirmed_frame_searches;
    report_.search_started = true;
  } else if (!search_->active()) {
    search_->startRelocalization(instant.t, world_T_body, odom_T_body);
    report_.search_started = true;
  }
  return searchWith(instant, odom_T_body, *solved);
}

Status PipelineCore::finish() {
  if (finished_) return Status(StatusCode::kFailedPrecondition, "pipeline: finish called twice");
  finished_ = true;
  if (self_calibrator_) self_calibrator_->finish(newest_odometry_t_);
  if (!newest_odometry_t_) return Status(StatusCode::kFailedPrecondition, "pipeline: no odometry sample was given");
  report_ = UpdateReport{};
  // What was still on its way when the odometry ended (taken within its span).
  DG_RETURN_IF_ERROR(handUpTo(*newest_odometry_t_, nullptr));
  for (const DetectionInstant& instant : waiting_) counters_.detections_after_odometry += static_cast<int>(instant.size());
  waiting_.clear();
  if (search_) {
    search_->explainNothingPlaced(static_cast<size_t>(counters_.detections_before_odometry + counters_.detections_after_odometry));
  }
  return localizer_->finish();
}

void PipelineCore::switchCamera(const CameraModel& camera, double t) {  // what arrives from now on, with it
  frontend_->setCamera(camera);
  time_offset_ = camera.time_offset;
  camera_switched_at_ = t;
  report_.camera_switched = true;
}

}  // namespace dualgraph
