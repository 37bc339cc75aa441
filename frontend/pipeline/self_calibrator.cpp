// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/self_calibrator.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include "dualgraph/core/stamp_tolerance.h"
#include "dualgraph/frontend/calibration/calibration_acceptance.h"
#include "dualgraph/frontend/calibration/camera_calibration.h"

namespace dualgraph {

SelfCalibrator::SelfCalibrator(double after_s, double time_offset_before, std::string why_off,
                               CalibrationParams calibration)
    : after_s_(after_s), calibration_(std::move(calibration)), pending_(why_off.empty()) {
  report_.time_offset_before = time_offset_before;
  report_.why_not = std::move(why_off);
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
  if (!(pending_ && started_ && tracking && notAfter(report_.at_s, t))) return false;
  // The corners run() would use: those stamped by t (a detector ahead of the odometry delivers later ones early),
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

namespace {

const char* partsName(bool time_offset, bool mount) {
  if (time_offset && mount) return "clock offset and mount";
  return time_offset ? "clock offset alone" : "mount alone";
}

}  // namespace

std::optional<CameraModel> SelfCalibrator::run(double t, const CameraModel& camera, const Track& track,
                                               const std::vector<CorrectedPose>& keyframes) {
  SelfCalibrationReport fresh;
  fresh.time_offset_before = report_.time_offset_before;
  fresh.clock_offset_first_at_s = report_.clock_offset_first_at_s;
  fresh.clock_offset_first_applied = report_.clock_offset_first_applied;
  fresh.clock_offset_first_s = report_.clock_offset_first_s;
  report_ = fresh;
  report_.at_s = t;
  report_.attempted = true;
  // The flight so far; kept for a later attempt when this one finds too little to go on.
  std::vector<CornerDetection> corners;
  std::copy_if(corners_.begin(), corners_.end(), std::back_inserter(corners),
               [&](const CornerDetection& d) { return d.t <= t; });
  if (corners.size() < kMinCorners) {  // the clock offset alone, first: the whole calibration follows
    clock_offset_first_done_ = true;
    Outcome outcome;
    std::optional<CameraModel> camera_to_use =
        calibrateParts(Parts::kTimeOffset, camera, track, keyframes, corners, report_, outcome);
    report_.clock_offset_first_at_s = t;
    report_.clock_offset_first_applied = camera_to_use.has_value();
    report_.clock_offset_first_s = report_.time_offset_after;
    // Too little to go on: again on twice the corners (the whole calibration at kMinCorners in any case).
    next_corners_ = camera_to_use || outcome.nothing_to_correct ? kMinCorners : std::min(2 * corners.size(), kMinCorners);
    if (!camera_to_use) {
      report_.why_not = "the clock offset alone, first, on " + std::to_string(corners.size()) +
                        " corner detections: " + report_.why_not + "; the next step at " + std::to_string(next_corners_);
    }
    return camera_to_use;
  }
  report_.attempts = ++attempts_;
  last_attempt_t_ = t;
  std::optional<CameraModel> camera_to_use = attempt(camera, track, keyframes, corners);
  if (!camera_to_use && report_.clock_offset_first_applied) {  // the first step's offset stays in use
    report_.applied = true;
    report_.time_offset_applied = true;
    report_.time_offset_after = report_.clock_offset_first_s;  // the offset in use, not the whole's estimate
    report_.why_not = "the whole calibration applied nothing (the clock offset calibrated first stays): " + report_.why_not;
  }
  pending_ = !camera_to_use && report_.evidence_missing && attempts_ < kMaxAttempts;
  if (pending_) {
    report_.at_s = t + after_s_;  // the next attempt, on a longer flight so far
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

std::optional<CameraModel> SelfCalibrator::attempt(const CameraModel& camera, const Track& track,
                                                   const std::vector<CorrectedPose>& keyframes,
                                                   const std::vector<CornerDetection>& corners) {
  // Both parts first.
  SelfCalibrationReport whole = report_;
  Outcome outcome;
  std::optional<CameraModel> whole_camera = calibrateParts(Parts::kBoth, camera, track, keyframes, corners, whole, outcome);
  // Nothing applied, and not merely nothing to correct: each part alone (the other held).
  if (whole_camera || outcome.nothing_to_correct) {
    report_ = whole;
    return whole_camera;
  }
  std::string why_not = whole.parts + ": " + whole.why_not;
  bool evidence_missing = whole.evidence_missing;
  for (const Parts parts : {Parts::kTimeOffset, Parts::kMount}) {
    SelfCalibrationReport alone = report_;
    Outcome unused;
    std::optional<CameraModel> alone_camera = calibrateParts(parts, camera, track, keyframes, corners, alone, unused);
    why_not += "; " + alone.parts + ": " + alone.why_not;
    evidence_missing = evidence_missing || alone.evidence_missing;
    if (alone_camera) {
      report_ = alone;
      // The part held says why: what the calibrations before this one found.
      (parts == Parts::kTimeOffset ? report_.why_not_mount : report_.why_not_time_offset) = "held: " + why_not;
      return alone_camera;
    }
  }
  report_ = whole;
  report_.evidence_missing = evidence_missing;
  report_.why_not = why_not;
  return std::nullopt;
}

std::optional<CameraModel> SelfCalibrator::calibrateParts(Parts parts, const CameraModel& camera, const Track& track,
                                                          const std::vector<CorrectedPose>& keyframes,
                                                          const std::vector<CornerDetection>& corners,
                                                          SelfCalibrationReport& self, Outcome& outcome) const {
  const std::vector<OdometrySample>& odometry = odometry_;
  CalibrationParams params = calibration_;
  params.solver.estimate_time_offset = parts != Parts::kMount;
  params.solver.estimate_mount = parts != Parts::kTimeOffset;
  self.parts = partsName(params.solver.estimate_time_offset, params.solver.estimate_mount);
  outcome = Outcome{};
  Result<CameraCalibration> calibrated =
      calibrateCameraOnRun(corners, track, camera, odometry, keyframes, params, "the flight so far");
  if (!calibrated.ok()) {
    self.why_not = "the calibration failed: " + calibrated.status().message();
    self.evidence_missing = true;
    return std::nullopt;
  }
  self.iterations = static_cast<int>(calibrated->iterations.size());
  self.time_offset_after = calibrated->camera.time_offset;
  self.time_offset_sigma = calibrated->time_offset_sigma;
  self.mount_change_deg = calibrated->mount_correction.norm() * 180.0 / M_PI;
  if (!calibrated->converged) {
    self.why_not = "the calibration did not converge in " + std::to_string(self.iterations) + " iterations";
    self.evidence_missing = true;
    return std::nullopt;
  }
  // Each half of the flight so far on its own: a correction is applied only when both halves show it.
  const auto middle = corners.begin() + static_cast<long>(corners.size() / 2);
  const std::vector<CornerDetection> halves[2] = {std::vector<CornerDetection>(corners.begin(), middle),
                                                  std::vector<CornerDetection>(middle, corners.end())};
  std::optional<CameraCalibration> half_calibrations[2];
  std::string half_failed;
  for (int h = 0; h < 2; ++h) {
    Result<CameraCalibration> half = calibrateCameraOnRun(halves[h], track, camera, odometry, keyframes, params,
                                                          h == 0 ? "its first half" : "its second half");
    if (half.ok()) {
      half_calibrations[h] = std::move(half).value();
      if (!half_calibrations[h]->converged && half_failed.empty()) {
        half_failed = std::string(h == 0 ? "its first half" : "its second half") + " did not converge in " +
                      std::to_string(half_calibrations[h]->iterations.size()) + " iterations";
      }
    } else if (half_failed.empty()) {
      half_failed = half.status().message();
    }
  }
  const CalibrationAcceptance accepted =
      judgeCalibration(camera, *calibrated, half_calibrations[0] ? &*half_calibrations[0] : nullptr,
                       half_calibrations[1] ? &*half_calibrations[1] : nullptr, half_failed);
  self.time_offset_applied = accepted.time_offset;
  self.mount_applied = accepted.mount;
  self.why_not_time_offset = params.solver.estimate_time_offset ? accepted.why_not_time_offset : "held (" + self.parts + ")";
  self.why_not_mount = params.solver.estimate_mount ? accepted.why_not_mount : "held (" + self.parts + ")";
  self.half_mount_change_deg[0] = accepted.half_mount_change_deg[0];
  self.half_mount_change_deg[1] = accepted.half_mount_change_deg[1];
  self.halves_mount_change_deg = accepted.halves_mount_change_deg;
  self.halves_mount_sigma_deg = accepted.halves_mount_sigma_deg;
  if (!accepted.time_offset && !accepted.mount) {
    const bool time_significant = params.solver.estimate_time_offset && accepted.time_offset_significant;
    const bool mount_significant = params.solver.estimate_mount && accepted.mount_significant;
    self.why_not = "nothing cleared the bar: ";
    if (params.solver.estimate_time_offset) self.why_not += accepted.why_not_time_offset;
    if (params.solver.estimate_time_offset && params.solver.estimate_mount) self.why_not += "; ";
    if (params.solver.estimate_mount) self.why_not += accepted.why_not_mount;
    outcome.nothing_to_correct = !time_significant && !mount_significant;
    // A part that was significant but could not be checked on both halves: the flight so far was too short for it.
    self.evidence_missing = !accepted.halves_calibrated && !outcome.nothing_to_correct;
    return std::nullopt;
  }
  self.applied = true;
  self.why_not.clear();
  return acceptedCamera(camera, *calibrated, accepted);
}

void SelfCalibrator::finish(std::optional<double> newest_t) {
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
