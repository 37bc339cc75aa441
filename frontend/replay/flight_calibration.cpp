// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/replay/flight_calibration.h"

#include <string>

namespace dualgraph {
namespace {

Status unusable(const Sequence& sequence, const std::string& why) {
  return Status(StatusCode::kFailedPrecondition, sequence.dir + ": " + why);
}

}  // namespace

Result<CameraCalibration> calibrateCamera(const Sequence& sequence, const SequenceRunParams& run_params,
                                          const CalibrationParams& params, const CalibrationObserver& observer) {
  DG_RETURN_IF_ERROR(validateCalibrationParams(params));
  if (!sequence.has_corners || sequence.corners.empty()) {
    return unusable(sequence, "calibration needs corner detections (corners.csv); pose detections carry no pixels");
  }
  if (!sequence.camera) return unusable(sequence, "calibration needs the camera (camera.yaml)");
  if (sequence.odometry.samples.size() < 2) return unusable(sequence, "calibration needs at least 2 odometry samples");
  DG_RETURN_IF_ERROR(sequence.camera->validate());

  Sequence working = sequence;
  CameraModel camera = *sequence.camera;
  camera.time_offset = detectionTimeOffset(sequence, run_params);
  const Eigen::Matrix3d input_body_R_camera = camera.body_T_camera.linear();
  const std::vector<OdometrySample>& odometry = sequence.odometry.samples;
  CameraCalibration result;
  for (int iteration = 1; iteration <= params.max_iterations && !result.converged; ++iteration) {
    working.camera = camera;
    SequenceRunParams run_with = run_params;
    run_with.time_offset = camera.time_offset;
    run_with.self_calibration_after_s = 0.0;  // each run with the camera as it is now
    auto run = runSequence(working, run_with);
    if (!run.ok()) return run.status();
    CalibrationIteration record;
    record.iteration = iteration;
    record.detections_used_by_run = run->frontend_counters.used;
    record.run_initialized = !run->initialization || run->initialization->locked;
    if (!record.run_initialized) {
      return unusable(sequence, "the run could not find the VIO's frame in the map (" + run->initialization->why_not +
                                    "), so no detection can be matched");
    }
    auto knots = VioDriftTrack::knotsFromKeyframes(run->keyframes, odometry, params.knot_spacing);
    if (!knots.ok()) return unusable(sequence, "the run made no keyframe to start from: " + knots.status().message());
    auto solved = calibrationStep(sequence.corners, sequence.map, odometry, *knots, input_body_R_camera, params, sequence.dir,
                            camera, record);
    if (!solved.ok()) return solved.status();
    result.converged = calibrationStepConverged(record, params);
    result.iterations.push_back(record);
    if (observer) observer(record, *run);
  }
  finishCameraCalibration(camera, result);
  return result;
}

}  // namespace dualgraph
