// SPDX-License-Identifier: MIT
// StreamingLocalizer: the tested field pipeline as a drone runs it — odometry and detections as they arrive, threads.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/pipeline/odometry_clock_guard.h"
#include "dualgraph/frontend/pipeline/odometry_motion_guard.h"
#include "dualgraph/frontend/pipeline/pipeline_core.h"

namespace dualgraph {

/// Where StreamingLocalizer does its work.
enum class PipelineThreading {
  /// Everything inside addOdometry, on the caller's thread: deterministic (`dualgraph run` replays this way), but a
  /// sample that closes a keyframe, runs a frame search or the self-calibration takes that long (bench/README.md,
  /// "Onboard pipeline per odometry sample").
  kCallerThread,
  /// addOdometry and addDetections only queue (microseconds) and answer from the last finished result; a worker
  /// thread does the work in arrival order. The graph sees the same inputs in the same order as kCallerThread when
  /// every detection arrives before the odometry passes its time plus detection_latency.
  kWorker,
};

/// A consistent view of the pipeline for any thread: the frame map_T_odom (world_T_odom) of the newest optimised
/// keyframe, the tracking state and the corrected pose world_T_body at the newest processed odometry sample t [s].
/// Frames: world = the gate map's, odom = the VIO's. Before any sample, and after a clock restart until the new
/// pipeline's first result: t = −∞, the configured initial frame and state (initialising when the frame is searched).
struct PipelineSnapshot {
  double t = -std::numeric_limits<double>::infinity();
  Eigen::Isometry3d map_T_odom = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
  TrackingState state = TrackingState::kInitialising;
  /// Covariance of world_T_body at t (CorrectedPose::covariance: metric [t; θ], right perturbation), where known.
  std::optional<Matrix6d> covariance;
  long samples = 0;   ///< odometry samples the pipeline has taken so far, refused ones included (a feeder's progress)
  long updates = 0;   ///< main-graph updates so far
  /// The newest keyframe time [s] whose main-graph update took at least one gate edge: t − this is how long the pose
  /// has gone on the odometry alone (a detector that stopped, a camera clock the pipeline refuses). −∞ before any.
  double last_gate_update_t = -std::numeric_limits<double>::infinity();
  /// The oldest detection time [s, camera clock] that can still be placed: the odometry before it was used already
  /// (a keyframe interval closed over it), so an instant older than this is refused as too late. −∞ before any.
  double placeable_from_t = -std::numeric_limits<double>::infinity();
  /// Detections refused as too late so far (PipelineCounters::detections_unplaced: a detector slower than
  /// localizer.detection_latency), in both modes; after finish(), the run's total.
  long detections_too_late = 0;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// What a finished run holds. After a clock restart (PipelineCounters::odometry_clock_restarts) everything but the
/// pipeline counters and the Localizer's odometry_rejected describes the flight since the last restart; those two
/// count the whole stream.
struct PipelineResults {
  std::vector<CorrectedPose> keyframes;   ///< the keyframes' final estimates (those of graphs given up first)
  std::vector<KeyframeStats> stats;       ///< one row per main-graph update
  LocalizerCounters localizer_counters;
  GateFrontendCounters frontend_counters;
  PipelineCounters pipeline_counters;
  std::optional<FrameInitialization> initialization;  ///< the first frame search's answer (auto_initialize)
  std::optional<double> camera_switched_at;           ///< [s], self-calibration's or a configured camera switch
  SelfCalibrationReport self_calibration;
  OdometryScaleReport odometry_scale;  ///< the VIO's scale, estimated and applied (SequenceRunParams::odometry_scale)
};

/// The onboard pipeline (frontend/pipeline/README.md): built from the run configuration, the gate map and the
/// camera; fed odometry samples (OdometryInput: t [s] on the odometry clock, odom_T_body, optional absolute
/// covariance) and detection instants (DetectionInstant, camera clock) as they arrive; gives the corrected pose
/// world_T_body and its tracking state at each odometry sample at once. Inside: the VIO's frame search, association
/// at the corrected pose, loss and relocalisation, frame checks, adaptive pixel noise, a configured camera switch,
/// detection latency (PipelineCore). Bad input is refused with a Status naming it and counted
/// (PipelineCounters); the pipeline goes on.
///
/// Threads: addOdometry from one thread (the VIO callback), addDetections from one other (the detector callback),
/// snapshot() from any number of threads at any rate. The inputs never wait for each other's graph work in
/// kWorker mode; in kCallerThread mode addDetections may wait while an odometry sample is processed. snapshot()
/// holds a lock only for a copy of a few hundred bytes, never while graph work runs. finish() once, from the
/// odometry thread, after the inputs stopped; results after it.
class StreamingLocalizer {
 public:
  /// Inputs the worker may fall behind by before new ones are refused (≈ 80 s of 200 Hz odometry with detections).
  static constexpr size_t kDefaultMaxQueuedInputs = size_t{1} << 15;
  /// kInvalidArgument for invalid parameters, map or camera (PipelineCore::create), or max_queued_inputs 0.
  /// `max_queued_inputs`: kWorker's queue bound (odometry samples and detection instants); an input beyond it is
  /// refused with kFailedPrecondition and counted (odometry_queue_full, detections_queue_full).
  static Result<std::unique_ptr<StreamingLocalizer>> create(const SequenceRunParams& params, const Track& map,
                                                            std::optional<CameraModel> camera,
                                                            PipelineThreading threading = PipelineThreading::kCallerThread,
                                                            size_t max_queued_inputs = kDefaultMaxQueuedInputs);
  /// Around a Localizer and a GateFrontend the caller keeps (no frame search); caller-thread mode.
  static Result<std::unique_ptr<StreamingLocalizer>> borrow(Localizer& localizer, GateFrontend& frontend,
                                                            double time_offset);
  ~StreamingLocalizer();
  StreamingLocalizer(const StreamingLocalizer&) = delete;
  StreamingLocalizer& operator=(const StreamingLocalizer&) = delete;

  /// One detection instant (camera clock); an empty one (an image without gates) says the detector is done up to its
  /// t, so keyframes need not wait detection_latency for it. Caller-thread mode: the PipelineCore's checks and their
  /// Status. Worker
  /// mode: the checks that need no pipeline state (finite values, one detector per instant) answered here, and an
  /// instant older than the last published PipelineSnapshot::placeable_from_t refused as too late
  /// (kFailedPrecondition, as the core says it in caller-thread mode); the others (order, lead over the odometry, too
  /// late by what the worker has done since) counted when the worker takes it.
  Status addDetections(const DetectionInstant& instant);
  /// One odometry sample; kInvalidArgument (counted) for a non-finite or non-rigid sample, one not after the
  /// previous, one held at a clock jump (more than `frontend.max_odometry_jump_s` from the newest accepted sample,
  /// either way; OdometryClockGuard: taken once 3 samples in a row continue from it, and behind once they span 1 s),
  /// or one held at a pose jump (moved or turned faster than `frontend.max_odometry_speed_mps` /
  /// `_turn_rate_radps` from the newest accepted sample; OdometryMotionGuard: taken once 3 samples continue from it).
  /// A confirmed jump ahead is a gap; a confirmed jump back restarts the pipeline as newly created
  /// (UpdateReport::clock_restarted, in both modes; a borrowed one cannot, and refuses the confirming sample with
  /// kFailedPrecondition). Caller-thread mode: this sample's work, its pose
  /// with the covariance where known, and its report.
  /// Worker mode: the pose through the last finished result's map_T_odom, its state, no covariance (the snapshot
  /// has the one at its own sample), and the report of the sample the worker finished last.
  Result<PoseUpdate> addOdometry(const OdometryInput& input);
  /// An odometry message its adapter could not even turn into an OdometryInput (a Python array of the wrong shape, a
  /// 4×4 whose last row is not 0 0 0 1): counted as taken (PipelineSnapshot::samples, so a feeder pacing itself on it
  /// never waits for it) and as invalid (PipelineCounters::odometry_invalid). The odometry thread.
  void countMalformedOdometry();
  /// Likewise `detections` detections an adapter could not turn into a DetectionInstant (counted in
  /// PipelineCounters::detections_invalid). The detector thread.
  void countMalformedDetections(int detections);
  /// The last published view (any thread).
  PipelineSnapshot snapshot() const;
  /// End of input: the worker drains its queue and stops; the detections within the odometry's span are used;
  /// the Localizer finishes. kFailedPrecondition when called twice or without any odometry.
  Result<PipelineResults> finish();
  /// The camera-to-odometry clock offset applied to detections handed over now [s] (changes at a camera switch).
  /// Caller-thread mode, odometry thread only.
  double timeOffset() const { return core_->timeOffset(); }

 private:
  struct Event {
    bool restart = false;  ///< the clock went back: a new core before this event's odometry
    std::optional<OdometryInput> odometry;
    DetectionInstant detections;
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  StreamingLocalizer(std::unique_ptr<PipelineCore> core, PipelineThreading threading, size_t max_queued_inputs);
  /// The clock went back: the core so far is finished (its waiting detections counted), its counters carried, and a
  /// new one made from the creation's parameters, map and camera — the camera in use when it was switched (the
  /// self-calibration's clock offset and mount). The thread that owns core_.
  Status restartCore();
  void publish(const PoseUpdate& update);
  /// The clock went back (odometry thread): the snapshot is a new pipeline's until the new core publishes, and what
  /// the worker still finishes of the flight before is not published.
  void announceRestart();
  /// The sample was taken (queued, in worker mode): the guards move on to it.
  void accepted(const OdometryInput& input, ClockCheck clock);
  /// A sample the core refused still counts as taken (PipelineSnapshot::samples).
  void countRefused();
  /// Worker mode: `event` queued for the worker (refused after finish, or with the queue full: `full` set).
  Status enqueue(Event event, const char* what, bool& full);
  void workerLoop();

  std::unique_ptr<PipelineCore> core_;
  const PipelineThreading threading_;
  const size_t max_queued_inputs_;
  /// What create() was given, for a restart (absent for a borrowed core, which cannot restart).
  struct Origin {
    Track map;
    std::optional<CameraModel> camera;
  };
  std::optional<Origin> origin_;
  PipelineCounters carried_;          ///< the counters of the cores before the last restart (summed)
  int carried_odometry_rejected_ = 0; ///< odometry those cores' Localizers (or the cores before them) refused
  std::mutex work_mutex_;  ///< guards core_ (caller-thread mode; the worker owns it otherwise)
  mutable std::mutex snapshot_mutex_;
  PipelineSnapshot snapshot_;
  PipelineSnapshot initial_snapshot_;  ///< a new pipeline's (a restart publishes it)
  int announced_generation_ = 0;       ///< restarts the odometry thread decided (under snapshot_mutex_)
  int core_generation_ = 0;            ///< restarts core_ went through (core_'s owner thread only)
  UpdateReport last_report_;  ///< worker mode: the report of the sample finished last (under snapshot_mutex_)
  // Worker mode.
  std::mutex queue_mutex_;
  std::condition_variable queue_ready_;
  std::deque<Event, Eigen::aligned_allocator<Event>> queue_;
  bool stopping_ = false;
  double last_submitted_t_ = -std::numeric_limits<double>::infinity();  ///< odometry thread only
  OdometryClockGuard clock_guard_;  ///< odometry thread only: both modes hold a clock jump here, before the core
  OdometryMotionGuard motion_guard_;  ///< odometry thread only: likewise a pose jump faster than a drone flies
  int refused_on_submit_ = 0;  ///< odometry refused as not after the newest before the core (odometry thread only)
  int invalid_on_submit_ = 0;  ///< odometry invalid before the core or the queue, and malformed (odometry thread only)
  /// Detections refused before they reached the core: worker mode's checks, and malformed ones (detector thread).
  std::atomic<int> detections_invalid_on_submit_{0};
  std::atomic<int> detections_late_on_submit_{0};  ///< worker mode: older than the snapshot's placeable_from_t
  std::atomic<int> detections_queue_full_on_submit_{0};  ///< worker mode: refused with the queue full (detector thread)
  int odometry_queue_full_ = 0;  ///< worker mode: refused with the queue full (odometry thread only)
  std::thread worker_;
  bool finished_ = false;
};

}  // namespace dualgraph
