// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/calibration/camera_calibration.h"

#include <cmath>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

Status validateCalibrationParams(const CalibrationParams& p) {
  const auto bad = [](const std::string& field, const std::string& why) {
    return Status(StatusCode::kInvalidArgument, "calibration: field '" + field + "' " + why);
  };
  if (p.max_iterations < 1) return bad("max_iterations", "must be >= 1");
  if (!(std::isfinite(p.converged_time_offset) && p.converged_time_offset >= 0.0))
    return bad("converged_time_offset", "must be >= 0");
  if (!(std::isfinite(p.converged_rotation_deg) && p.converged_rotation_deg >= 0.0))
    return bad("converged_rotation_deg", "must be >= 0");
  if (!(std::isfinite(p.knot_spacing) && p.knot_spacing > 0.0)) return bad("knot_spacing", "must be > 0");
  if (!(std::isfinite(p.max_match_rms_px) && p.max_match_rms_px > 0.0)) return bad("max_match_rms_px", "must be > 0");
  if (p.min_matches < 8) return bad("min_matches", "must be >= 8");
  return Status();
}

Status unusable(const Sequence& sequence, const std::string& why) {
  return Status(StatusCode::kFailedPrecondition, sequence.dir + ": " + why);
}

// RMS corner distance of the matches at matching time [px].
double matchRms(const std::vector<GateCornerMatch>& matches) {
  double sum = 0.0;
  for (const GateCornerMatch& match : matches) sum += match.rms_px * match.rms_px;
  return matches.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(matches.size()));
}

/// One match → solve → update step at `knots`: fills `record` from the solution, updates `camera`, returns the
/// solution (its refined knots for the next step).
Result<CalibrationSolution> solveStep(const std::vector<CornerDetection>& corners, const Track& map,
                                      const std::vector<OdometrySample>& odometry, const DriftKnots& knots,
                                      const Eigen::Matrix3d& input_body_R_camera, const CalibrationParams& params,
                                      const std::string& source, CameraModel& camera, CalibrationIteration& record) {
  const VioDriftTrack track(odometry, knots);
  const std::vector<GateCornerMatch> matches =
      matchGateCorners(corners, map, camera, camera.time_offset, track, params.max_match_rms_px, &record.matching);
  if (static_cast<int>(matches.size()) < params.min_matches) {
    return Status(StatusCode::kFailedPrecondition,
                  source + ": " + std::to_string(matches.size()) + " of " + std::to_string(corners.size()) +
                      " corner detections matched a map gate within " + std::to_string(params.max_match_rms_px) +
                      " px (at least " + std::to_string(params.min_matches) + " needed): nothing to calibrate against");
  }
  record.time_offset_used = camera.time_offset;
  record.rms_before_px = matchRms(matches);
  auto solution = solveCameraCalibration(matches, odometry, camera, camera.time_offset, knots, params.solver);
  if (!solution.ok()) return Status(solution.status().code(), source + ": " + solution.status().message());
  record.time_offset = solution->time_offset;
  record.time_offset_step = std::abs(solution->time_offset - camera.time_offset);
  record.rotation_step_deg =
      so3Log(camera.body_T_camera.linear().transpose() * solution->body_R_camera).norm() * 180.0 / M_PI;
  record.mount_correction = so3Log(input_body_R_camera.transpose() * solution->body_R_camera);
  record.time_offset_sigma = solution->time_offset_sigma;
  record.rotation_sigma = solution->rotation_sigma;
  record.rms_px = solution->rms_px;
  record.inlier_rms_px = solution->inlier_rms_px;
  record.robust_sigma_px = solution->robust_sigma_px;
  record.corners = solution->corners;
  record.inlier_corners = solution->inlier_corners;
  record.solver_iterations = solution->iterations;
  camera.time_offset = solution->time_offset;
  camera.body_T_camera.linear() = solution->body_R_camera;
  return solution;
}

bool stepConverged(const CalibrationIteration& record, const CalibrationParams& params) {
  return record.time_offset_step < params.converged_time_offset &&
         record.rotation_step_deg < params.converged_rotation_deg;
}

void finishCalibration(const CameraModel& camera, CameraCalibration& result) {
  const CalibrationIteration& last = result.iterations.back();
  result.camera = camera;
  result.mount_correction = last.mount_correction;
  result.time_offset_sigma = last.time_offset_sigma;
  result.rotation_sigma = last.rotation_sigma;
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
    auto solved = solveStep(sequence.corners, sequence.map, odometry, *knots, input_body_R_camera, params, sequence.dir,
                            camera, record);
    if (!solved.ok()) return solved.status();
    result.converged = stepConverged(record, params);
    result.iterations.push_back(record);
    if (observer) observer(record, *run);
  }
  finishCalibration(camera, result);
  return result;
}

Result<CameraCalibration> calibrateCameraOnRun(const std::vector<CornerDetection>& corners, const Track& map,
                                               const CameraModel& camera, const std::vector<OdometrySample>& odometry,
                                               const std::vector<CorrectedPose>& keyframes,
                                               const CalibrationParams& params, const std::string& source) {
  DG_RETURN_IF_ERROR(validateCalibrationParams(params));
  if (corners.empty()) return Status(StatusCode::kFailedPrecondition, source + ": no corner detections to calibrate on");
  if (odometry.size() < 2) return Status(StatusCode::kFailedPrecondition, source + ": calibration needs at least 2 odometry samples");
  DG_RETURN_IF_ERROR(camera.validate());
  auto first_knots = VioDriftTrack::knotsFromKeyframes(keyframes, odometry, params.knot_spacing);
  if (!first_knots.ok()) {
    return Status(StatusCode::kFailedPrecondition, source + ": no keyframe to start from: " + first_knots.status().message());
  }
  DriftKnots knots = *first_knots;
  CameraModel working = camera;
  const Eigen::Matrix3d input_body_R_camera = camera.body_T_camera.linear();
  CameraCalibration result;
  for (int iteration = 1; iteration <= params.max_iterations && !result.converged; ++iteration) {
    CalibrationIteration record;
    record.iteration = iteration;
    record.run_initialized = true;
    auto solved = solveStep(corners, map, odometry, knots, input_body_R_camera, params, source, working, record);
    if (!solved.ok()) return solved.status();
    if (params.solver.refine_trajectory) knots = solved->knots;  // the next match at the refined drift
    result.converged = stepConverged(record, params);
    result.iterations.push_back(record);
  }
  finishCalibration(working, result);
  return result;
}

}  // namespace dualgraph
