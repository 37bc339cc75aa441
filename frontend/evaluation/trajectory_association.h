// SPDX-License-Identifier: MIT
// Pairing an estimate with ground truth by time stamp: interpolated, nearest stamp from the estimate, or evo's.
#pragma once

#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/io/trajectory_io.h"

namespace dualgraph {

/// Estimate poses paired with ground-truth poses by time stamp, in time order. Every pose of the trajectory the
/// pairs are made from (the estimate, or with associateAsEvo the one with fewer poses) is either associated or
/// counted in exactly one of the three counters.
struct TrajectoryAssociation {
  std::vector<size_t> estimate_index;      ///< index into the estimate of each pair
  std::vector<size_t> ground_truth_index;  ///< index into the ground truth of each pair (nearest-stamp modes only)
  StampedPoses world_T_body_gt;            ///< the ground truth of each pair [s, m]
  StampedPoses estimate_T_body;            ///< the estimate pose of each pair [s, m]
  bool paired_from_ground_truth = false;  ///< associateAsEvo with fewer ground-truth poses: the counters count GT poses
  long paired_from_poses = 0;  ///< poses of the trajectory the pairs are made from (associated + unassociated)
  long before_span = 0;  ///< stamps earlier than the other trajectory's first (less max_dt_s for nearest stamps)
  long after_span = 0;   ///< stamps later than the other trajectory's last (plus max_dt_s for nearest stamps)
  long beyond_gap = 0;   ///< inside that span, but no sample of the other close enough

  size_t size() const { return estimate_index.size(); }
  long unassociated() const { return before_span + after_span + beyond_gap; }
};

/// Pairs every estimate pose whose stamp lies inside the GT span [t_first, t_last] and has a GT sample within
/// `max_gap_s` [s] (inclusive) with the ground truth interpolated at its stamp: translation linearly, rotation
/// by slerp (the GT entry carries the estimate's stamp). Errors: kInvalidArgument when either trajectory is
/// empty, a stamp or pose is not finite, a rotation is not a rotation, stamps do not strictly increase, or
/// max_gap_s is not positive and finite (each naming the trajectory and index); kFailedPrecondition when no
/// estimate stamp lies inside the GT span (the two spans are quoted) or none has GT within the gap.
Result<TrajectoryAssociation> associateByTime(const StampedPoses& world_T_body_gt,
                                              const StampedPoses& estimate_T_body, double max_gap_s = 0.1);

/// Every estimate pose paired with the ground-truth sample of the nearest stamp (not interpolated) when it lies
/// within `max_dt_s` [s] (inclusive; ties to the earlier sample); the GT entry carries the estimate's stamp.
/// Pairs from every estimate pose, so a ground-truth sample serves several when the estimate is the denser;
/// associateAsEvo is evo's pairing. Stamps outside the GT span by more than max_dt_s count as before/after the
/// span, the others without a sample that close as beyond the gap. Errors as associateByTime.
Result<TrajectoryAssociation> associateByNearestStamp(const StampedPoses& world_T_body_gt,
                                                      const StampedPoses& estimate_T_body, double max_dt_s);

/// evo's association (evo_ape / evo_rpe `--t_max_diff`, evo.core.sync.associate_trajectories, nearest_time): for
/// each stamp of the trajectory with fewer poses (the estimate when both have as many), in time order, the pose
/// of the other at the nearest stamp (ties to the earlier), paired when |Δt| ≤ `max_diff_s` [s]. Each pose of the
/// sparser trajectory is used at most once; as in evo, a pose of the denser one may serve two pairs when two
/// sparse stamps have it as their nearest. Each entry keeps its own stamp. The counters count the sparser
/// trajectory's poses (paired_from_ground_truth says which): before/after the other's span by more than
/// max_diff_s, or inside it without a stamp that close. evo's `--t_offset` is not applied. Errors as
/// associateByTime (max_diff_s positive and finite).
Result<TrajectoryAssociation> associateAsEvo(const StampedPoses& world_T_body_gt, const StampedPoses& estimate_T_body,
                                             double max_diff_s = 0.01);

}  // namespace dualgraph
