// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/calibration/camera_calibration.h"

#include <algorithm>
#include <cmath>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {

Status validateCalibrationParams(const CalibrationParams& p) {
  const auto bad = [](const std::string& field, const std::string& why) {
    return Status(StatusCode::kInvalidArgument, "calibration: field '" + field + "' " + why);
  };
  if (p.max_iterations < 1) return bad("max_iterations", "must be >= 1");
  if (!(std::isfinite(p.converged_time_offset) && p.converged_time_offset >= 0.0))
    return bad("converged_time_offset", "must be >= 0");
  if (!(std::isfinite(p.converged_rotation_deg) && p.converged_rotation_deg >= 0.0))
    return bad("converged_rotation_deg", "must be >= 0");
  if (!(std::isfinite(p.converged_sigma_fraction) && p.converged_sigma_fraction >= 0.0))
    return bad("converged_sigma_fraction", "must be >= 0");
  if (!(std::isfinite(p.knot_spacing) && p.knot_spacing > 0.0)) return bad("knot_spacing", "must be > 0");
  if (!(std::isfinite(p.max_match_rms_px) && p.max_match_rms_px > 0.0)) return bad("max_match_rms_px", "must be > 0");
  if (p.min_matches < 8) return bad("min_matches", "must be >= 8");
  return Status();
}

namespace {

// RMS corner distance of the matches at matching time [px].
double matchRms(const std::vector<GateCornerMatch>& matches) {
  double sum = 0.0;
  for (const GateCornerMatch& match : matches) sum += match.rms_px * match.rms_px;
  return matches.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(matches.size()));
}

}  // namespace

/// One match → solve → update step at `knots`: fills `record` from the solution, updates `camera`, returns the
/// solution (its refined knots for the next step).
Result<CalibrationSolution> calibrationStep(const std::vector<CornerDetection>& corners, const Track& map,
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

bool calibrationStepConverged(const CalibrationIteration& record, const CalibrationParams& params) {
  // A step of a tenth of the part's own 1σ changes nothing the estimate can tell (the matches it re-made can move
  // it that much); a part held is not judged.
  const double fraction = params.converged_sigma_fraction;
  const double time_tolerance = std::max(params.converged_time_offset, fraction * record.time_offset_sigma);
  const double rotation_tolerance =
      std::max(params.converged_rotation_deg, fraction * record.rotation_sigma.norm() * 180.0 / M_PI);
  return (!params.solver.estimate_time_offset || record.time_offset_step < time_tolerance) &&
         (!params.solver.estimate_mount || record.rotation_step_deg < rotation_tolerance);
}

void finishCameraCalibration(const CameraModel& camera, CameraCalibration& result) {
  const CalibrationIteration& last = result.iterations.back();
  result.camera = camera;
  result.mount_correction = last.mount_correction;
  result.time_offset_sigma = last.time_offset_sigma;
  result.rotation_sigma = last.rotation_sigma;
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
    auto solved = calibrationStep(corners, map, odometry, knots, input_body_R_camera, params, source, working, record);
    if (!solved.ok()) return solved.status();
    if (params.solver.refine_trajectory) knots = solved->knots;  // the next match at the refined drift
    result.converged = calibrationStepConverged(record, params);
    result.iterations.push_back(record);
  }
  finishCameraCalibration(working, result);
  return result;
}

}  // namespace dualgraph
