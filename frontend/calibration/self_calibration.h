// SPDX-License-Identifier: MIT
// Self-calibration: the camera's clock offset and mount calibrated on the flight so far, then used for the rest.
#pragma once

#include <string>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/calibration/camera_calibration.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/sequence_run.h"

namespace dualgraph {

/// What a self-calibrating run did (metrics.json `self_calibration_*`).
struct SelfCalibrationReport {
  bool attempted = false;            ///< the flight lasted past the calibration time and had corners and a camera
  bool applied = false;              ///< the rest of the run used the calibrated camera
  double at_s = 0.0;                 ///< t_c: the flight so far ends there; the camera switched there [s]
  double time_offset_before = 0.0;   ///< the clock offset the run started with [s]
  double time_offset_after = 0.0;    ///< the calibrated one [s]
  double time_offset_sigma = 0.0;    ///< its formal 1σ [s]
  double mount_change_deg = 0.0;     ///< the angle of the mount rotation's correction [deg]
  int iterations = 0;                ///< calibration runs
  std::string why_not;               ///< when not applied: why (empty when applied)
};

/// runSequence with self-calibration when params.self_calibration_after_s > 0 and the sequence has corner
/// detections and a camera: the flight up to t_c = first odometry stamp + self_calibration_after_s (the odometry
/// up to t_c and the detections stamped up to it) is calibrated as calibrateCamera does (the same run
/// parameters, `calibration`); when that converged, the whole flight is run with a switch to the calibrated
/// camera at t_c (SequenceRunParams::camera_switch), else as it is. Causal: nothing after t_c is used before it,
/// and up to t_c the run is the one the calibration started from. The calibration is taken as instantaneous
/// (onboard it would run beside the flight, seconds of CPU, and be applied when done). Otherwise (off, pose
/// detections, no camera, mapping mode, a flight not longer than t_c) it is runSequence, `report` saying why. Errors:
/// runSequence's (a calibration that fails is reported, not returned).
Result<SequenceRunResult> runSequenceSelfCalibrating(const Sequence& sequence, const SequenceRunParams& params,
                                                      const RunProgress& progress, SelfCalibrationReport* report,
                                                      const CalibrationParams& calibration = CalibrationParams{});

}  // namespace dualgraph
