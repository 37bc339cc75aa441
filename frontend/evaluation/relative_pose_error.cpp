// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/evaluation/relative_pose_error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

// Own names throughout: unity builds join this file with trajectory_metrics.cpp and trajectory_association.cpp.
constexpr double kRpeRadToDeg = 180.0 / EIGEN_PI;

using IndexPairs = std::vector<std::pair<size_t, size_t>>;

/// Path length [m] from pose 0 to each pose along the associated ground truth.
std::vector<double> groundTruthPath(const TrajectoryAssociation& association) {
  std::vector<double> path_m(association.size(), 0.0);
  for (size_t k = 1; k < association.size(); ++k) {
    path_m[k] = path_m[k - 1] + (association.world_T_body_gt[k].second.translation() -
                                 association.world_T_body_gt[k - 1].second.translation())
                                    .norm();
  }
  return path_m;
}

/// kEveryPose in metres: from every i, the first j whose GT path from i reaches Δ. A relative tolerance keeps
/// round-off in the sum from skipping the sample that reaches Δ exactly.
IndexPairs everyPosePairsByDistance(const TrajectoryAssociation& association, double distance_m) {
  const std::vector<double> path_m = groundTruthPath(association);
  const double reach_m = distance_m * (1.0 - 1e-9);
  IndexPairs pairs;
  for (size_t i = 0; i + 1 < association.size(); ++i) {
    const auto reached = std::lower_bound(path_m.begin() + i + 1, path_m.end(), path_m[i] + reach_m);
    if (reached == path_m.end()) break;  // the rest of the path is shorter than Δ, for every later i too
    pairs.emplace_back(i, reached - path_m.begin());
  }
  return pairs;
}

/// kEvo in metres: along the estimate's (scaled) path, the poses where the path since the previous one reaches Δ,
/// paired in succession.
IndexPairs evoPairsByDistance(const TrajectoryAssociation& association, double distance_m, double scale) {
  std::vector<size_t> marks;
  double since_mark_m = 0.0;
  for (size_t k = 1; k < association.size(); ++k) {
    since_mark_m += scale * (association.estimate_T_body[k].second.translation() -
                             association.estimate_T_body[k - 1].second.translation())
                                .norm();
    if (since_mark_m >= distance_m) {
      marks.push_back(k);
      since_mark_m = 0.0;
    }
  }
  IndexPairs pairs;
  for (size_t m = 1; m < marks.size(); ++m) pairs.emplace_back(marks[m - 1], marks[m]);
  return pairs;
}

/// Pairs Δ = `frames` poses apart: from every pose, or consecutive from pose 0.
IndexPairs pairsByFrames(size_t poses, size_t frames, RpePairing pairing) {
  IndexPairs pairs;
  const size_t step = pairing == RpePairing::kEvo ? frames : 1;
  for (size_t i = 0; i + frames < poses; i += step) pairs.emplace_back(i, i + frames);
  return pairs;
}

/// The errors of E = (gt_i⁻¹ gt_j)⁻¹ (est_i⁻¹ est_j) over `pairs`, with their statistics.
RelativePoseError errorsOverPairs(const TrajectoryAssociation& association, const IndexPairs& pairs, double scale) {
  RelativePoseError rpe;
  std::vector<double> translation_m, rotation_deg;
  double sum_translation = 0.0;
  double sum_rotation = 0.0;
  for (const auto& [i, j] : pairs) {
    const Eigen::Isometry3d gt_i_T_j =
        association.world_T_body_gt[i].second.inverse() * association.world_T_body_gt[j].second;
    Eigen::Isometry3d est_i_T_j = association.estimate_T_body[i].second.inverse() * association.estimate_T_body[j].second;
    est_i_T_j.translation() *= scale;
    const Eigen::Isometry3d error = gt_i_T_j.inverse() * est_i_T_j;
    const double angle = so3Log(error.linear()).norm();
    sum_translation += error.translation().squaredNorm();
    sum_rotation += angle * angle;
    translation_m.push_back(error.translation().norm());
    rotation_deg.push_back(angle * kRpeRadToDeg);
  }
  rpe.pairs = static_cast<long>(pairs.size());
  if (pairs.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    rpe.translation_rmse_m = rpe.rotation_rmse_deg = nan;
    rpe.translation_m = rpe.rotation_deg = ErrorStatistics{nan, nan, nan, nan, nan, nan};
    return rpe;
  }
  const double n = static_cast<double>(pairs.size());
  rpe.translation_rmse_m = std::sqrt(sum_translation / n);
  rpe.rotation_rmse_deg = std::sqrt(sum_rotation / n) * kRpeRadToDeg;
  rpe.translation_m = errorStatistics(std::move(translation_m));
  rpe.rotation_deg = errorStatistics(std::move(rotation_deg));
  // One RMSE per window, whichever way it is read (the two sums differ in the last bits).
  rpe.translation_m.rmse = rpe.translation_rmse_m;
  rpe.rotation_deg.rmse = rpe.rotation_rmse_deg;
  return rpe;
}

}  // namespace

ErrorStatistics errorStatistics(std::vector<double> errors) {
  ErrorStatistics s;
  if (errors.empty()) return s;
  const double n = static_cast<double>(errors.size());
  double sum = 0.0, sum_squares = 0.0;
  for (const double e : errors) {
    sum += e;
    sum_squares += e * e;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_squares / n);
  double deviation = 0.0;
  for (const double e : errors) deviation += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(deviation / n);
  std::sort(errors.begin(), errors.end());
  const size_t middle = errors.size() / 2;
  s.median = errors.size() % 2 == 1 ? errors[middle] : 0.5 * (errors[middle - 1] + errors[middle]);
  s.min = errors.front();
  s.max = errors.back();
  return s;
}

const char* rpePairingName(RpePairing pairing) {
  switch (pairing) {
    case RpePairing::kEveryPose: return "every";
    case RpePairing::kEvo: return "evo";
  }
  return "unknown";
}

Result<RpePairing> parseRpePairing(const std::string& name) {
  for (const RpePairing pairing : {RpePairing::kEveryPose, RpePairing::kEvo}) {
    if (name == rpePairingName(pairing)) return pairing;
  }
  return Status(StatusCode::kInvalidArgument, "unknown RPE pairing '" + name + "' (every or evo)");
}

Result<RelativePoseError> relativePoseError(const TrajectoryAssociation& association, double distance_m, double scale,
                                            RpePairing pairing) {
  if (!(std::isfinite(distance_m) && distance_m > 0.0)) {
    return Status(StatusCode::kInvalidArgument,
                  "RPE distance " + formatNumber(distance_m) + " m must be positive and finite");
  }
  const IndexPairs pairs = pairing == RpePairing::kEvo ? evoPairsByDistance(association, distance_m, scale)
                                                       : everyPosePairsByDistance(association, distance_m);
  RelativePoseError rpe = errorsOverPairs(association, pairs, scale);
  rpe.distance_m = distance_m;
  rpe.pairing = pairing;
  return rpe;
}

Result<RelativePoseError> relativePoseErrorFrames(const TrajectoryAssociation& association, long frames, double scale,
                                                  RpePairing pairing) {
  if (frames < 1) {
    return Status(StatusCode::kInvalidArgument, "RPE window of " + std::to_string(frames) + " frames must be at least 1");
  }
  RelativePoseError rpe =
      errorsOverPairs(association, pairsByFrames(association.size(), static_cast<size_t>(frames), pairing), scale);
  rpe.frames = frames;
  rpe.pairing = pairing;
  return rpe;
}

}  // namespace dualgraph
