// SPDX-License-Identifier: MIT
// FrameSearch: while initialising, lost or checking, where the VIO's frame lies in the gate map, and what to do on a find.
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/frontend/gates/frame_corner_fit.h"
#include "dualgraph/frontend/gates/frame_initializer.h"
#include "dualgraph/frontend/gates/gate_frontend.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/pipeline/detection_instant.h"

namespace dualgraph {

/// What one instant did to the search and, through it, to the Localizer.
enum class SearchAction {
  kNone,            ///< no lock yet (or no search running)
  kRelocalized,     ///< a frame was found (first lock, relocalisation, or a check that replaced the frame): new graph
  kResumed,         ///< lost, the frame in use was found again: tracking on in the same graph (a false alarm)
  kResumedNewGraph, ///< lost, the frame in use about right: tracking on in a new graph at the estimate
  kCheckPassed,     ///< a check of the frame in use while tracking kept it
};

/// The search of the pipeline (StreamingLocalizer) for the VIO's frame in the map: a FrameInitializer over the
/// instants' PnP solutions (pose observations in the body frame), and the decision taken on a find, applied to
/// the Localizer (`relocalize`, `resumeTracking`, `resumeWithNewGraph`, `distrustFrame`). The first search starts
/// at the first odometry sample with the coarse start pose (LocalizerParams::initial_world_T_body) when given; a
/// relocalisation search starts where the Localizer was lost, with the estimate then as its start pose
/// (RelocalizationParams σ), and searches the whole map after global_after_s without a lock; a check (tracking,
/// but detections keep failing beside used ones) runs the same search and replaces the frame only when the
/// estimate explained fewer than replace_ratio of the detections the found frame explains. Times [s] on the
/// odometry clock, positions [m] in the map (world) frame. Not thread-safe (owned by one pipeline).
class FrameSearch {
 public:
  /// `params` and `map` must outlive the search.
  FrameSearch(const SequenceRunParams& params, const GateMap& map) : params_(params), map_(map) {}

  /// An instant the first search saw before its lock, to be handed over again from the new first keyframe on.
  struct Seen {
    DetectionInstant instant;            ///< on the odometry clock
    Eigen::Isometry3d odom_T_body;       ///< the odometry at its instant
    SolvedDetections solved;             ///< its PnP solutions (reused on replay: PnP runs once per instant)
    double path_m = 0.0;                 ///< the odometry's path at its instant (a first search's) [m]
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  struct Outcome {
    SearchAction action = SearchAction::kNone;
    std::vector<Seen> replay;  ///< first lock: the search's instants from the new first keyframe on
  };

  bool active() const { return initializer_.has_value(); }
  /// A search is running over the whole map (no start pose to search near).
  bool searchingAnywhere() const { return initializer_.has_value() && !has_start_pose_; }
  /// The first search, from the first odometry sample.
  void startInitial(const Eigen::Isometry3d& first_odom_T_body);
  /// A relocalisation search at t [s] from where the estimate puts the body.
  void startRelocalization(double t, const Eigen::Isometry3d& world_T_body, const Eigen::Isometry3d& odom_T_body);
  /// A relocalisation search anywhere in the map (as the first search, without its start pose), placing the
  /// detections through the odometry from odom_T_body on: the estimate is no guide (its frame was never confirmed
  /// by a gate), and there is nothing to widen to after relocalization_global_after_s.
  void startRelocalizationAnywhere(const Eigen::Isometry3d& odom_T_body);
  /// A check of the frame in use (tracking but suspicious): a relocalisation's search that replaces the frame only
  /// by a clearly better one.
  void startCheck(double t, const Eigen::Isometry3d& world_T_body, const Eigen::Isometry3d& odom_T_body);
  /// After a gap in the odometry the window's sightings, placed through the odometry before it, no longer apply:
  /// the running search starts again empty (the first search keeps its start pose).
  void restartAfterGap(double t, const Eigen::Isometry3d& world_T_body, const Eigen::Isometry3d& odom_T_body);
  bool checksFrames() const { return params_.relocalization.replace_ratio > 0.0; }
  bool checking() const { return initializer_.has_value() && checking_; }
  /// The Localizer turned lost during a check: from now on the search is a relocalisation's.
  void checkBecameRelocalization() { checking_ = false; }
  void stop();

  /// One instant's PnP solutions `solved` (their pose observations, detector ids kept) at odom_T_body, the estimate in use at
  /// localizer.mapTOdom(). On a find the Localizer is relocalised or resumed as the class brief says.
  Result<Outcome> add(const DetectionInstant& instant, const Eigen::Isometry3d& odom_T_body,
                      const SolvedDetections& solved, Localizer& localizer);

  /// The first search's answer so far (unset before it started).
  const std::optional<FrameInitialization>& initialization() const { return initialization_; }
  /// Checks that found a clearly better frame and replaced the one in use.
  int checksReplaced() const { return checks_replaced_; }
  /// The first search's answer when it never locked and saw nothing it could use: says why, with `skipped`
  /// detections outside the odometry's time span.
  void explainNothingPlaced(size_t skipped);

 private:
  /// The initialization's parameters without its long memory (a relocalisation's detections from before the loss
  /// were placed by the frame that failed).
  FrameInitializerParams relocalizationSearch() const;
  static bool sameFrame(const FrameInitialization& found, const Eigen::Isometry3d& current,
                        const Eigen::Isometry3d& odom_T_body);
  double foundSigmaT(const FrameInitialization& found, const Eigen::Isometry3d& odom_T_body) const;
  /// A first lock: `frame` fitted again on the window's corner rays (fitFrameOnCorners), and `sigma_t` the fit's
  /// position σ at the first keyframe (clamped as foundSigmaT); both unchanged when the fit does not refine it.
  void refineOnCorners(const Eigen::Isometry3d& anchor_odom_T_body, Eigen::Isometry3d& frame, double& sigma_t);
  void start(const FrameInitializerParams& search, const Eigen::Isometry3d& odom_T_body, double t);

  const SequenceRunParams& params_;
  const GateMap& map_;
  std::optional<FrameInitializer> initializer_;
  std::deque<Seen> seen_;
  /// A first search's detections older than the window, thinned as the initializer keeps them (one per gate per
  /// second while the odometry moved less than memory_m since): the corner fit's view of the gates seen before.
  struct Remembered {
    double t = 0.0;
    double path_m = 0.0;
    Eigen::Vector3d p_odom = Eigen::Vector3d::Zero();  ///< the gate's centre in the odometry frame [m]
    FrameFitDetection detection;
    int weight = 1;  ///< detections of its gate it stands for (thinned to one per second)
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  std::deque<Remembered, Eigen::aligned_allocator<Remembered>> remembered_;
  double path_m_ = 0.0;  ///< the odometry's path over the instants seen, chord by chord [m]
  std::optional<Eigen::Vector3d> last_position_;
  /// Moves what leaves the window at `t` into remembered_ and forgets what is beyond memory_m / memory_max_s.
  void remember(double t);
  bool initial_ = false;
  bool checking_ = false;         ///< a check of the frame in use while tracking, not a relocalisation
  bool initial_started_ = false;  ///< the run looks for the frame (auto_initialize): it reports how that went
  std::optional<Eigen::Isometry3d> first_odom_T_body_;  ///< where the first search began
  bool has_start_pose_ = false;   ///< the running search looks near a start pose (else the whole map)
  double started_t_ = -1.0;       ///< a relocalisation search's start [s]; −1: global already
  size_t placed_ = 0;
  std::optional<FrameInitialization> initialization_;
  int checks_replaced_ = 0;
};

}  // namespace dualgraph
