// SPDX-License-Identifier: MIT
// Self-calibration: the camera's clock offset and mount calibrated on the flight so far, then used for the rest.
#pragma once

#include <string>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/replay/flight_calibration.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/replay/sequence_run.h"

namespace dualgraph {


/// runSequence, which self-calibrates when params.self_calibration_after_s > 0 (PipelineCore: at the first odometry
/// sample at or after t_c = first odometry stamp + self_calibration_after_s, the camera's clock offset and mount
/// rotation are calibrated on the flight so far — the corners stamped up to t_c, the odometry up to it and the
/// run's keyframes so far, calibrateCameraOnRun with default CalibrationParams, no run again — and, when that
/// converged, the rest of the flight uses the calibrated camera). Causal: nothing after t_c is used before it. The
/// calibration is taken as instantaneous (in worker mode it runs on the worker while the poses are answered from
/// the last result). `report` (may be null) gets SequenceRunResult::self_calibration: what it did, or why not (off,
/// pose detections, no camera, mapping mode, a flight not longer than t_c, a calibration that failed).
Result<SequenceRunResult> runSequenceSelfCalibrating(const Sequence& sequence, const SequenceRunParams& params,
                                                      const RunProgress& progress, SelfCalibrationReport* report);

}  // namespace dualgraph
