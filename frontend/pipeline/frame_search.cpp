// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/frame_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "dualgraph/core/stamp_tolerance.h"
#include "dualgraph/frontend/gates/frame_corner_fit.h"

namespace dualgraph {

void FrameSearch::startInitial(const Eigen::Isometry3d& first_odom_T_body) {
  FrameInitializerParams search = params_.initialization;
  if (params_.localizer.initial_world_T_body) {
    search.start_world_T_body = params_.localizer.initial_world_T_body;
    search.start_sigma_t = params_.localizer.initial_sigma_t;
    search.start_sigma_r = params_.localizer.initial_sigma_r;
  }
  start(search, first_odom_T_body, -1.0);
  first_odom_T_body_ = first_odom_T_body;
  initial_ = true;
  initial_started_ = true;
  if (!initialization_) initialization_ = FrameInitialization{};
}

FrameInitializerParams FrameSearch::relocalizationSearch() const {
  FrameInitializerParams search = params_.initialization;
  search.memory_m = 0.0;  // what was seen before the loss is what the lost frame misplaced
  return search;
}

void FrameSearch::startRelocalization(double t, const Eigen::Isometry3d& world_T_body,
                                      const Eigen::Isometry3d& odom_T_body) {
  FrameInitializerParams search = relocalizationSearch();
  search.start_world_T_body = world_T_body;
  search.start_sigma_t = params_.relocalization.sigma_t;
  search.start_sigma_r = params_.relocalization.sigma_r;
  start(search, odom_T_body, t);
  initial_ = false;
  checking_ = false;
}

void FrameSearch::startRelocalizationAnywhere(const Eigen::Isometry3d& odom_T_body) {
  start(relocalizationSearch(), odom_T_body, -1.0);  // the whole map already: nothing to widen after global_after_s
  initial_ = false;
  checking_ = false;
}

void FrameSearch::startCheck(double t, const Eigen::Isometry3d& world_T_body, const Eigen::Isometry3d& odom_T_body) {
  startRelocalization(t, world_T_body, odom_T_body);
  checking_ = true;
}

void FrameSearch::restartAfterGap(double t, const Eigen::Isometry3d& world_T_body,
                                  const Eigen::Isometry3d& odom_T_body) {
  if (!initializer_) return;
  if (initial_) {
    const FrameInitialization so_far = initialization_.value_or(FrameInitialization{});
    seen_.clear();
    remembered_.clear();
    startInitial(first_odom_T_body_.value_or(odom_T_body));
    initialization_ = so_far;
    return;
  }
  const bool was_checking = checking_;
  startRelocalization(t, world_T_body, odom_T_body);
  checking_ = was_checking;
}

void FrameSearch::stop() {
  initializer_.reset();
  seen_.clear();
  remembered_.clear();
}

Result<FrameSearch::Outcome> FrameSearch::add(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body,
                                              const SolvedDetections& solved, Localizer& localizer) {
  Outcome outcome;
  const Eigen::Isometry3d world_T_body = localizer.mapTOdom() * odom_T_body;  // where the estimate puts it
  if (!initializer_) return outcome;
  placed_ += solved.poses.size();
  if (initial_) {
    if (last_position_) path_m_ += (odom_T_body.translation() - *last_position_).norm();
    last_position_ = odom_T_body.translation();
    seen_.push_back(Seen{instant, odom_T_body, solved, path_m_});
    remember(instant.t);
  }
  // A relocalisation or check also records where the estimate in use put each detection, to weigh it.
  const FrameInitialization& found = initial_ ? initializer_->add(instant.t, odom_T_body, solved.poses)
                                              : initializer_->addInUse(instant.t, odom_T_body, world_T_body, solved.poses);
  if (initial_) initialization_ = found;
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
      if (checking_) {
        outcome.action = SearchAction::kCheckPassed;
      } else if (same || in_use >= found.inliers) {
        localizer.resumeTracking();
        outcome.action = SearchAction::kResumed;
      } else {
        DG_RETURN_IF_ERROR(localizer.resumeWithNewGraph(foundSigmaT(found, odom_T_body), params_.localizer.initial_sigma_r));
        outcome.action = SearchAction::kResumedNewGraph;
      }
      stop();
      return outcome;
    }
    if (checking_) {
      localizer.distrustFrame();
      ++checks_replaced_;
    }
  }
  if (found.locked) {
    const double since = seen_.empty() ? std::numeric_limits<double>::infinity() : seen_.front().instant.t;
    // The new first keyframe: at the search's first detection (a first lock), else at the newest sample.
    const Eigen::Isometry3d anchor_odom_T_body = seen_.empty() ? odom_T_body : seen_.front().odom_T_body;
    // The found frame's position is held as well as its uncertainty at the first keyframe says (foundSigmaT); its
    // yaw keeps the configured σ (a few nearby gates fix it only to degrees). A first lock is fitted again on its
    // window's corners first (refineOnCorners).
    Eigen::Isometry3d frame = found.world_T_odom;
    double sigma_t = foundSigmaT(found, anchor_odom_T_body);
    if (initial_ && params_.initialization.refine_on_corners) refineOnCorners(anchor_odom_T_body, frame, sigma_t);
    Result<double> anchor = localizer.relocalize(frame, since, sigma_t, params_.localizer.initial_sigma_r);
    if (!anchor.ok()) return anchor.status();
    for (Seen& seen : seen_) {
      if (notAfter(*anchor, seen.instant.t)) outcome.replay.push_back(std::move(seen));
    }
    outcome.action = SearchAction::kRelocalized;
    stop();
    return outcome;
  }
  if (!initial_ && !checking_ && started_t_ >= 0.0 && elapsedMoreThan(instant.t, started_t_, params_.relocalization.global_after_s)) {
    start(relocalizationSearch(), odom_T_body, -1.0);  // the estimate was no guide: anywhere in the map
  }
  return outcome;
}

void FrameSearch::explainNothingPlaced(size_t skipped) {
  if (!initial_started_) return;
  if (!initialization_) initialization_ = FrameInitialization{};
  if (initialization_->locked || placed_ > 0) return;
  initialization_->why_not = "none of the detections could be used: " + std::to_string(skipped) +
                             " outside the odometry's time span, the others refused by PnP";
}

/// Whether a found frame is the one the Localizer uses: within 3 of its residual RMS (at least 0.5 m) in position
/// where the drone is, and 5° in yaw.
bool FrameSearch::sameFrame(const FrameInitialization& found, const Eigen::Isometry3d& current,
                            const Eigen::Isometry3d& odom_T_body) {
  const Eigen::Matrix3d difference = found.world_T_odom.linear().transpose() * current.linear();
  const double yaw = std::atan2(difference(1, 0), difference(0, 0));
  const double apart = ((found.world_T_odom * odom_T_body).translation() - (current * odom_T_body).translation()).norm();
  return apart <= std::max(0.5, 3.0 * found.residual_rms_m) && std::abs(yaw) <= 5.0 * M_PI / 180.0;
}

/// A found frame's position σ at the body its first keyframe will be (odom_T_body): the frame's own uncertainty
/// there (FrameInitialization::positionSigmaAt), at least 0.1 m, no worse than the configured initial prior [m].
/// Not the inliers' residual RMS: two or three gates fitted by a yaw and a translation agree with each other far
/// better than with the map when their errors are their own (a far gate's range bias).
double FrameSearch::foundSigmaT(const FrameInitialization& found, const Eigen::Isometry3d& odom_T_body) const {
  const double sigma = found.positionSigmaAt(odom_T_body);
  return std::clamp(std::isfinite(sigma) ? sigma : params_.localizer.initial_sigma_t, 0.1,
                    std::max(0.1, params_.localizer.initial_sigma_t));
}

void FrameSearch::refineOnCorners(const Eigen::Isometry3d& anchor_odom_T_body, Eigen::Isometry3d& frame, double& sigma_t) {
  std::vector<FrameFitDetection, Eigen::aligned_allocator<FrameFitDetection>> detections;
  std::vector<int> recent_gates;
  for (const Seen& seen : seen_) {
    for (const GateObservation& pose : seen.solved.poses) {
      detections.push_back(FrameFitDetection{seen.odom_T_body, pose});
      if (std::find(recent_gates.begin(), recent_gates.end(), pose.gate_id) == recent_gates.end()) recent_gates.push_back(pose.gate_id);
    }
  }
  // The remembered detections only when the window alone holds one gate (ids unknown: -1 counts as one): they tell
  // the frame, but the odometry may have moved its frame since (the initializer's refine does the same).
  if (recent_gates.size() < 2) {
    for (const Remembered& old : remembered_) detections.push_back(old.detection);
  }
  const FrameCornerFit fit = fitFrameOnCorners(detections, map_, frame, params_.initialization.inlier_distance);
  if (!fit.refined) return;
  frame = fit.world_T_odom;
  sigma_t = std::clamp(fit.positionSigmaAt(anchor_odom_T_body), 0.1, std::max(0.1, params_.localizer.initial_sigma_t));
  if (initialization_) {
    initialization_->world_T_odom = frame;
    initialization_->refined_on_corners = true;
  }
}

void FrameSearch::remember(double t) {
  const FrameInitializerParams& p = params_.initialization;
  // As the initializer keeps its sightings (FrameInitializer::age): a gate is its id, or without one its place.
  const auto sameGate = [&](int id, const Eigen::Vector3d& at, const Remembered& r) {
    return r.detection.observation.gate_id == id && (id >= 0 || (r.p_odom - at).norm() <= p.inlier_distance);
  };
  while (elapsedMoreThan(t, seen_.front().instant.t, p.window_s)) {
    const Seen& old = seen_.front();
    for (const GateObservation& pose : old.solved.poses) {
      if (p.memory_m <= 0.0) break;
      const Eigen::Vector3d at = (old.odom_T_body * pose.body_T_gate).translation();
      // One per gate per second, counting the views it stands for.
      const auto same = std::find_if(remembered_.rbegin(), remembered_.rend(), [&](const Remembered& r) {
        return sameGate(pose.gate_id, at, r) && !elapsedAtLeast(old.instant.t, r.t, 1.0);
      });
      if (same != remembered_.rend()) {
        ++same->weight;
      } else {
        remembered_.push_back(Remembered{old.instant.t, old.path_m, at, FrameFitDetection{old.odom_T_body, pose}});
      }
      // A gate's older views go once min_gate_inliers views came more than memory_gate_s after them, not for a lone
      // glimpse (the initializer's rule, FrameInitializer::age).
      std::vector<bool> superseded(remembered_.size(), false);
      for (size_t i = 0; i < remembered_.size(); ++i) {
        if (!sameGate(pose.gate_id, at, remembered_[i])) continue;
        int later = 0;
        for (const Remembered& other : remembered_) {
          if (sameGate(pose.gate_id, at, other) && elapsedMoreThan(other.t, remembered_[i].t, p.memory_gate_s)) {
            later += other.weight;
          }
        }
        superseded[i] = later >= p.min_gate_inliers;
      }
      std::deque<Remembered, Eigen::aligned_allocator<Remembered>> kept;
      for (size_t i = 0; i < remembered_.size(); ++i) {
        if (!superseded[i]) kept.push_back(remembered_[i]);
      }
      remembered_ = std::move(kept);
    }
    seen_.pop_front();
  }
  while (!remembered_.empty() && (path_m_ - remembered_.front().path_m > p.memory_m ||
                                  elapsedMoreThan(t, remembered_.front().t, p.memory_max_s))) {
    remembered_.pop_front();
  }
}

void FrameSearch::start(const FrameInitializerParams& search, const Eigen::Isometry3d& odom_T_body, double t) {
  initializer_.emplace(search, map_);
  has_start_pose_ = search.start_world_T_body.has_value();
  initializer_->setStartOdometry(odom_T_body);
  started_t_ = t;
}

}  // namespace dualgraph
