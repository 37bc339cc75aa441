// SPDX-License-Identifier: MIT
// GateAssociator: gate detections matched to map gates (Hungarian), new gates in mapping mode.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/gate_map.h"
#include "dualgraph/dual_graph/measurements.h"

namespace dualgraph {

/// Thresholds of `GateAssociator` (frontend/gates/README.md).
struct AssociationParams {
  double max_distance = 2.0;        ///< gate: detection centre within this of the map gate centre, world frame [m]
  double max_normal_angle = 0.7;    ///< orientation check: angle between the detection's and the map gate's normal [rad]
  bool allow_reversed = true;       ///< a square gate seen from behind matches after a 180° turn about its vertical (z) axis
  int mapping_min_sightings = 3;    ///< mapping mode: consistent sightings before a new landmark
  double mapping_consistency = 0.5; ///< [m] sightings within this of each other count as the same new gate
};

/// kInvalidArgument naming the field unless max_distance and mapping_consistency are finite and > 0,
/// max_normal_angle ∈ [0, π] and mapping_min_sightings ≥ 1.
Status validateAssociationParams(const AssociationParams& params);

/// What happened to one detection.
enum class AssociationOutcome {
  kAssigned,             ///< matched a map gate as seen (front side)
  kAssignedReversed,     ///< matched a map gate seen from behind; the pose was turned by Rz(π)
  kRejectedDistance,     ///< no map gate within max_distance (also: empty map)
  kRejectedOrientation,  ///< map gates within max_distance, but none passes the normal check
  kUnassigned,           ///< had candidate gates, but another detection took them (duplicate sighting)
  kNewLandmarkPending,   ///< mapping mode: counted as a sighting of a not yet confirmed new gate
  kNewLandmark,          ///< mapping mode: this sighting confirmed a new gate, now in the map
};

/// "Assigned", "RejectedDistance", ...
const char* associationOutcomeName(AssociationOutcome outcome);

/// One result per detection, in the detections' order. `observation` is the detection with `gate_id`
/// set (−1 when not associated); for kAssignedReversed (and a reversed kNewLandmark) its `body_T_gate`
/// is the detection's · Rz(π) and its pose covariance is expressed in that turned gate frame, so it
/// agrees with the map gate's orientation. The PnP stage uses the reversed flag to swap the corners'
/// left/right (`reversed`).
struct AssociationResult {
  AssociationOutcome outcome = AssociationOutcome::kUnassigned;
  int gate_id = -1;
  GateObservation observation;
  bool reversed = false;  ///< the pose was turned by Rz(π) (kAssignedReversed, or a kNewLandmark seen from behind)
  bool mirrored = false;  ///< the detection's alternative pose (its mirrored tilt) agreed with the gate and was taken

  bool associated() const {
    return outcome == AssociationOutcome::kAssigned || outcome == AssociationOutcome::kAssignedReversed ||
           outcome == AssociationOutcome::kNewLandmark;
  }

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Associates unlabelled gate detections (`gate_id` is ignored) with the gates of a map.
///
/// Each detection is placed in the world with `world_T_body` (the current corrected pose). The cost of
/// detection i and gate j is the Euclidean distance between the detection's centre and the gate's
/// centre in the world frame [m]; the pair is forbidden when that distance exceeds max_distance, or
/// — for kPose detections — when the angle between the normals (gate-frame x axes) exceeds
/// max_normal_angle and, with allow_reversed, so does the angle to the flipped normal (π − angle).
/// When both pass (max_normal_angle ≥ π/2) the smaller angle decides. kPosition detections carry no
/// orientation and are gated on distance only. A kPose detection with an alternative (GateObservation::
/// has_alternative: a PnP's mirrored tilt) that its returned pose pairs with some gate is also paired on the
/// alternative: where both pass, the one whose normal is nearer the gate's holds the pair; the alternative alone may
/// pair where the returned pose fails (a wrong tilt fails its own gate and can pass a neighbour's). A pair held by
/// the alternative costs its distance, and the result's observation takes it as its pose (withAlternativeTaken;
/// `mirrored`). A detection the returned pose pairs nowhere stays refused: under a wrong frame, twice the chances
/// to pass would confirm the frame. The Hungarian assignment (`solveAssignment`)
/// then gives each gate at most one detection and each detection at most one gate, assigning as many detections
/// as possible, then minimising the summed distance.
///
/// Mapping mode (`associateMapping`) tracks detections with no map gate within max_distance across
/// calls as candidates in the world frame. A sighting belongs to a candidate when its centre is within
/// mapping_consistency of the candidate's mean centre and its normal passes the same orientation check
/// against the candidate's first normal; at most one sighting per candidate per call counts. After
/// mapping_min_sightings sightings the candidate becomes a map gate with id max(existing ids) + 1 (0 in
/// an empty map) and as pose the mean of its sightings (centres averaged; rotations of pose sightings,
/// each turned by Rz(π) when seen from the other side, averaged as quaternions; identity when all were
/// positions). Candidates are kept until confirmed or `resetMapping()`.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class GateAssociator {
 public:
  explicit GateAssociator(const AssociationParams& params = AssociationParams()) : params_(params) {}

  const AssociationParams& params() const { return params_; }

  /// Localisation mode: unassociated detections are reported and dropped. kInvalidArgument for invalid
  /// params, a non-rigid or non-finite `world_T_body`, map gate or detection pose (naming which).
  Result<std::vector<AssociationResult>> associate(const Eigen::Isometry3d& world_T_body,
                                                   std::vector<GateObservation> detections,
                                                   const GateMap& map) const;

  /// Mapping mode: as `associate`, then detections rejected for distance feed the candidates; a
  /// confirmed candidate is inserted into `map` and reported as kNewLandmark with its new id.
  Result<std::vector<AssociationResult>> associateMapping(const Eigen::Isometry3d& world_T_body,
                                                          std::vector<GateObservation> detections,
                                                          GateMap& map);

  /// Number of unconfirmed candidate gates being tracked.
  size_t pendingCandidates() const { return candidates_.size(); }
  /// Forgets all candidates.
  void resetMapping() { candidates_.clear(); }

 private:
  /// Sightings of one possible new gate, world frame.
  struct Candidate {
    Eigen::Vector3d centre_sum = Eigen::Vector3d::Zero();
    int sightings = 0;
    bool has_normal = false;
    Eigen::Vector3d first_normal = Eigen::Vector3d::UnitX();
    Eigen::Vector4d quaternion_sum = Eigen::Vector4d::Zero();  ///< [x y z w] of aligned rotations
    Eigen::Vector3d meanCentre() const { return centre_sum / sightings; }
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };

  /// Counts a sighting (centre, and world_R_gate when `has_normal`) and marks the result pending.
  static void addSighting(Candidate& candidate, const Eigen::Vector3d& centre, const Eigen::Matrix3d& world_R_gate,
                          bool has_normal, AssociationResult& result);
  /// The mean pose of a candidate's sightings.
  static Eigen::Isometry3d candidatePose(const Candidate& candidate);

  AssociationParams params_;
  std::vector<Candidate, Eigen::aligned_allocator<Candidate>> candidates_;
};

}  // namespace dualgraph
