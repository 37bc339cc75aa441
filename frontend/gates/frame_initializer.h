// SPDX-License-Identifier: MIT
// Where the VIO's frame lies in the gate map, found from the first gate detections without any prior.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dualgraph/dual_graph/gate_map.h"
#include "dualgraph/dual_graph/measurements.h"

namespace dualgraph {

/// How FrameInitializer searches (units: m, rad, s).
struct FrameInitializerParams {
  double window_s = 4.0;            ///< detections older than this before the newest are thinned or forgotten [s]
  /// A slow flight sees its gates minutes apart: detections older than window_s are kept, thinned to one per gate
  /// per second that counts for the detections it stands for, while the odometry has moved less than this since
  /// them (its positions at the detection instants, chord by chord) and for at most memory_max_s; 0: forgotten at
  /// window_s. A racing flight moves this far within window_s (unchanged there); drift grows with path, not time [m].
  double memory_m = 20.0;
  double memory_max_s = 120.0;      ///< [s]
  /// Of each gate, only the sightings within this of its newest views are remembered (older ones once
  /// min_gate_inliers views came later than this after them): a VIO still initialising moves its own frame by
  /// degrees in its first seconds, so a gate's newest views are those nearest the present frame [s].
  double memory_gate_s = 5.0;
  /// When a hypothesis leans on remembered detections, a gate counts towards the two a lock needs only with at
  /// least this many (one sighting of a new gate beside hundreds remembered of another cannot tell the other's
  /// side); within the window alone every gate counts from its first [count], ≥ 1.
  int min_gate_inliers = 3;
  int min_inliers = 8;              ///< detections that must agree with a hypothesis before it locks
  double inlier_distance = 1.0;     ///< a detection's gate centre within this of its map gate, in the map [m]
  double inlier_normal_angle = 0.5; ///< and its normal within this of the gate's (either side) [rad]
  /// The runner-up hypothesis (one that differs by more than 1 m or 10°) must have fewer than this share of
  /// the best one's inliers, else the layout is ambiguous and nothing locks.
  double ambiguity_ratio = 0.7;
  bool use_ids = true;              ///< a detection's own gate id (≥ 0) restricts it to that map gate
  /// A coarse start pose world_T_body at the start (setStartOdometry; else the first detection) with its position and yaw sigmas
  /// (m, rad): hypotheses further than 3 σ from it are discarded. Breaks a symmetric layout.
  std::optional<Eigen::Isometry3d> start_world_T_body;
  double start_sigma_t = 1.0;
  double start_sigma_r = 0.5;
  /// The first lock's frame fitted again on the window's corner rays against the map gates (fitFrameOnCorners,
  /// frame_corner_fit.h; FrameSearch does it, `frontend.initialization_corner_fit`): the search's PnP centres are
  /// biased short at range and two far gates fix its yaw to degrees only.
  bool refine_on_corners = true;
};

/// What the search has found so far.
struct FrameInitialization {
  bool locked = false;
  Eigen::Isometry3d world_T_odom = Eigen::Isometry3d::Identity();  ///< when locked: yaw and translation
  int inliers = 0;          ///< detections agreeing with the best hypothesis
  int gates = 0;            ///< distinct map gates among them
  int runner_up = 0;        ///< inliers of the best distinct hypothesis
  double locked_at = 0.0;   ///< time of the detection that locked it [s]
  double residual_rms_m = 0.0;  ///< when locked: RMS distance of the inliers' gate centres from their map gates [m]
  /// When locked: the frame's uncertainty from its inliers, each gate counted once (its detections share their
  /// errors). σ² per axis s² = the inliers' mean squared residual per axis, at least their PnP centre variance;
  /// the centroid of the gates' centres σ²/G; the yaw s² / Σ_g |h_g − h̄|² (h: a gate centre's horizontal
  /// position), infinite with one gate.
  double centroid_sigma_m = 0.0;
  double yaw_sigma_rad = 0.0;
  Eigen::Vector3d centroid_odom = Eigen::Vector3d::Zero();  ///< that centroid in the odometry frame [m]
  /// The position σ per axis [m] this frame puts on a body at `odom_T_body`: the centroid's, and the yaw's times the
  /// horizontal distance from the centroid.
  double positionSigmaAt(const Eigen::Isometry3d& odom_T_body) const;
  std::string why_not;      ///< when not locked: too few detections, or an ambiguous layout (with counts)
  /// The first lock only: world_T_odom is the search's frame fitted again on its window's corner rays
  /// (FrameInitializerParams::refine_on_corners), and the position σ at the first keyframe that fit's.
  bool refined_on_corners = false;
};

/// Finds world_T_odom from gate detections alone (issue 24: "automatic initialisation"). Every detection,
/// placed in the odometry frame through odom_T_body at its instant, against every map gate it may be (its
/// own id when the detector gives one and use_ids) and both gate sides, gives one gravity-aligned
/// hypothesis (the VIO's frame is gravity-aligned: a yaw from the gate normals and the translation that puts
/// the detection on the gate). Each hypothesis is scored by the detections of the window it explains; the best
/// one (most distinct gates, then most detections) locks when at least min_inliers detections of two gates or more
/// (one with a start pose) agree and no distinct hypothesis, over any number of gates, explains ambiguity_ratio of its detections
/// (a layout with a symmetry, such as the RATM ellipse's half turn, without ids or a start pose never
/// locks and says so). The locked hypothesis is refined on its inliers (least squares in yaw and
/// translation). Deterministic; never prints.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class FrameInitializer {
 public:
  FrameInitializer(const FrameInitializerParams& params, GateMap map);

  /// Adds one instant's pose observations (body_T_gate; gate_id −1 when unknown) taken at odom_T_body and
  /// searches again; the answer once locked stays as it is.
  const FrameInitialization& add(double t, const Eigen::Isometry3d& odom_T_body,
                                 const std::vector<GateObservation>& observations);
  const FrameInitialization& state() const { return state_; }
  /// Detections of the window that the estimate in use explained at their instants (by the same test as a
  /// hypothesis), counting those added with the estimate's world_T_body only (addInUse) [count].
  int inUseInliers() const;
  /// As `add`, also recording where the estimate in use put the body then (world_T_body), for inUseInliers.
  const FrameInitialization& addInUse(double t, const Eigen::Isometry3d& odom_T_body,
                                      const Eigen::Isometry3d& world_T_body,
                                      const std::vector<GateObservation>& observations);
  /// odom_T_body where the flight starts (the first odometry sample), where the coarse start pose applies.
  void setStartOdometry(const Eigen::Isometry3d& odom_T_body) { start_odom_T_body_ = odom_T_body; }

 private:
  struct Sighting {
    double t;
    int gate_id;
    Eigen::Vector3d p_odom;  ///< gate centre in the odometry frame [m]
    double yaw_odom;         ///< heading of the gate normal in the odometry frame [rad]
    double centre_variance = 0.0;  ///< the PnP's variance of p_odom per axis (trace / 3) [m²]
    bool has_in_use = false;          ///< added with the estimate in use (addInUse)
    Eigen::Vector3d p_in_use = Eigen::Vector3d::Zero();  ///< gate centre where that estimate put it [m, world]
    double yaw_in_use = 0.0;          ///< its normal's heading there [rad]
    int weight = 1;                   ///< detections it stands for (thinned beyond window_s)
    double path_m = 0.0;              ///< the odometry's path length at its instant [m]
  };
  struct Hypothesis {
    double yaw = 0.0;
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    int inliers = 0;  ///< detections it explains
    int gates = 0;    ///< distinct map gates among them (one gate seen again and again fixes neither which
                      ///< gate it is nor the side it was flown from)
    bool operator<(const Hypothesis& other) const {  // better first: more gates, then more detections
      return gates != other.gates ? gates > other.gates : inliers > other.inliers;
    }
  };
  const FrameInitialization& addSightings(double t, const Eigen::Isometry3d& odom_T_body,
                                          const Eigen::Isometry3d* world_T_body,
                                          const std::vector<GateObservation>& observations);
  void search();
  int score(Hypothesis& hypothesis, std::vector<std::pair<size_t, int>>* matches) const;
  /// The map gate a detection at p_world with normal heading yaw_world [rad] may be (−1: none).
  int explainedBy(const Eigen::Vector3d& p_world, double yaw_world, int gate_id) const;
  bool allowedByStart(const Hypothesis& hypothesis) const;
  Hypothesis refine(const Hypothesis& hypothesis) const;
  /// MSAC's cost of a hypothesis over the window: Σ min(d², inlier_distance²) [m²], d an explained detection's
  /// distance from its map gate (the threshold's square for the others).
  double truncatedCost(const Hypothesis& hypothesis) const;
  /// The locked frame's uncertainty (FrameInitialization::centroid_sigma_m, yaw_sigma_rad, centroid_odom).
  void setUncertainty(const std::vector<std::pair<size_t, int>>& inlier_pairs);

  FrameInitializerParams params_;
  GateMap map_;
  /// Ages the window at t: forgets or thins what is older than window_s (memory_m).
  void age(double t);
  /// The distinct map gates among (sighting, gate id) matches.
  static int distinctGates(const std::vector<std::pair<size_t, int>>& matches);

  std::vector<Sighting> window_;
  double path_m_ = 0.0;  ///< odometry path length over the instants added, chord by chord [m]
  double newest_t_ = 0.0;  ///< the newest instant added [s]
  std::optional<Eigen::Vector3d> last_odom_position_;
  std::optional<Eigen::Isometry3d> start_odom_T_body_;
  double last_search_t_ = -1e300;  ///< searches at most every 0.2 s of detections
  FrameInitialization state_;
};

}  // namespace dualgraph
