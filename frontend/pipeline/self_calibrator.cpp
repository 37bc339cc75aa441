// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/self_calibrator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <utility>

#include "dualgraph/core/stamp_tolerance.h"

namespace dualgraph {

SelfCalibrator::SelfCalibrator(double after_s, double budget_s, double time_offset_before, std::string why_off,
                               CalibrationParams calibration)
    : after_s_(after_s), budget_s_(budget_s), calibration_(std::move(calibration)), pending_(why_off.empty()) {
  report_.time_offset_before = time_offset_before;
  report_.why_not = std::move(why_off);
}

SelfCalibrator::~SelfCalibrator() {
  // A deferred one (budget 0) never ran: waiting would run it.
  if (running_ && running_->answer.valid() &&
      running_->answer.wait_for(std::chrono::seconds(0)) != std::future_status::deferred) {
    running_->answer.wait();
  }
}

void SelfCalibrator::addCorners(const std::vector<CornerDetection>& corners, double time_offset) {
  if (!pending_) return;
  for (const CornerDetection& corner : corners) {
    const double t_odometry = corner.t - time_offset;
    if (newest_noted_ && notAfter(t_odometry, *newest_noted_)) {
      judge(corner, t_odometry);
    } else {
      waiting_.push_back(Waiting{corner, t_odometry});
    }
  }
}

void SelfCalibrator::noteState(double t, bool tracking) {
  if (!pending_) return;
  while (!waiting_.empty() && notAfter(waiting_.front().t_odometry, t)) {
    judge(waiting_.front().corner, waiting_.front().t_odometry);
    waiting_.pop_front();
  }
  if (transitions_.empty() || transitions_.back().second != tracking) transitions_.emplace_back(t, tracking);
  newest_noted_ = t;
}

bool SelfCalibrator::trackingJustBefore(double t) const {
  bool tracking = false;
  for (const auto& [from, state] : transitions_) {
    if (!clearlyBefore(from, t)) break;  // a corner stamped at a sample is used before that sample's own state
    tracking = state;
  }
  return tracking;
}

void SelfCalibrator::judge(const CornerDetection& corner, double t_odometry) {
  if (trackingJustBefore(t_odometry)) corners_.push_back(corner);
}

void SelfCalibrator::addOdometry(const OdometrySample& sample) {
  if (!pending_) return;
  if (!started_) {
    started_ = true;
    report_.at_s = sample.t + after_s_;  // t_c until it runs, then when it ran
  }
  odometry_.push_back(sample);
}

bool SelfCalibrator::due(double t, bool tracking) const {
  if (running_ || !(pending_ && started_ && tracking && notAfter(report_.at_s, t))) return false;
  // The corners start() would use: those stamped by t (a detector ahead of the odometry delivers later ones early),
  // counted up to what is needed (this runs at every sample while a calibration is pending).
  size_t usable = 0;
  for (const CornerDetection& corner : corners_) {
    if (corner.t <= t && ++usable >= kMinCorners) return true;
  }
  // The clock offset alone only once the whole calibration has waited after_s past t_c for its corners: a flight
  // that has them by then calibrates both parts together, as the offset alone leans on a mount error (2° put
  // 3 ms into it on a harsh flight, whose jump recovery it then delayed by 8 s).
  const double wait = clock_offset_first_done_ ? 0.0 : after_s_;
  return usable >= next_corners_ && notAfter(report_.at_s + wait, t);
}

void SelfCalibrator::start(double t, const CameraModel& camera, const Track& track,
                           const std::vector<CorrectedPose>& keyframes) {
  SelfCalibrationJob job;
  job.report.time_offset_before = report_.time_offset_before;
  job.report.clock_offset_first_at_s = report_.clock_offset_first_at_s;
  job.report.clock_offset_first_applied = report_.clock_offset_first_applied;
  job.report.clock_offset_first_s = report_.clock_offset_first_s;
  job.report.at_s = t;
  job.report.attempted = true;
  // The flight so far; kept for a later attempt when this one finds too little to go on.
  std::copy_if(corners_.begin(), corners_.end(), std::back_inserter(job.corners),
               [&](const CornerDetection& d) { return d.t <= t; });
  // Fewer corners than the whole calibration needs: the clock offset alone, first; the whole follows.
  job.step = job.corners.size() < kMinCorners ? SelfCalibrationJob::Step::kClockOffsetFirst
                                              : SelfCalibrationJob::Step::kWhole;
  if (job.step == SelfCalibrationJob::Step::kWhole) {
    job.report.attempts = ++attempts_;
    last_attempt_t_ = t;
  }
  job.camera = camera;
  job.track = track;
  job.keyframes = keyframes;
  job.odometry = odometry_;
  job.calibration = calibration_;
  Running running;
  running.t = t;
  running.clock_offset_first = job.step == SelfCalibrationJob::Step::kClockOffsetFirst;
  running.corners = job.corners.size();
  // budget_s_ = 0: deferred, i.e. computed in takeAnswer on the caller's thread, at this same sample.
  const std::launch policy = budget_s_ > 0.0 ? std::launch::async : std::launch::deferred;
  running.answer = std::async(policy, [job = std::move(job)] { return answerSelfCalibration(job); });
  running_ = std::move(running);
}

bool SelfCalibrator::answerDue(double t) const { return running_ && notAfter(running_->t + budget_s_, t); }

std::optional<CameraModel> SelfCalibrator::takeAnswer(double t) {
  if (!running_) return std::nullopt;
  Running running = std::move(*running_);
  running_.reset();
  SelfCalibrationAnswer answer = running.answer.get();
  report_ = std::move(answer.report);
  std::optional<CameraModel> camera_to_use = std::move(answer.camera);
  if (camera_to_use) report_.applied_at_s = t;
  if (running.clock_offset_first) {
    clock_offset_first_done_ = true;
    report_.clock_offset_first_at_s = running.t;
    report_.clock_offset_first_applied = camera_to_use.has_value();
    report_.clock_offset_first_s = report_.time_offset_after;
    if (camera_to_use) first_offset_applied_at_s_ = t;
    // Too little to go on: again on twice the corners (the whole calibration at kMinCorners in any case).
    next_corners_ = camera_to_use || answer.nothing_to_correct ? kMinCorners : std::min(2 * running.corners, kMinCorners);
    if (!camera_to_use) {
      report_.why_not = "the clock offset alone, first, on " + std::to_string(running.corners) +
                        " corner detections: " + report_.why_not + "; the next step at " + std::to_string(next_corners_);
    }
    return camera_to_use;
  }
  if (!camera_to_use && report_.clock_offset_first_applied) {  // the first step's offset stays in use
    report_.applied = true;
    report_.time_offset_applied = true;
    report_.time_offset_after = report_.clock_offset_first_s;  // the offset in use, not the whole's estimate
    report_.applied_at_s = first_offset_applied_at_s_;
    report_.why_not = "the whole calibration applied nothing (the clock offset calibrated first stays): " + report_.why_not;
  }
  pending_ = !camera_to_use && report_.evidence_missing && attempts_ < kMaxAttempts;
  if (pending_) {
    report_.at_s = running.t + after_s_;  // the next attempt, on a longer flight so far
    report_.why_not += " (attempt " + std::to_string(attempts_) + " of " + std::to_string(kMaxAttempts) +
                       "; again at t = " + formatTimestamp(report_.at_s) + " s)";
  } else {
    corners_.clear();
    corners_.shrink_to_fit();
    odometry_.clear();
    odometry_.shrink_to_fit();
    waiting_.clear();
    transitions_.clear();
  }
  return camera_to_use;
}

void SelfCalibrator::finish(std::optional<double> newest_t) {
  if (running_) {  // its figures stand; its camera was never used
    const double due_at = running_->t + budget_s_;
    const bool clock_offset_first = running_->clock_offset_first;
    const bool first_offset_in_use = report_.clock_offset_first_applied;
    if (takeAnswer(due_at)) {
      report_.applied_at_s = 0.0;
      if (clock_offset_first) report_.clock_offset_first_applied = false;
      report_.applied = !clock_offset_first && first_offset_in_use;  // the first step's offset stays in use
      report_.time_offset_applied = report_.applied;
      if (report_.applied) {
        report_.time_offset_after = report_.clock_offset_first_s;
        report_.applied_at_s = first_offset_applied_at_s_;
      }
      report_.mount_applied = false;
    }
    report_.why_not = "the flight ended before its answer was due at t = " + formatTimestamp(due_at) +
                      " s (frontend.self_calibration_budget_s)" + (report_.why_not.empty() ? "" : "; " + report_.why_not);
    pending_ = false;
    return;
  }
  if (!pending_ || !newest_t) return;
  pending_ = false;
  if (attempts_ > 0) {  // a later attempt was due: the last one's figures and reasons stand
    report_.why_not += "; the flight ended before the next attempt";
    report_.at_s = last_attempt_t_;
    return;
  }
  if (clock_offset_first_done_) {  // the clock offset alone ran; the whole calibration never did
    if (!report_.why_not.empty()) report_.why_not += "; ";
    report_.why_not += "the whole calibration never ran: the flight ended with " + std::to_string(corners_.size()) +
                       " corner detections kept while tracking, " + std::to_string(kMinCorners) + " needed";
    return;
  }
  if (corners_.empty() && pose_detections_seen_) {
    report_.why_not = "needs corner detections and a camera (pose detections carry no pixels)";
  } else if (notAfter(report_.at_s, *newest_t)) {
    report_.why_not = "the flight ended before the flight so far could carry it while tracking (" +
                      std::to_string(corners_.size()) + " corner detections, " + std::to_string(kMinCorners) +
                      " needed)";
  } else {
    report_.why_not = "the flight ends before t = " + formatTimestamp(report_.at_s) + " s";
  }
}

}  // namespace dualgraph
