// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/localizer.h"

#include <cmath>

#include "dualgraph/core/stamp_tolerance.h"
#include "dualgraph/core/wall_clock.h"
#include "dualgraph/dual_graph/dual_graph_feed.h"
#include "dualgraph/dual_graph/single_graph_baseline.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
namespace {

/// Odometry kept while initialising or lost, so `relocalize` can anchor where a frame search began [s]
/// (FrameInitializerParams::window_s is 4 s by default).
constexpr double kSearchHistorySeconds = 5.0;

std::unique_ptr<MainGraphFeed> makeFeed(const LocalizerParams& params, std::shared_ptr<const RobustKernel> kernel) {
  if (params.mode == LocalizerMode::kSingle) return std::make_unique<SingleGraphBaseline>(params);
  return std::make_unique<DualGraphFeed>(params, std::move(kernel));
}

}  // namespace

Result<std::unique_ptr<Localizer>> Localizer::create(const LocalizerParams& params, GateMap map,
                                                     TrackingState initial) {
  DG_RETURN_IF_ERROR(validateLocalizerParams(params));
  if (initial == TrackingState::kLost) {
    return Status(StatusCode::kInvalidArgument, "a Localizer starts tracking or initialising, not lost");
  }
  if (params.mapping) initial = TrackingState::kTracking;
  DG_RETURN_IF_ERROR(validateGateMapFor(params, map));
  std::shared_ptr<const RobustKernel> kernel;
  if (params.robust_kernel != "none") {
    Result<std::shared_ptr<const RobustKernel>> parsed = makeRobustKernel(params.robust_kernel);
    if (!parsed.ok()) return parsed.status();
    kernel = *parsed;
  }
  return std::unique_ptr<Localizer>(new Localizer(params, std::move(map), std::move(kernel), initial));
}

Localizer::Localizer(const LocalizerParams& params, GateMap map, std::shared_ptr<const RobustKernel> kernel,
                     TrackingState initial)
    : params_(params),
      map_(std::move(map)),
      kernel_(kernel),
      feed_(makeFeed(params, kernel)),
      noise_model_(noiseModelOf(params)),
      noise_learner_(OdometryNoiseLearner::Params::of(params)),
      monitor_(initial, params.lost_after_s, params.lost_min_failures) {
  main_ = std::make_unique<MainGraph>(params_, map_, kernel_);
}

double Localizer::openIntervalStart() const {
  return main_->keyframes().empty() ? -std::numeric_limits<double>::infinity() : main_->keyframes().back().t;
}

Status Localizer::checkOdometry(const OdometrySample& sample) const {
  DG_RETURN_IF_ERROR(validateOdometrySample(sample));
  if (!history_.empty() && !(sample.t > history_.newest().t)) {
    return Status(StatusCode::kInvalidArgument, "odometry sample at t=" + formatTimestamp(sample.t) +
                                                    " is not after the previous one at t=" + formatTimestamp(history_.newest().t));
  }
  return Status();
}

Result<CorrectedPose> Localizer::addOdometry(const OdometrySample& sample) {
  const Status valid = checkOdometry(sample);
  if (!valid.ok()) {
    ++counters_.odometry_rejected;
    counters_.last_error = valid.message();
    return valid;
  }
  ++counters_.odometry_accepted;
  if (!history_.empty()) pose_covariance_.advance(history_.newest(), sample, noise_model_);
  history_.push(sample);
  if (monitor_.state() == TrackingState::kInitialising) {  // no graph until the frame is known
    history_.discardBefore(sample.t - kSearchHistorySeconds);
    return CorrectedPose{sample.t, mapTOdom() * sample.odom_T_body, TrackingState::kInitialising, std::nullopt};
  }
  if (main_->keyframes().empty()) {
    const Status first = main_->addFirstKeyframe(sample.t, sample.odom_T_body);
    if (!first.ok()) counters_.last_error = first.message();
    noise_learner_.addKeyframe(sample.odom_T_body, std::nullopt);
  }
  // Observations this sample now covers, in time order (attached before a keyframe at this instant), but none
  // after a keyframe that waits for late detections.
  processPending(keyframe_due_ ? std::min(*keyframe_due_, sample.t) : sample.t);
  const bool requested = keyframe_requested_after_ && notAfter(*keyframe_requested_after_, sample.t) &&
                         main_->keyframes().back().t < sample.t;
  if (!keyframe_due_ && (requested || feed_->keyframeDueAfter(sample, *main_))) keyframe_due_ = sample.t;
  if (keyframe_due_ && keyframe_requested_after_ && notAfter(*keyframe_requested_after_, *keyframe_due_)) {
    keyframe_requested_after_.reset();  // this keyframe covers what the request asked for
  }
  if (keyframe_due_ && (elapsedAtLeast(sample.t, *keyframe_due_, params_.detection_latency) ||
                        notAfter(*keyframe_due_, observations_complete_until_))) {
    closeDueKeyframe();
  }
  const TrackingState state = monitor_.state();
  return CorrectedPose{sample.t, mapTOdom() * sample.odom_T_body, state,
                       state == TrackingState::kTracking ? pose_covariance_.at(sample.t) : std::nullopt};
}

void Localizer::observationsCompleteUntil(double t) {
  if (t > observations_complete_until_) observations_complete_until_ = t;
}

void Localizer::processPending(double until) {
  while (!pending_.empty() && pending_.front().t <= until) {
    const Status used = processObservation(pending_.front());
    if (!used.ok()) {
      ++counters_.observations_failed;
      counters_.last_error = used.message();
    }
    pending_.pop_front();
  }
}

void Localizer::closeDueKeyframe() {
  const OdometrySample keyframe = history_.sampleAtOrBefore(*keyframe_due_);
  keyframe_due_.reset();
  const Status closed = closeKeyframe(&keyframe);
  if (!closed.ok()) {
    ++counters_.keyframes_failed;
    counters_.last_error = closed.message();
  }
  processPending(history_.newest().t);  // what waited behind the keyframe
}

Status Localizer::checkObservation(const GateObservation& observation) const {
  DG_RETURN_IF_ERROR(validateGateObservation(observation));
  const std::string what = "observation of gate " + std::to_string(observation.gate_id) + " at t=" + formatTimestamp(observation.t);
  if (history_.empty()) return Status(StatusCode::kFailedPrecondition, what + " arrived before any odometry");
  if (tooFarAhead(observation)) {
    return Status(StatusCode::kInvalidArgument, what + " is more than " + formatTimestamp(params_.max_observation_lead_s) +
                                                    " s beyond the newest odometry sample at t=" +
                                                    formatTimestamp(history_.newest().t) +
                                                    " (another clock? localizer.max_observation_lead_s)");
  }
  if (monitor_.state() == TrackingState::kInitialising) {
    return Status(StatusCode::kFailedPrecondition, what + ": initialising, the odometry's frame in the map is not known yet");
  }
  DG_RETURN_IF_ERROR(checkObservationFor(params_, map_, observation, what));
  if (observation.t < last_observation_t_) {
    return Status(StatusCode::kInvalidArgument, what + " is older than the previous observation at t=" +
                                                    formatTimestamp(last_observation_t_));
  }
  if (tooLate(observation)) {
    return Status(StatusCode::kFailedPrecondition, what + " arrived after the keyframe at t=" +
                                                       formatTimestamp(openIntervalStart()) + " that closed its interval");
  }
  return Status();
}

bool Localizer::tooFarAhead(const GateObservation& observation) const {
  return !history_.empty() && params_.max_observation_lead_s > 0.0 &&
         elapsedMoreThan(observation.t, history_.newest().t, params_.max_observation_lead_s);
}

bool Localizer::tooLate(const GateObservation& observation) const {
  return !history_.empty() && (observation.t < openIntervalStart() || observation.t < history_.oldestTime());
}

Status Localizer::addObservation(const GateObservation& observation) {
  const Status valid = checkObservation(observation);
  if (!valid.ok()) {
    ++counters_.observations_rejected;
    if (valid.code() == StatusCode::kFailedPrecondition && tooLate(observation)) ++counters_.observations_too_late;
    if (tooFarAhead(observation)) ++counters_.observations_too_far_ahead;
    if (monitor_.state() == TrackingState::kInitialising && !history_.empty()) ++counters_.observations_without_frame;
    counters_.last_error = valid.message();
    return valid;
  }
  ++counters_.observations_accepted;
  last_observation_t_ = observation.t;
  if (observation.t > history_.newest().t || (keyframe_due_ && observation.t > *keyframe_due_)) {
    pending_.push_back(observation);
    return Status();
  }
  const Status used = processObservation(observation);
  if (!used.ok()) {
    ++counters_.observations_failed;
    counters_.last_error = used.message();
  }
  return used;
}

Status Localizer::processObservation(const GateObservation& observation) {
  Result<Eigen::Isometry3d> odom_T_body = history_.poseAt(observation.t);
  if (!odom_T_body.ok()) return odom_T_body.status();
  if (feed_->keyframeDueBefore(observation.t, *odom_T_body, *main_)) {
    OdometrySample node;
    node.t = observation.t;
    node.odom_T_body = *odom_T_body;
    DG_RETURN_IF_ERROR(closeKeyframe(&node));
  }
  Result<ObservationUse> use = feed_->addObservation(observation, *odom_T_body, *main_, history_);
  if (!use.ok()) return use.status();
  if (*use == ObservationUse::kBetweenNodes) ++counters_.observations_between_nodes;
  return Status();
}

Status Localizer::closeKeyframe(const OdometrySample* new_keyframe) {
  const bool add = new_keyframe != nullptr && main_->keyframes().back().t < new_keyframe->t;
  if (add) {
    // The base covariance (unscaled): the main graph applies the scale, and keeps the base to rescale later.
    Result<Matrix6d> base =
        history_.relativeCovariance(main_->keyframes().back().t, new_keyframe->t, noiseModelOf(params_));
    if (!base.ok()) return base.status();
    DG_RETURN_IF_ERROR(main_->addKeyframe(new_keyframe->t, new_keyframe->odom_T_body, *base));
    noise_learner_.addKeyframe(new_keyframe->odom_T_body, *base);
  }
  ClosingEdges closing = feed_->handOverEdges(*main_, add, history_);
  learnOdometryNoise(closing.edges);
  KeyframeStats row;
  row.temp_nodes = closing.temp_nodes;
  row.temp_edges = closing.temp_edges;
  row.temp_iterations = closing.temp_iterations;
  row.temp_ms = closing.temp_ms;
  row.observations = closing.observations;
  const double start = nowMs();
  const GateEdgeOutcome outcome = main_->addGateEdges(closing.owner, closing.edges);
  row.gate_edges_added = outcome.added;
  row.gate_edges_rejected = outcome.rejected;
  row.observations_rejected = outcome.rejected_observations;
  row.gates_skipped = closing.skipped_gates + outcome.failed;
  counters_.partial_used += closing.partial_used;
  counters_.partial_unanchored += closing.partial_unanchored;
  if (!closing.skip_reason.empty()) counters_.last_error = closing.skip_reason;
  if (!outcome.message.empty()) counters_.last_error = outcome.message;
  optimizeAndRecord(row, start);
  stats_.back().covariance_ms = pose_covariance_.refresh(*main_, history_, noise_model_);
  discardHistory(main_->keyframes().back().t);
  return Status();
}

void Localizer::learnOdometryNoise(GateEdgeMeasurements& distilled) {
  if (!params_.learn_odometry_noise || params_.mode != LocalizerMode::kDual) return;
  if (noise_learner_.learnFrom(distilled)) {
    noise_model_.scale = noise_learner_.factors().odometry;
    feed_->setOdometryScale(noise_model_.scale);
    const Status scaled = main_->setOdometryScale(noise_model_.scale);
    if (!scaled.ok()) counters_.last_error = scaled.message();
  }
  noise_learner_.inflate(distilled);
}

void Localizer::optimizeAndRecord(KeyframeStats& row, double start_ms) {
  const SolverSummary summary = main_->optimize();
  const size_t conditioned_before = main_->conditionedKeyframes();
  const Status slid = main_->slideWindow();
  row.optimize_ms = nowMs() - start_ms;
  if (!slid.ok()) counters_.last_error = slid.message();
  if (main_->conditionedKeyframes() > conditioned_before) {
    counters_.keyframes_conditioned += static_cast<int>(main_->conditionedKeyframes() - conditioned_before);
    counters_.last_error = main_->lastFallback();
  }
  row.keyframe = static_cast<int>(main_->keyframes().size()) - 1;
  row.t = main_->keyframes().back().t;
  row.main_vertices = static_cast<int>(given_up_graph_keyframes_ + main_->totalVertices());
  row.main_edges = static_cast<int>(given_up_graph_edges_ + main_->totalEdges());
  row.active_edges = static_cast<int>(main_->graph().numEdges());
  row.iterations = summary.iterations;
  row.termination = summary.termination;
  if (!summary.usable() && summary.termination != TerminationReason::kNothingToOptimize) {
    counters_.last_error = "main graph optimisation: " + std::string(terminationReasonName(row.termination)) + " " + summary.message;
  }
  stats_.push_back(row);
  if (!params_.mapping) {
    monitor_.addUpdate(row.t, row.gate_edges_added, row.observations_rejected);
    if (row.gate_edges_added > 0) frame_confirmed_ = true;
    counters_.losses = monitor_.losses();
    counters_.recoveries = monitor_.recoveries();
  }
}

Status Localizer::reportUnmatched(double t, const std::vector<Eigen::Vector3d>& p_world) {
  bool finite = std::isfinite(t);
  for (const Eigen::Vector3d& p : p_world) finite = finite && p.allFinite();
  if (!finite) {
    return Status(StatusCode::kInvalidArgument, "reportUnmatched: needs a finite time and positions, got t=" +
                                                    formatTimestamp(t));
  }
  if (params_.mapping) return Status();
  monitor_.addUnmatched(t, p_world);
  counters_.losses = monitor_.losses();
  return Status();
}

void Localizer::discardHistory(double keyframe_t) {
  const bool searching = monitor_.state() != TrackingState::kTracking;
  history_.discardBefore(searching ? std::min(keyframe_t, history_.newest().t - kSearchHistorySeconds) : keyframe_t);
}

void Localizer::resumeTracking() {
  if (history_.empty()) return;
  monitor_.resume(history_.newest().t);
  counters_.recoveries = monitor_.recoveries();
}

Status Localizer::resumeWithNewGraph(double sigma_t, double sigma_r) {
  if (history_.empty()) return Status(StatusCode::kFailedPrecondition, "resumeWithNewGraph: no odometry yet");
  if (monitor_.state() != TrackingState::kLost) return Status();
  // The same frame in a new graph: a recovery, not a relocalisation.
  Result<double> anchor = startGraph(mapTOdom(), std::numeric_limits<double>::infinity(), sigma_t, sigma_r);
  if (!anchor.ok()) return anchor.status();
  monitor_.countRecovery();
  counters_.recoveries = monitor_.recoveries();
  return Status();
}

void Localizer::requestKeyframe() {
  if (history_.empty() || monitor_.state() == TrackingState::kInitialising) return;
  keyframe_requested_after_ = std::max(last_observation_t_, history_.newest().t);
}

void Localizer::distrustFrame() {
  if (history_.empty()) return;
  monitor_.declareLost(history_.newest().t);
  counters_.losses = monitor_.losses();
}

Result<double> Localizer::relocalize(const Eigen::Isometry3d& world_T_odom, double since, double sigma_t,
                                     double sigma_r) {
  if (history_.empty()) return Status(StatusCode::kFailedPrecondition, "relocalize: no odometry yet");
  DG_RETURN_IF_ERROR(checkRigidTransform(world_T_odom, "relocalize: world_T_odom"));
  const TrackingState before = monitor_.state();
  Result<double> anchor = startGraph(world_T_odom, since, sigma_t, sigma_r);
  if (!anchor.ok()) return anchor.status();
  if (before == TrackingState::kLost) ++counters_.relocalizations;
  frame_confirmed_ = false;
  return anchor;
}

Result<double> Localizer::startGraph(const Eigen::Isometry3d& world_T_odom, double since, double sigma_t,
                                     double sigma_r) {
  // σ ≤ 0: the configured prior; anything else (NaN included) must be a usable σ, or nothing changes.
  if (!(sigma_t <= 0.0)) DG_RETURN_IF_ERROR(validateSigma("prior sigma_t", sigma_t));
  if (!(sigma_r <= 0.0)) DG_RETURN_IF_ERROR(validateSigma("prior sigma_r", sigma_r));
  LocalizerParams in_frame = params_;
  in_frame.initial_world_T_odom = world_T_odom;
  if (sigma_t > 0.0 && sigma_r > 0.0) {
    in_frame.initial_sigma_t = sigma_t;
    in_frame.initial_sigma_r = sigma_r;
  }
  // The new graph and its first keyframe first: when they fail, the run goes on as it was.
  auto fresh = std::make_unique<MainGraph>(in_frame, map_, kernel_);
  (void)fresh->setOdometryScale(noise_model_.scale);  // an empty graph: nothing to rescale, nothing to fail
  const OdometrySample anchor = history_.sampleAtOrBefore(std::min(since, history_.newest().t));
  DG_RETURN_IF_ERROR(fresh->addFirstKeyframe(anchor.t, anchor.odom_T_body));
  given_up_keyframes_ = keyframeTrajectory();
  given_up_graph_keyframes_ += main_->keyframes().size();
  given_up_graph_edges_ += main_->totalEdges();
  const int dropped = static_cast<int>(pending_.size() + feed_->numObservations());
  counters_.observations_without_frame += dropped;
  pending_.clear();
  keyframe_due_.reset();
  keyframe_requested_after_.reset();
  feed_->clear();
  main_ = std::move(fresh);
  pose_covariance_.reset();
  history_.discardBefore(anchor.t);
  monitor_.locked(history_.newest().t);
  last_observation_t_ = -std::numeric_limits<double>::infinity();
  noise_learner_.addKeyframe(anchor.odom_T_body, std::nullopt);
  return anchor.t;
}

Status Localizer::finish() {
  if (keyframe_due_) closeDueKeyframe();  // and the observations behind it
  counters_.observations_never_processed += static_cast<int>(pending_.size());
  pending_.clear();
  if (history_.empty()) return Status(StatusCode::kFailedPrecondition, "finish: no odometry was given");
  if (monitor_.state() == TrackingState::kInitialising) return Status();  // no graph to finish
  const OdometrySample newest = history_.newest();
  return closeKeyframe(feed_->keyframeAtFinish() ? &newest : nullptr);
}

Eigen::Isometry3d Localizer::mapTOdom() const {
  if (main_->keyframes().empty()) return params_.initial_world_T_odom;
  const size_t newest = main_->keyframes().size() - 1;
  return main_->keyframePose(newest) * main_->keyframes()[newest].odom_T_body.inverse();
}

std::vector<CorrectedPose> Localizer::keyframeTrajectory() const {
  std::vector<CorrectedPose> trajectory = given_up_keyframes_;
  for (size_t k = 0; k < main_->keyframes().size(); ++k) {
    trajectory.push_back(
        CorrectedPose{main_->keyframes()[k].t, main_->keyframePose(k), TrackingState::kTracking, std::nullopt});
  }
  return trajectory;
}

}  // namespace dualgraph
