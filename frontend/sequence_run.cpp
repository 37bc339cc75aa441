// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/sequence_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>

#include "dualgraph/dual_graph/odometry_history.h"
#include "dualgraph/frontend/detection_feed.h"

namespace dualgraph {
namespace {

/// While the Localizer is initialising or lost: a FrameInitializer over the instants' PnP solutions, and the
/// frame it finds handed to the Localizer (`relocalize`). The first search starts at the first odometry
/// sample with the coarse start pose, when given; a relocalisation search starts where the Localizer was
/// lost, with the estimate then as its start pose (relocalization_sigma_t/_r), and searches globally after
/// relocalization_global_after_s without a lock.
class FrameSearch {
 public:
  FrameSearch(const SequenceRunParams& params, const GateMap& map) : params_(params), map_(map) {}

  bool active() const { return initializer_.has_value(); }
  void startInitial(const Eigen::Isometry3d& first_odom_T_body) {
    FrameInitializerParams search = params_.initialization;
    if (params_.localizer.initial_world_T_body) {
      search.start_world_T_body = params_.localizer.initial_world_T_body;
      search.start_sigma_t = params_.localizer.initial_sigma_t;
      search.start_sigma_r = params_.localizer.initial_sigma_r;
    }
    start(search, first_odom_T_body, -1.0);
    initial_ = true;
    initial_started_ = true;
  }
  void startRelocalization(double t, const Eigen::Isometry3d& world_T_body, const Eigen::Isometry3d& odom_T_body) {
    FrameInitializerParams search = params_.initialization;
    search.start_world_T_body = world_T_body;
    search.start_sigma_t = params_.relocalization.sigma_t;
    search.start_sigma_r = params_.relocalization.sigma_r;
    start(search, odom_T_body, t);
    initial_ = false;
    checking_ = false;
  }
  /// Tracking but suspicious (Localizer::frameSuspicious): the same search as a relocalisation's, to check the
  /// frame in use; it is replaced only by a frame that explains clearly more of the window's detections.
  void startCheck(double t, const Eigen::Isometry3d& world_T_body, const Eigen::Isometry3d& odom_T_body) {
    startRelocalization(t, world_T_body, odom_T_body);
    checking_ = true;
  }
  bool checksFrames() const { return params_.relocalization.replace_ratio > 0.0; }
  bool checking() const { return initializer_.has_value() && checking_; }
  /// The Localizer turned lost during a check: from now on the search is a relocalisation's.
  void checkBecameRelocalization() { checking_ = false; }
  void stop() {
    initializer_.reset();
    seen_.clear();
  }
  /// The first search's instants (not yet through the frontend), oldest first, within the search's window.
  struct Seen {
    DetectionInstant instant;
    Eigen::Isometry3d odom_T_body;
  };
  /// One instant's PnP solutions at odom_T_body. On lock: relocalises `localizer` and returns the first
  /// search's instants from the new first keyframe on, to be handed over again (empty for a relocalisation,
  /// whose instants went through the frontend already).
  Result<std::vector<Seen>> add(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body,
                                const std::vector<GateObservation>& solved, Localizer& localizer,
                                SequenceRunResult& result) {
    const Eigen::Isometry3d world_T_body = localizer.mapTOdom() * odom_T_body;  // where the estimate puts it
    if (!initializer_) return std::vector<Seen>{};
    placed_ += solved.size();
    if (initial_) {
      seen_.push_back(Seen{instant, odom_T_body});
      while (seen_.front().instant.t < instant.t - params_.initialization.window_s) seen_.pop_front();
    }
    // A relocalisation or check also records where the estimate in use put each detection, to weigh it.
    const FrameInitialization& found = initial_ ? initializer_->add(instant.t, odom_T_body, solved)
                                                : initializer_->addInUse(instant.t, odom_T_body, world_T_body, solved);
    if (initial_) result.initialization = found;
    if (found.locked && !initial_) {
      // The frame in use is kept when the found one is the same, or when the estimate in use explained, where it
      // placed them at their instants, at least replace_ratio of the detections the found frame explains: the
      // found frame is the best of many hypotheses from a short window, the estimate has the whole graph
      // behind it (a loss among failures can be a false alarm).
      const double ratio = params_.relocalization.replace_ratio;
      const int in_use = initializer_->inUseInliers();
      const bool same = sameFrame(found, localizer.mapTOdom(), odom_T_body);
      if (same || (ratio > 0.0 && in_use >= ratio * found.inliers)) {
        // Checking: nothing to do. Lost, and the estimate explained as many as the found frame: a false alarm,
        // tracking on in the same graph. Lost, and it explained fewer (but not clearly fewer): the frame in use
        // was about right, but its graph (its marginal prior confident in a pose that failed for lost_after_s)
        // is dropped for a new one at the current estimate, held as the search's frame would be.
        if (!checking_ && (same || in_use >= found.inliers)) {
          localizer.resumeTracking();
        } else if (!checking_) {
          DG_RETURN_IF_ERROR(localizer.resumeWithNewGraph(foundSigmaT(found), params_.localizer.initial_sigma_r));
        }
        stop();
        return std::vector<Seen>{};
      }
      if (checking_) {
        localizer.distrustFrame();
        ++result.frame_checks_replaced;
      }
    }
    if (found.locked) {
      const Eigen::Isometry3d world_T_odom = found.world_T_odom;
      const double since = seen_.empty() ? std::numeric_limits<double>::infinity() : seen_.front().instant.t;
      // The found frame's position is held as well as its own inliers say (at least 0.1 m, no worse than the
      // configured initial prior); its yaw keeps the configured σ (a few nearby gates fix it only to degrees).
      const double sigma_t = foundSigmaT(found);
      const double sigma_r = params_.localizer.initial_sigma_r;
      Result<double> anchor = localizer.relocalize(world_T_odom, since, sigma_t, sigma_r);
      if (!anchor.ok()) return anchor.status();
      std::vector<Seen> replay;
      for (Seen& seen : seen_) {
        if (seen.instant.t >= *anchor) replay.push_back(std::move(seen));
      }
      stop();
      return replay;
    }
    if (!initial_ && !checking_ && started_t_ >= 0.0 && instant.t - started_t_ > params_.relocalization.global_after_s) {
      start(params_.initialization, odom_T_body, -1.0);  // the estimate was no guide: anywhere in the map
    }
    return std::vector<Seen>{};
  }
  /// The first search's answer when it never locked and saw nothing it could use (or no detection at all).
  void explainNothingPlaced(SequenceRunResult& result, size_t skipped) const {
    if (!initial_started_) return;
    if (!result.initialization) result.initialization = FrameInitialization{};
    if (result.initialization->locked || placed_ > 0) return;
    result.initialization->why_not = "none of the detections could be used: " + std::to_string(skipped) +
                                     " outside the odometry's time span, the others refused by PnP";
  }

 private:
  /// Whether a found frame is the one the Localizer uses: within 3 of its residual RMS (at least 0.5 m) in
  /// position where the drone is, and 5° in yaw.
  static bool sameFrame(const FrameInitialization& found, const Eigen::Isometry3d& current,
                        const Eigen::Isometry3d& odom_T_body) {
    const Eigen::Matrix3d difference = found.world_T_odom.linear().transpose() * current.linear();
    const double yaw = std::atan2(difference(1, 0), difference(0, 0));
    const double apart = ((found.world_T_odom * odom_T_body).translation() - (current * odom_T_body).translation()).norm();
    return apart <= std::max(0.5, 3.0 * found.residual_rms_m) && std::abs(yaw) <= 5.0 * M_PI / 180.0;
  }
  /// A found frame's position σ: as well as its own inliers say, at least 0.1 m, no worse than the configured
  /// initial prior [m].
  double foundSigmaT(const FrameInitialization& found) const {
    return std::clamp(found.residual_rms_m, 0.1, std::max(0.1, params_.localizer.initial_sigma_t));
  }
  void start(const FrameInitializerParams& search, const Eigen::Isometry3d& odom_T_body, double t) {
    initializer_.emplace(search, map_);
    initializer_->setStartOdometry(odom_T_body);
    started_t_ = t;
  }

  const SequenceRunParams& params_;
  const GateMap& map_;
  std::optional<FrameInitializer> initializer_;
  std::deque<Seen> seen_;
  bool initial_ = false;
  bool checking_ = false;  ///< a check of the frame in use while tracking, not a relocalisation
  bool initial_started_ = false;  ///< the run looks for the frame (auto_initialize): it reports how that went
  double started_t_ = -1.0;  ///< a relocalisation search's start [s]; −1: global already
  size_t placed_ = 0;
};

/// One instant through the frontend into the Localizer at the Localizer's estimate; the detections that
/// matched no map gate go to its TrackingMonitor. With `search`: while initialising the instant goes to the
/// search alone; while lost to both.
Status handInstant(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body, GateFrontend& frontend,
                   Localizer& localizer, FrameSearch* search, SequenceRunResult& result);

/// `instant` to the frame search; on lock, the search's own instants again, now through the frontend.
Status searchWith(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body, GateFrontend& frontend,
                  Localizer& localizer, FrameSearch& search, SequenceRunResult& result) {
  // While initialising the instant reaches no other part of the frontend: its residuals teach the noise here.
  const bool initialising = localizer.trackingState() == TrackingState::kInitialising;
  Result<std::vector<GateObservation>> solved =
      initialising ? solveInstantLearningNoise(frontend, instant) : solveInstant(frontend, instant);
  if (!solved.ok()) return Status();  // PnP's own failures are counted by the frontend when it sees them
  Result<std::vector<FrameSearch::Seen>> replay = search.add(instant, odom_T_body, *solved, localizer, result);
  if (!replay.ok()) return replay.status();
  for (const FrameSearch::Seen& seen : *replay) {
    result.detections_frame_search_only -= static_cast<int>(seen.instant.size());
    DG_RETURN_IF_ERROR(handInstant(seen.instant, seen.odom_T_body, frontend, localizer, &search, result));
  }
  return Status();
}

Status handInstant(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body, GateFrontend& frontend,
                   Localizer& localizer, FrameSearch* search, SequenceRunResult& result) {
  if (search && localizer.trackingState() == TrackingState::kInitialising) {
    result.detections_frame_search_only += static_cast<int>(instant.size());
    return searchWith(instant, odom_T_body, frontend, localizer, *search, result);
  }
  const Eigen::Isometry3d world_T_body = localizer.mapTOdom() * odom_T_body;
  Result<std::vector<GateObservation>> observations = processInstant(frontend, instant, world_T_body);
  if (!observations.ok()) return observations.status();
  for (const GateObservation& observation : *observations) {
    if (!localizer.addObservation(observation).ok()) ++result.observations_rejected;
  }
  if (!frontend.lastUnmatched().empty()) DG_RETURN_IF_ERROR(localizer.reportUnmatched(instant.t, frontend.lastUnmatched()));
  if (!search) return Status();
  if (localizer.trackingState() == TrackingState::kTracking) {
    const bool suspicious = search->checksFrames() && localizer.frameSuspicious();
    if (!suspicious) {
      search->stop();
      return Status();
    }
    if (!search->active()) {
      search->startCheck(instant.t, world_T_body, odom_T_body);
      ++result.frame_checks;
    }
    return searchWith(instant, odom_T_body, frontend, localizer, *search, result);
  }
  if (search->checking()) search->checkBecameRelocalization();
  if (!search->active()) search->startRelocalization(instant.t, world_T_body, odom_T_body);
  return searchWith(instant, odom_T_body, frontend, localizer, *search, result);
}

/// Hands every instant up to `until` [s] on, the pose of an instant interpolated between the two samples of
/// `recent` (accepted odometry, oldest first) around it; instants older than recent's oldest cannot be placed
/// (counted as rejected).
Status handDetectionsUpTo(double until, const std::deque<OdometrySample>& recent, DetectionFeed& feed,
                          GateFrontend& frontend, Localizer& localizer, FrameSearch* search, SequenceRunResult& result) {
  while (!feed.done() && feed.nextTime() <= until) {
    Result<Eigen::Isometry3d> odom_T_body = odometryPoseAt(recent, feed.nextTime());
    if (!odom_T_body.ok()) {
      result.observations_rejected += static_cast<int>(feed.skipInstant());
      continue;
    }
    const DetectionInstant instant = feed.next();
    DG_RETURN_IF_ERROR(handInstant(instant, *odom_T_body, frontend, localizer, search, result));
  }
  return Status();
}

/// runSequenceWith's loop; `search` (may be null) finds the frame while initialising or lost.
Result<SequenceRunResult> runLoop(Localizer& localizer, GateFrontend& frontend, const Sequence& sequence,
                                  const RunProgress& progress, double time_offset, FrameSearch* search,
                                  const std::optional<SequenceRunParams::CameraSwitch>& camera_switch = std::nullopt) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<OdometrySample>& samples = sequence.odometry.samples;
  if (samples.empty()) return Status(StatusCode::kInvalidArgument, sequence.dir + ": no odometry samples");
  SequenceRunResult result;
  DetectionFeed feed(sequence, time_offset);
  while (!feed.done() && feed.nextTime() < samples.front().t) {
    result.detections_before_odometry += static_cast<int>(feed.skipInstant());
  }
  // Detections reach the Localizer detection_latency after their image (as onboard): an instant at t is handed
  // over once the odometry has reached t + latency, at its pose among the recent samples.
  const double latency = localizer.params().detection_latency;
  std::deque<OdometrySample> recent;  // the accepted samples of the last latency + 1 s
  bool switched = false;
  for (size_t k = 0; k < samples.size(); ++k) {
    const OdometrySample& sample = samples[k];
    if (camera_switch && !switched && sample.t >= camera_switch->t) {  // what arrives from now on, with it
      frontend.setCamera(camera_switch->camera);
      feed.setTimeOffset(camera_switch->camera.time_offset);
      result.camera_switched_at = sample.t;
      switched = true;
    }
    // The detections that arrived by this sample go first: if it closes a keyframe interval, they are in it.
    const bool first = recent.empty();
    if (!first && localizer.checkOdometry(sample).ok()) {
      recent.push_back(sample);
      DG_RETURN_IF_ERROR(handDetectionsUpTo(sample.t - latency, recent, feed, frontend, localizer, search, result));
      recent.pop_back();
    }
    Result<CorrectedPose> corrected = localizer.addOdometry(sample);
    if (corrected.ok()) {
      recent.push_back(sample);
      while (recent.front().t < sample.t - latency - 1.0) recent.pop_front();
      if (first) {  // the first accepted sample: the detections at its own instant (earlier ones cannot be placed)
        DG_RETURN_IF_ERROR(handDetectionsUpTo(sample.t - latency, recent, feed, frontend, localizer, search, result));
        corrected->state = localizer.trackingState();
      }
      result.estimate.push_back(*corrected);
    }
    if (progress) progress(k + 1, samples.size());
  }
  // What was still on its way when the odometry ended (taken within its span).
  if (!recent.empty()) {
    DG_RETURN_IF_ERROR(handDetectionsUpTo(recent.back().t, recent, feed, frontend, localizer, search, result));
  }
  result.detections_after_odometry = static_cast<int>(feed.remaining());
  if (search) search->explainNothingPlaced(result, result.detections_before_odometry + result.detections_after_odometry);
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

Result<SequenceRunResult> runSequence(const Sequence& sequence, const SequenceRunParams& params,
                                      const RunProgress& progress) {
  if (sequence.odometry.samples.empty()) return Status(StatusCode::kInvalidArgument, sequence.dir + ": no odometry samples");
  if (params.camera_switch) {
    if (!sequence.has_corners || !sequence.camera) {
      return Status(StatusCode::kInvalidArgument, sequence.dir + ": a camera switch needs corner detections and a camera");
    }
    const Status camera = params.camera_switch->camera.validate();
    if (!camera.ok()) return Status(camera.code(), sequence.dir + ": the camera switched to: " + camera.message());
  }
  auto known_map = sequence.map.gateMap();
  if (!known_map.ok()) return Status(known_map.status().code(), sequence.dir + ": " + known_map.status().message());
  GateFrontendParams frontend_params = params.frontend;
  frontend_params.mapping = params.localizer.mapping;
  // Corner rays are used by the dual graph's temporary graph with SE(3) gates only; elsewhere they are counted.
  if (params.localizer.mode != LocalizerMode::kDual || params.localizer.landmark != LandmarkModel::kPose) {
    frontend_params.partial_gates = false;
  }
  auto frontend = GateFrontend::create(frontend_params, sequence.map, sequence.camera);
  if (!frontend.ok()) return frontend.status();
  LocalizerParams localizer_params = params.localizer;
  const Eigen::Isometry3d& first_odom_T_body = sequence.odometry.samples.front().odom_T_body;
  const bool find_frame = params.auto_initialize && !params.localizer.mapping;
  // Until the frame is found, the estimate is the odometry through the best guess there is: the start pose.
  if (find_frame && params.localizer.initial_world_T_body) {
    localizer_params.initial_world_T_odom = *params.localizer.initial_world_T_body * first_odom_T_body.inverse();
  }
  auto localizer = Localizer::create(localizer_params, params.localizer.mapping ? GateMap{} : *known_map,
                                     find_frame ? TrackingState::kInitialising : TrackingState::kTracking);
  if (!localizer.ok()) return localizer.status();
  FrameSearch search(params, *known_map);
  if (find_frame) search.startInitial(first_odom_T_body);
  return runLoop(**localizer, *frontend, sequence, progress, detectionTimeOffset(sequence, params),
                 params.localizer.mapping ? nullptr : &search, params.camera_switch);
}

Result<SequenceRunResult> runSequenceWith(Localizer& localizer, GateFrontend& frontend, const Sequence& sequence,
                                          const RunProgress& progress) {
  return runLoop(localizer, frontend, sequence, progress, detectionTimeOffset(sequence, SequenceRunParams{}), nullptr);
}

}  // namespace dualgraph
