// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/calibration/self_calibration.h"

#include <cmath>

namespace dualgraph {
namespace {

/// The flight up to `until` [s]: odometry samples (and their absolute covariances) and corner detections
/// stamped up to it; no ground truth (a calibration must not see it).
Sequence flightSoFar(const Sequence& sequence, double until) {
  Sequence prefix;
  prefix.dir = sequence.dir;
  prefix.has_corners = sequence.has_corners;
  prefix.map = sequence.map;
  prefix.camera = sequence.camera;
  const std::vector<OdometrySample>& samples = sequence.odometry.samples;
  size_t count = 0;
  while (count < samples.size() && samples[count].t <= until) ++count;
  prefix.odometry.samples.assign(samples.begin(), samples.begin() + static_cast<long>(count));
  if (sequence.odometry.absolute_covariances.size() == samples.size()) {
    prefix.odometry.absolute_covariances.assign(sequence.odometry.absolute_covariances.begin(),
                                                sequence.odometry.absolute_covariances.begin() + static_cast<long>(count));
  }
  for (const CornerDetection& detection : sequence.corners) {
    if (detection.t <= until) prefix.corners.push_back(detection);
  }
  return prefix;
}

}  // namespace

Result<SequenceRunResult> runSequenceSelfCalibrating(const Sequence& sequence, const SequenceRunParams& params,
                                                      const RunProgress& progress, SelfCalibrationReport* report,
                                                      const CalibrationParams& calibration) {
  SelfCalibrationReport local;
  SelfCalibrationReport& r = report != nullptr ? *report : local;
  r = SelfCalibrationReport{};
  const double after = params.self_calibration_after_s;
  if (!(after > 0.0)) {
    r.why_not = "off (frontend.self_calibration_after_s: 0)";
    return runSequence(sequence, params, progress);
  }
  if (params.localizer.mapping) {
    r.why_not = "not in mapping mode (no map to calibrate against)";
    return runSequence(sequence, params, progress);
  }
  if (!sequence.has_corners || !sequence.camera) {
    r.why_not = "needs corner detections and a camera (the sequence has " +
                std::string(sequence.has_corners ? "no camera" : "pose detections") + ")";
    return runSequence(sequence, params, progress);
  }
  const std::vector<OdometrySample>& samples = sequence.odometry.samples;
  if (samples.empty()) return runSequence(sequence, params, progress);  // runSequence's own error
  r.at_s = samples.front().t + after;
  r.time_offset_before = detectionTimeOffset(sequence, params);
  if (!(samples.back().t > r.at_s)) {
    r.why_not = "the flight ends before t = " + std::to_string(r.at_s) + " s";
    return runSequence(sequence, params, progress);
  }
  r.attempted = true;
  Result<CameraCalibration> calibrated = calibrateCamera(flightSoFar(sequence, r.at_s), params, calibration);
  if (!calibrated.ok()) {
    r.why_not = "the calibration failed: " + calibrated.status().message();
    return runSequence(sequence, params, progress);
  }
  r.iterations = static_cast<int>(calibrated->iterations.size());
  r.time_offset_after = calibrated->camera.time_offset;
  r.time_offset_sigma = calibrated->time_offset_sigma;
  r.mount_change_deg = calibrated->mount_correction.norm() * 180.0 / M_PI;
  if (!calibrated->converged) {
    r.why_not = "the calibration did not converge in " + std::to_string(r.iterations) + " runs";
    return runSequence(sequence, params, progress);
  }
  SequenceRunParams switched = params;
  switched.camera_switch = SequenceRunParams::CameraSwitch{r.at_s, calibrated->camera};
  Result<SequenceRunResult> run = runSequence(sequence, switched, progress);
  if (run.ok() && run->camera_switched_at) r.applied = true;
  if (run.ok() && !r.applied) r.why_not = "no odometry sample at or after the calibration time";
  return run;
}

}  // namespace dualgraph
