// SPDX-License-Identifier: MIT
// calibrateCamera (`dualgraph calibrate`): the camera's clock offset and mount from a whole recorded flight, by runs.
#pragma once

#include <functional>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/calibration/camera_calibration.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/replay/sequence_run.h"

namespace dualgraph {

/// Called after each iteration with its record and the run it solved from (e.g. to measure the run's ATE).
using CalibrationObserver = std::function<void(const CalibrationIteration&, const SequenceRunResult&)>;

/// Estimates the camera-to-VIO clock offset δ (CameraModel::time_offset) and the camera-mount rotation
/// (body_T_camera's rotation; its translation is kept) from a flight's gate corners against the known map:
/// repeat { runSequence with the current camera (δ as run_params.time_offset) → the VIO's drift correction
/// from the run's keyframes (VioDriftTrack::knotsFromKeyframes) → matchGateCorners → solveCameraCalibration
/// (δ, mount rotation and the drift correction together) → the camera updated } until δ moved less than
/// its tolerance and the rotation less than its (CalibrationParams::converged_*), or max_iterations.
/// The start: run_params.time_offset when set, else the camera's time_offset.
/// Errors: kFailedPrecondition naming the folder for a sequence without corner detections or camera, a run
/// that found no frame, fewer than min_matches matched detections; kInvalidArgument for bad params;
/// runSequence's and the solver's errors.
Result<CameraCalibration> calibrateCamera(const Sequence& sequence, const SequenceRunParams& run_params,
                                          const CalibrationParams& params, const CalibrationObserver& observer = {});

}  // namespace dualgraph
