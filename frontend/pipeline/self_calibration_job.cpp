// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/self_calibration_job.h"

#include <cmath>
#include <string>
#include <utility>

#include "dualgraph/frontend/calibration/calibration_acceptance.h"

namespace dualgraph {

namespace {

/// Which parts a calibration estimates (the rest held).
enum class Parts { kBoth, kTimeOffset, kMount };

const char* partsName(bool time_offset, bool mount) {
  if (time_offset && mount) return "clock offset and mount";
  return time_offset ? "clock offset alone" : "mount alone";
}

/// One calibration of `parts` from `report` (its figures, what was applied, why not).
SelfCalibrationAnswer calibrateParts(Parts parts, const SelfCalibrationJob& job, const SelfCalibrationReport& report) {
  SelfCalibrationAnswer answer;
  SelfCalibrationReport& self = answer.report;
  self = report;
  const std::vector<CornerDetection>& corners = job.corners;
  CalibrationParams params = job.calibration;
  params.solver.estimate_time_offset = parts != Parts::kMount;
  params.solver.estimate_mount = parts != Parts::kTimeOffset;
  self.parts = partsName(params.solver.estimate_time_offset, params.solver.estimate_mount);
  Result<CameraCalibration> calibrated =
      calibrateCameraOnRun(corners, job.track, job.camera, job.odometry, job.keyframes, params, "the flight so far");
  if (!calibrated.ok()) {
    self.why_not = "the calibration failed: " + calibrated.status().message();
    self.evidence_missing = true;
    return answer;
  }
  self.iterations = static_cast<int>(calibrated->iterations.size());
  self.time_offset_after = calibrated->camera.time_offset;
  self.time_offset_sigma = calibrated->time_offset_sigma;
  self.mount_change_deg = calibrated->mount_correction.norm() * 180.0 / M_PI;
  if (!calibrated->converged) {
    self.why_not = "the calibration did not converge in " + std::to_string(self.iterations) + " iterations";
    self.evidence_missing = true;
    return answer;
  }
  // Each half of the flight so far on its own: a correction is applied only when both halves show it.
  const auto middle = corners.begin() + static_cast<long>(corners.size() / 2);
  const std::vector<CornerDetection> halves[2] = {std::vector<CornerDetection>(corners.begin(), middle),
                                                  std::vector<CornerDetection>(middle, corners.end())};
  std::optional<CameraCalibration> half_calibrations[2];
  std::string half_failed;
  for (int h = 0; h < 2; ++h) {
    Result<CameraCalibration> half = calibrateCameraOnRun(halves[h], job.track, job.camera, job.odometry, job.keyframes,
                                                          params, h == 0 ? "its first half" : "its second half");
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
      judgeCalibration(job.camera, *calibrated, half_calibrations[0] ? &*half_calibrations[0] : nullptr,
                       half_calibrations[1] ? &*half_calibrations[1] : nullptr, half_failed);
  self.time_offset_applied = accepted.time_offset;
  self.mount_applied = accepted.mount;
  self.why_not_time_offset =
      params.solver.estimate_time_offset ? accepted.why_not_time_offset : "held (" + self.parts + ")";
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
    answer.nothing_to_correct = !time_significant && !mount_significant;
    // A part that was significant but could not be checked on both halves: the flight so far was too short for it.
    self.evidence_missing = !accepted.halves_calibrated && !answer.nothing_to_correct;
    return answer;
  }
  self.applied = true;
  self.why_not.clear();
  answer.camera = acceptedCamera(job.camera, *calibrated, accepted);
  return answer;
}

/// The whole calibration, stepping down to each part alone (the other held) when it applies nothing and not merely
/// because there is nothing to correct.
SelfCalibrationAnswer calibrateWhole(const SelfCalibrationJob& job) {
  SelfCalibrationAnswer whole = calibrateParts(Parts::kBoth, job, job.report);
  if (whole.camera || whole.nothing_to_correct) return whole;
  std::string why_not = whole.report.parts + ": " + whole.report.why_not;
  bool evidence_missing = whole.report.evidence_missing;
  for (const Parts parts : {Parts::kTimeOffset, Parts::kMount}) {
    SelfCalibrationAnswer alone = calibrateParts(parts, job, job.report);
    why_not += "; " + alone.report.parts + ": " + alone.report.why_not;
    evidence_missing = evidence_missing || alone.report.evidence_missing;
    if (alone.camera) {
      // The part held says why: what the calibrations before this one found.
      (parts == Parts::kTimeOffset ? alone.report.why_not_mount : alone.report.why_not_time_offset) =
          "held: " + why_not;
      alone.nothing_to_correct = false;
      return alone;
    }
  }
  whole.report.evidence_missing = evidence_missing;
  whole.report.why_not = why_not;
  return whole;
}

}  // namespace

SelfCalibrationAnswer answerSelfCalibration(const SelfCalibrationJob& job) {
  return job.step == SelfCalibrationJob::Step::kClockOffsetFirst ? calibrateParts(Parts::kTimeOffset, job, job.report)
                                                                 : calibrateWhole(job);
}

}  // namespace dualgraph
