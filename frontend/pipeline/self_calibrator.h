// SPDX-License-Identifier: MIT
// SelfCalibrator: the onboard self-calibration — the flight so far collected, calibrated once it can carry it, applied in parts that hold.
#pragma once

#include <deque>
#include <future>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/frontend/calibration/camera_calibration.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/corner_detection.h"
#include "dualgraph/frontend/gates/track.h"
#include "dualgraph/frontend/pipeline/pipeline_report.h"
#include "dualgraph/frontend/pipeline/self_calibration_job.h"

namespace dualgraph {

/// The camera's clock offset and mount rotation calibrated on the flight so far, onboard (PipelineCore's). From the
/// first odometry sample t0 it keeps the odometry and the corner detections (camera clock) stamped while the
/// localizer was tracking (judged by stamp against the states after each sample, so the answer does not depend on
/// how far ahead of the odometry a detection arrived). From t_c = t0 + after_s on, at a sample at which it is
/// tracking:
/// - with kMinCornersClockOffset such corners but fewer than kMinCorners at t_c + after_s (the whole calibration
///   waited that long for its corners), the **clock offset alone** (mount held) is calibrated first: an offset
///   shows in every moving image, a mount needs many views of several gates (a real VI-SLAM's 50 ms offset cost
///   one real flight 5 cm of ATE: it never had 200). When that finds too little to go on, again on twice the
///   corners, until the whole calibration is due;
/// - with kMinCorners corners, the whole calibration (offset and mount, from the camera the first step left). It
///   **steps down** when it applies nothing and not because both parts are insignificant (it failed, did not
///   converge, a half could not be calibrated, the halves disagree): the clock offset alone, then the mount alone.
///   When it applies one part and refuses the other, its part stands: held at its value, a mount-like VIO attitude
///   error goes into the offset instead (a roll drifting 0-6° over a flight: the offset's halves then 5 ms apart).
/// Each calibration runs calibrateCameraOnRun on the corners and on each half apart, and the camera changes only by
/// the parts judgeCalibration accepts (frontend/calibration/calibration_acceptance.h); the report says which parts
/// were estimated (`parts`), what was applied, and why not the rest. The whole calibration runs once, unless it found
/// too little to go on (evidence_missing): then again after_s later on the longer flight so far, kMaxAttempts in
/// all.
///
/// A calibration takes 0.1-0.5 s of computation: with `budget_s` > 0 it runs on a thread of its own, on copies of
/// its inputs taken when it starts at t, and its camera is used from the first sample at or after t + budget_s
/// (odometry clock); the pipeline waits for it there when it is still running. The answer, and the sample it takes
/// effect at, are thus the same however fast the machine or the feed is (a replay gives what the drone got).
/// `budget_s` = 0: it runs on the caller's thread, at t. Not thread-safe (the pipeline's thread).
class SelfCalibrator {
 public:
  static constexpr size_t kMinCorners = 200;
  /// Corners for the clock offset alone, first [count].
  static constexpr size_t kMinCornersClockOffset = 50;
  /// Attempts at most: a later one only when the one before found too little to go on (evidence_missing).
  static constexpr int kMaxAttempts = 3;

  /// `why_off` non-empty: never runs, the report says so. `time_offset_before`: the camera's offset at the start [s].
  /// `budget_s` [s] ≥ 0: the odometry time a calibration has before its camera is used (see above).
  /// `calibration`: how each calibration runs (its solver's parts are set by the step).
  SelfCalibrator(double after_s, double budget_s, double time_offset_before, std::string why_off,
                 CalibrationParams calibration = {});
  SelfCalibrator(SelfCalibrator&&) = default;
  SelfCalibrator& operator=(SelfCalibrator&&) = default;
  /// Waits for a calibration still running (its answer is dropped).
  ~SelfCalibrator();

  bool pending() const { return pending_; }
  /// Corners kept so far (stamped while tracking) [count].
  size_t cornersKept() const { return corners_.size(); }
  /// Corners as they arrive (camera clock; `time_offset` [s] the camera's offset in use, t_odometry = t − it); kept
  /// only when stamped while the localizer was tracking (noteState): before the lock or while lost there is no
  /// trajectory to match them against (a flight locked late, at 24.5 s, calibrated on its first keyframe alone: 6.3 deg).
  void addCorners(const std::vector<CornerDetection>& corners, double time_offset);
  /// After each accepted odometry sample at `t` [s]: whether the localizer is tracking from it on. The corners
  /// stamped up to t are judged by the state after the sample before theirs (the state they were used in).
  void noteState(double t, bool tracking);
  void notePoseDetections() { pose_detections_seen_ = true; }
  /// Every accepted odometry sample; the first sets t_c.
  void addOdometry(const OdometrySample& sample);
  /// t_c passed (t ≥ t_c, to core/stamp_tolerance.h), tracking, enough corners for the next step, and no
  /// calibration running: start() now.
  bool due(double t, bool tracking) const;
  /// Starts a calibration of the flight so far (its corners up to t) from `camera` (its time_offset the one in use)
  /// against `track` with the run's `keyframes`, all copied: on its own thread when budget_s > 0.
  void start(double t, const CameraModel& camera, const Track& track, const std::vector<CorrectedPose>& keyframes);
  /// A started calibration's camera is due at the sample at `t` (t ≥ its start + budget_s).
  bool answerDue(double t) const;
  /// The started calibration's answer (waiting for it while it runs): the camera to use from now on, or none
  /// (report().why_not says why). Call when answerDue.
  std::optional<CameraModel> takeAnswer(double t);
  /// The flight ended (newest odometry stamp, if any): a calibration still pending says why it never ran, one
  /// still running why its camera was never used.
  void finish(std::optional<double> newest_t);
  const SelfCalibrationReport& report() const { return report_; }

 private:
  double after_s_;
  double budget_s_;
  CalibrationParams calibration_;
  int attempts_ = 0;
  bool clock_offset_first_done_ = false;
  size_t next_corners_ = kMinCornersClockOffset;  ///< corners the next step needs
  double last_attempt_t_ = 0.0;
  double first_offset_applied_at_s_ = 0.0;  ///< when the clock offset calibrated alone first took effect [s]
  bool pending_;
  bool started_ = false;
  bool pose_detections_seen_ = false;
  std::vector<CornerDetection> corners_;  ///< kept: stamped while tracking
  struct Waiting {
    CornerDetection corner;
    double t_odometry;  ///< its stamp on the odometry clock [s]
  };
  std::deque<Waiting> waiting_;  ///< stamped after the newest noted sample: not judged yet (arrival = stamp order)
  std::vector<std::pair<double, bool>> transitions_;  ///< (t, tracking from just after t): the state's changes
  std::optional<double> newest_noted_;
  bool trackingJustBefore(double t) const;
  void judge(const CornerDetection& corner, double t_odometry);
  std::vector<OdometrySample> odometry_;
  SelfCalibrationReport report_;
  /// The calibration started and not yet taken: its start, whether it is the clock offset alone first, its corners.
  struct Running {
    double t = 0.0;
    bool clock_offset_first = false;
    size_t corners = 0;
    std::future<SelfCalibrationAnswer> answer;
  };
  std::optional<Running> running_;
};

}  // namespace dualgraph
