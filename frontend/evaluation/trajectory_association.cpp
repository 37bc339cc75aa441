// SPDX-License-Identifier: MIT
// Association of an estimate with ground truth by time stamp: interpolated (associateByTime), nearest stamp
// from the estimate (associateByNearestStamp) or from the sparser trajectory (associateAsEvo).
#include <algorithm>
#include <cmath>
#include <string>

#include "dualgraph/frontend/evaluation/trajectory_association.h"
#include "dualgraph/types/se3_covariance.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

/// "[first, last] s" of a non-empty trajectory, for messages.
std::string spanText(const StampedPoses& poses) {
  return "[" + formatTimestamp(poses.front().first) + ", " + formatTimestamp(poses.back().first) + "] s";
}

/// Finite stamps in strictly increasing order and finite rigid poses; `what` names the trajectory.
Status validateTrajectory(const StampedPoses& poses, const std::string& what) {
  if (poses.empty()) return Status(StatusCode::kInvalidArgument, what + " is empty");
  for (size_t i = 0; i < poses.size(); ++i) {
    const std::string where = what + ": pose " + std::to_string(i);
    const double t = poses[i].first;
    if (!std::isfinite(t)) return Status(StatusCode::kInvalidArgument, where + ": time stamp is not finite");
    DG_RETURN_IF_ERROR(checkRigidTransform(poses[i].second, where + " (t = " + formatTimestamp(t) + " s)"));
    if (i > 0 && !(t > poses[i - 1].first)) {
      return Status(StatusCode::kInvalidArgument, where + ": time stamp " + formatTimestamp(t) +
                                                      " s does not increase (previous " +
                                                      formatTimestamp(poses[i - 1].first) + " s)");
    }
  }
  return Status();
}

/// Translation linear, rotation by slerp (shortest arc), alpha ∈ [0, 1].
Eigen::Isometry3d interpolateLinearSlerp(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double alpha) {
  const Eigen::Quaterniond q_a(a.linear());
  const Eigen::Quaterniond q_b(b.linear());
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = q_a.slerp(alpha, q_b).normalized().toRotationMatrix();
  out.translation() = (1.0 - alpha) * a.translation() + alpha * b.translation();
  return out;
}

/// The association, or kFailedPrecondition when the two do not overlap in time or nothing was paired (`what`: the
/// condition no pose of the trajectory paired from met, for the message).
Result<TrajectoryAssociation> nonEmpty(TrajectoryAssociation association, const StampedPoses& world_T_body_gt,
                                       const StampedPoses& estimate_T_body, const std::string& what) {
  if (association.before_span + association.after_span == association.paired_from_poses) {
    return Status(StatusCode::kFailedPrecondition, "the estimate " + spanText(estimate_T_body) +
                                                       " does not overlap the ground truth " +
                                                       spanText(world_T_body_gt) + " in time");
  }
  if (association.size() == 0) {
    const std::string paired = association.paired_from_ground_truth ? "ground-truth" : "estimate";
    const std::string other = association.paired_from_ground_truth ? "the estimate's" : "the ground truth's";
    return Status(StatusCode::kFailedPrecondition, "no " + paired + " pose has " + what + " (" +
                                                       std::to_string(association.beyond_gap) + " inside " + other +
                                                       " span)");
  }
  return association;
}

/// The index of the stamp in `poses` (strictly increasing, not empty) nearest to t; ties to the earlier one.
size_t nearestStamp(const StampedPoses& poses, double t) {
  const auto after = std::lower_bound(poses.begin(), poses.end(), t,
                                      [](const auto& sample, double value) { return sample.first < value; });
  size_t nearest = after == poses.end() ? poses.size() - 1 : after - poses.begin();
  if (nearest > 0 && t - poses[nearest - 1].first <= std::abs(poses[nearest].first - t)) --nearest;
  return nearest;
}

/// kInvalidArgument unless `max_dt_s` is positive and finite.
Status checkMaxTimeDifference(double max_dt_s) {
  if (std::isfinite(max_dt_s) && max_dt_s > 0.0) return Status();
  return Status(StatusCode::kInvalidArgument,
                "maximum time difference " + formatNumber(max_dt_s) + " s must be positive and finite");
}

}  // namespace

Result<TrajectoryAssociation> associateByTime(const StampedPoses& world_T_body_gt,
                                              const StampedPoses& estimate_T_body, double max_gap_s) {
  DG_RETURN_IF_ERROR(validateTrajectory(world_T_body_gt, "ground truth"));
  DG_RETURN_IF_ERROR(validateTrajectory(estimate_T_body, "estimate"));
  if (!(std::isfinite(max_gap_s) && max_gap_s > 0.0)) {
    return Status(StatusCode::kInvalidArgument, "maximum gap " + formatNumber(max_gap_s) + " s must be positive and finite");
  }
  const double t_first = world_T_body_gt.front().first;
  const double t_last = world_T_body_gt.back().first;
  TrajectoryAssociation association;
  association.paired_from_poses = static_cast<long>(estimate_T_body.size());
  for (size_t i = 0; i < estimate_T_body.size(); ++i) {
    const double t = estimate_T_body[i].first;
    if (t < t_first) {
      ++association.before_span;
      continue;
    }
    if (t > t_last) {
      ++association.after_span;
      continue;
    }
    // The GT samples k0 ≤ k1 around t: t(k0) ≤ t ≤ t(k1), k0 = k1 only at the last sample.
    const auto after = std::upper_bound(world_T_body_gt.begin(), world_T_body_gt.end(), t,
                                        [](double value, const auto& sample) { return value < sample.first; });
    const size_t k1 = after == world_T_body_gt.end() ? world_T_body_gt.size() - 1 : after - world_T_body_gt.begin();
    const size_t k0 = after == world_T_body_gt.end() ? k1 : k1 - 1;
    const double t0 = world_T_body_gt[k0].first;
    const double t1 = world_T_body_gt[k1].first;
    if (std::min(t - t0, t1 - t) > max_gap_s) {
      ++association.beyond_gap;
      continue;
    }
    const double alpha = k1 == k0 ? 0.0 : (t - t0) / (t1 - t0);
    association.estimate_index.push_back(i);
    association.world_T_body_gt.emplace_back(
        t, interpolateLinearSlerp(world_T_body_gt[k0].second, world_T_body_gt[k1].second, alpha));
    association.estimate_T_body.push_back(estimate_T_body[i]);
  }
  return nonEmpty(std::move(association), world_T_body_gt, estimate_T_body,
                  "a ground-truth sample within the maximum gap of " + formatNumber(max_gap_s) + " s");
}

Result<TrajectoryAssociation> associateByNearestStamp(const StampedPoses& world_T_body_gt,
                                                      const StampedPoses& estimate_T_body, double max_dt_s) {
  DG_RETURN_IF_ERROR(validateTrajectory(world_T_body_gt, "ground truth"));
  DG_RETURN_IF_ERROR(validateTrajectory(estimate_T_body, "estimate"));
  DG_RETURN_IF_ERROR(checkMaxTimeDifference(max_dt_s));
  const double t_first = world_T_body_gt.front().first;
  const double t_last = world_T_body_gt.back().first;
  TrajectoryAssociation association;
  association.paired_from_poses = static_cast<long>(estimate_T_body.size());
  for (size_t i = 0; i < estimate_T_body.size(); ++i) {
    const double t = estimate_T_body[i].first;
    if (t < t_first - max_dt_s) {
      ++association.before_span;
      continue;
    }
    if (t > t_last + max_dt_s) {
      ++association.after_span;
      continue;
    }
    const size_t nearest = nearestStamp(world_T_body_gt, t);
    if (std::abs(world_T_body_gt[nearest].first - t) > max_dt_s) {
      ++association.beyond_gap;
      continue;
    }
    association.estimate_index.push_back(i);
    association.ground_truth_index.push_back(nearest);
    association.world_T_body_gt.emplace_back(t, world_T_body_gt[nearest].second);
    association.estimate_T_body.push_back(estimate_T_body[i]);
  }
  return nonEmpty(std::move(association), world_T_body_gt, estimate_T_body,
                  "a ground-truth stamp within " + formatNumber(max_dt_s) + " s");
}

Result<TrajectoryAssociation> associateAsEvo(const StampedPoses& world_T_body_gt, const StampedPoses& estimate_T_body,
                                             double max_diff_s) {
  DG_RETURN_IF_ERROR(validateTrajectory(world_T_body_gt, "ground truth"));
  DG_RETURN_IF_ERROR(validateTrajectory(estimate_T_body, "estimate"));
  DG_RETURN_IF_ERROR(checkMaxTimeDifference(max_diff_s));
  TrajectoryAssociation association;
  association.paired_from_ground_truth = estimate_T_body.size() > world_T_body_gt.size();
  const StampedPoses& sparse = association.paired_from_ground_truth ? world_T_body_gt : estimate_T_body;
  const StampedPoses& dense = association.paired_from_ground_truth ? estimate_T_body : world_T_body_gt;
  association.paired_from_poses = static_cast<long>(sparse.size());
  for (size_t i = 0; i < sparse.size(); ++i) {
    const double t = sparse[i].first;
    const size_t k = nearestStamp(dense, t);
    if (std::abs(dense[k].first - t) <= max_diff_s) {
      const size_t gt = association.paired_from_ground_truth ? i : k;
      const size_t est = association.paired_from_ground_truth ? k : i;
      association.estimate_index.push_back(est);
      association.ground_truth_index.push_back(gt);
      association.world_T_body_gt.push_back(world_T_body_gt[gt]);
      association.estimate_T_body.push_back(estimate_T_body[est]);
    } else if (t < dense.front().first - max_diff_s) {
      ++association.before_span;
    } else if (t > dense.back().first + max_diff_s) {
      ++association.after_span;
    } else {
      ++association.beyond_gap;
    }
  }
  const std::string what = (association.paired_from_ground_truth ? "an estimate" : "a ground-truth") +
                           std::string(" stamp within ") + formatNumber(max_diff_s) + " s";
  return nonEmpty(std::move(association), world_T_body_gt, estimate_T_body, what);
}

}  // namespace dualgraph
