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

SelfCalibrator::SelfCalibrator(double after_s, double time_offset_before, std::string why_off)
    : after_s_(after_s), pending_(why_off.empty()) {
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
  return pending_ && started_ && notAfter(report_.at_s, t) && tracking && corners_.size() >= kMinCorners;
}

std::optional<CameraModel> SelfCalibrator::run(double t, const CameraModel& camera, const Track& track,
                                               const std::vector<CorrectedPose>& keyframes) {
  SelfCalibrationReport fresh;
  fresh.time_offset_before = report_.time_offset_before;
  report_ = fresh;
  report_.at_s = t;
  report_.attempted = true;
  report_.attempts = ++attempts_;
  last_attempt_t_ = t;
  // The flight so far; kept for a later attempt when this one finds too little to go on.
  std::vector<CornerDetection> corners;
  std::copy_if(corners_.begin(), corners_.end(), std::back_inserter(corners),
               [&](const CornerDetection& d) { return d.t <= t; });
  const std::optional<CameraModel> camera_to_use = attempt(camera, track, keyframes, corners);
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
  const std::vector<OdometrySample>& odometry = odometry_;
  SelfCalibrationReport& self = report_;
  Result<CameraCalibration> calibrated =
      calibrateCameraOnRun(corners, track, camera, odometry, keyframes, CalibrationParams{}, "the flight so far");
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
    Result<CameraCalibration> half = calibrateCameraOnRun(halves[h], track, camera, odometry, keyframes, CalibrationParams{},
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
  self.why_not_time_offset = accepted.why_not_time_offset;
  self.why_not_mount = accepted.why_not_mount;
  self.half_mount_change_deg[0] = accepted.half_mount_change_deg[0];
  self.half_mount_change_deg[1] = accepted.half_mount_change_deg[1];
  self.halves_mount_change_deg = accepted.halves_mount_change_deg;
  self.halves_mount_sigma_deg = accepted.halves_mount_sigma_deg;
  if (!accepted.time_offset && !accepted.mount) {
    self.why_not = "neither part cleared the bar: " + accepted.why_not_time_offset + "; " + accepted.why_not_mount;
    // A part that was significant but could not be checked on both halves: the flight so far was too short for it.
    self.evidence_missing =
        !accepted.halves_calibrated && (accepted.time_offset_significant || accepted.mount_significant);
    return std::nullopt;
  }
  self.applied = true;
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
