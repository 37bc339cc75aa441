// SPDX-License-Identifier: MIT
// SelfCalibrationJob: one onboard self-calibration's inputs, copied when it starts, and the computation answering it.
#pragma once

#include <optional>
#include <vector>

#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/frontend/calibration/camera_calibration.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/corner_detection.h"
#include "dualgraph/frontend/gates/track.h"
#include "dualgraph/frontend/pipeline/pipeline_report.h"

namespace dualgraph {

/// What one step of SelfCalibrator calibrates, with everything it reads held by value, so that
/// answerSelfCalibration may run on any thread while the pipeline goes on. Times [s] on the odometry clock but the
/// corners' (camera clock); `camera.time_offset` is the offset in use. A plain value.
struct SelfCalibrationJob {
  enum class Step {
    kClockOffsetFirst,  ///< the clock offset alone, on fewer corners than the whole calibration needs
    kWhole,             ///< offset and mount, stepping down to each part alone when it cannot carry both
  };
  Step step = Step::kWhole;
  CameraModel camera;
  Track track;
  std::vector<CorrectedPose> keyframes;    ///< the run's keyframes so far
  std::vector<CornerDetection> corners;    ///< the flight so far: corners stamped while tracking, up to the start
  std::vector<OdometrySample> odometry;    ///< every accepted sample from the first to the start
  CalibrationParams calibration;           ///< its solver's parts are set by the step
  SelfCalibrationReport report;            ///< the report so far: the answer's starting point
};

/// A job's answer: the camera to use (none: nothing applied, `report.why_not` says why), the report with the
/// calibration's figures, and whether every estimated part was within its bar (no reason to step down or retry).
struct SelfCalibrationAnswer {
  std::optional<CameraModel> camera;
  SelfCalibrationReport report;
  bool nothing_to_correct = false;
};

/// Runs the job: calibrateCameraOnRun on its corners and on each half apart, judged by judgeCalibration
/// (frontend/calibration/calibration_acceptance.h); kWhole steps down to the clock offset alone, then the mount
/// alone, when the whole applies nothing and not because both parts are insignificant. Thread-safe (reads the job
/// only); deterministic.
SelfCalibrationAnswer answerSelfCalibration(const SelfCalibrationJob& job);

}  // namespace dualgraph
