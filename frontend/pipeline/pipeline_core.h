// SPDX-License-Identifier: MIT
// PipelineCore: the onboard policy on one thread — odometry and detection instants in, corrected poses out.
#pragma once

#include <deque>
#include <memory>
#include <optional>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/dual_graph/odometry_covariance.h"
#include "dualgraph/dual_graph/odometry_scale.h"
#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/pipeline/frame_search.h"
#include "dualgraph/frontend/pipeline/pipeline_report.h"
#include "dualgraph/frontend/pipeline/self_calibrator.h"

namespace dualgraph {

/// The whole onboard policy, single-threaded (StreamingLocalizer wraps it with threads; use that one). Detection
/// instants wait in arrival order until the odometry covers their time plus LocalizerParams::detection_latency;
/// each is then placed at the odometry interpolated at its instant (the Localizer's own odometry, the one
/// buffer), solved by PnP, associated at the corrected pose and handed to the Localizer before the sample that
/// covers it (so a keyframe that sample closes finds them), or given to the frame search while initialising,
/// lost or checking the frame (FrameSearch). Times [s]: odometry clock; detections arrive on the camera clock and
/// are moved by the camera's time_offset (or SequenceRunParams::time_offset) when handed over. Bad input is
/// refused with a Status and counted (PipelineCounters); the pipeline goes on. Not thread-safe.
class PipelineCore {
 public:
  /// kInvalidArgument for invalid parameters, an invalid camera or map, a camera switch without a camera.
  static Result<std::unique_ptr<PipelineCore>> create(const SequenceRunParams& params, const Track& map,
                                                      std::optional<CameraModel> camera);
  /// Around a Localizer and a GateFrontend the caller made and keeps (benchmarks read the main graph afterwards):
  /// no frame search, the frame is the Localizer's. Both must outlive the core.
  static Result<std::unique_ptr<PipelineCore>> borrow(Localizer& localizer, GateFrontend& frontend, double time_offset);

  /// Queues one instant (camera clock). Refused (and counted): non-finite values, corners and poses mixed,
  /// older than an instant given before, more than max_detection_lead_s beyond the newest odometry
  /// (kInvalidArgument), or a full queue (kFailedPrecondition). An empty instant (the detector's image at t held no
  /// gate) says the detector has processed its images up to t: the instants up to it are handed over, and a keyframe
  /// closed, without waiting detection_latency (an older empty one is ignored; a non-finite t, or one more than
  /// max_detection_lead_s beyond the newest odometry, refused).
  Status addDetections(const DetectionInstant& instant);
  /// One odometry sample: the instants it covers are handed over first, then the sample goes to the Localizer.
  /// kInvalidArgument (counted) for a non-finite or non-rigid sample or one not after the newest.
  Result<PoseUpdate> addOdometry(const OdometryInput& input);
  /// End of input: the instants within the odometry's span are handed over, the Localizer finishes.
  Status finish();

  Localizer& localizer() { return *localizer_; }
  const Localizer& localizer() const { return *localizer_; }
  const GateFrontend& frontend() const { return *frontend_; }
  const PipelineCounters& counters() const { return counters_; }
  /// The first frame search's answer (unset without one).
  const std::optional<FrameInitialization>& initialization() const;
  /// Self-calibration (SequenceRunParams::self_calibration_after_s): what it did, or why not (so far).
  const SelfCalibrationReport& selfCalibration() const {
    static const SelfCalibrationReport kNone;
    return self_calibrator_ ? self_calibrator_->report() : kNone;
  }
  /// The odometry time [s] at which a configured camera switch took effect.
  std::optional<double> cameraSwitchedAt() const { return camera_switched_at_; }
  /// The camera-to-odometry clock offset applied to the instants handed over now [s].
  double timeOffset() const { return time_offset_; }
  /// Odometry samples refused before the Localizer saw them (their absolute covariance): LocalizerCounters does not
  /// hold them.
  int odometryRefusedBeforeLocalizer() const { return odometry_refused_before_localizer_; }
  const SequenceRunParams& params() const { return params_; }
  /// The VIO's scale as estimated and applied (SequenceRunParams::odometry_scale).
  const OdometryScale& odometryScale() const { return odometry_scale_; }

 private:
  /// After a main-graph update: the scale estimate from the graph's newest keyframes.
  void updateOdometryScale(double t);
  PipelineCore(const SequenceRunParams& params, GateMap map);
  /// Hands over the waiting instants with (t − offset) ≤ until; `next`: the sample about to be added.
  Status handUpTo(double until, const OdometrySample* next);
  /// One instant at odom_T_body: solved (unless `solved_before`), associated at the corrected pose and handed to
  /// the Localizer, or to the frame search alone while initialising; the search also while lost or checking.
  Status handInstant(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body,
                     const SolvedDetections* solved_before = nullptr);
  Status searchWith(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body,
                    const SolvedDetections& solved);
  void refuse(int& counter, size_t detections);
  /// kInvalidArgument when `t` (odometry clock) is more than max_detection_lead_s beyond the newest odometry sample.
  Status checkLead(double t) const;
  /// An empty instant at `t` (camera clock): the detector is done up to it (addDetections).
  Status markDetectorDone(double t);
  /// The camera from `t` [s] on (the detections handed over from then on are solved with it).
  void switchCamera(const CameraModel& camera, double t);
  /// An odometry sample refused after the Localizer's own checks passed (it never sees it): counted as invalid here.
  Status refuseBeforeLocalizer(Status why) {
    ++counters_.odometry_invalid;
    ++odometry_refused_before_localizer_;
    return why;
  }

  SequenceRunParams params_;
  int odometry_refused_before_localizer_ = 0;  ///< refused for their absolute covariance (the Localizer never saw them)
  GateMap map_;
  std::unique_ptr<Localizer> owned_localizer_;
  std::optional<GateFrontend> owned_frontend_;
  Localizer* localizer_ = nullptr;
  GateFrontend* frontend_ = nullptr;
  std::optional<FrameSearch> search_;
  RelativeCovarianceStream covariances_;
  OdometryScale odometry_scale_;
  std::deque<DetectionInstant> waiting_;  ///< camera clock, arrival (= time) order
  double last_instant_t_ = -std::numeric_limits<double>::infinity();  ///< camera clock
  /// The detector has processed its images up to this time (camera clock): the newest instant given, empty or not.
  double detections_complete_until_ = -std::numeric_limits<double>::infinity();
  std::optional<double> first_odometry_t_;
  std::optional<double> newest_odometry_t_;
  /// The last odometry gap (from, to) [s]: instants strictly inside it are refused.
  std::optional<std::pair<double, double>> gap_;
  double time_offset_ = 0.0;
  std::optional<double> camera_switched_at_;
  Track track_;  ///< the map as given (the self-calibration matches corners against it)
  std::optional<SelfCalibrator> self_calibrator_;  ///< absent in a borrowed core (no self-calibration there)
  PipelineCounters counters_;
  UpdateReport report_;  ///< the report of the call in progress
  bool finished_ = false;
};

}  // namespace dualgraph
