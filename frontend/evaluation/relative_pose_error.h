// SPDX-License-Identifier: MIT
// Relative pose error over associated poses (windows in metres or in frames, two pairings) and evo's statistics.
#pragma once

#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/evaluation/trajectory_association.h"

namespace dualgraph {

/// evo's statistics of non-negative errors: rmse, mean, median, std (the population's, as numpy's default), min
/// and max, in the errors' unit.
struct ErrorStatistics {
  double rmse = 0.0, mean = 0.0, median = 0.0, std = 0.0, min = 0.0, max = 0.0;
};
/// Those statistics of any non-negative errors (all zero when `errors` is empty).
ErrorStatistics errorStatistics(std::vector<double> errors);

/// Which pairs (i, j), i < j over the associated poses, an RPE window takes.
enum class RpePairing {
  /// One pair from every pose i. Frames: j = i + Δ (evo's `--all_pairs`). Metres: j the first pose at which the
  /// ground truth's path length from i (the sum of the straight segments between consecutive associated GT
  /// positions) reaches Δ, none once the rest of the path is shorter (as rpg_trajectory_evaluation, but the
  /// first pose reaching Δ rather than the closest).
  kEveryPose,
  /// evo_rpe's default (`all_pairs` off): consecutive pairs that do not overlap. Frames: (0, Δ), (Δ, 2Δ), …
  /// Metres: along the estimate's path (its segments times the alignment's scale) from pose 0, the poses at
  /// which the path since the previous such pose (pose 0 for the first, which is not one) reaches Δ; each pair
  /// two successive such poses.
  kEvo,
};
/// "every" or "evo".
const char* rpePairingName(RpePairing pairing);
/// The inverse of rpePairingName; kInvalidArgument naming the text otherwise.
Result<RpePairing> parseRpePairing(const std::string& name);

/// Relative pose error over one window Δ: for each pair (i, j), as TUM's RPE (Sturm et al. 2012) and evo's
/// E = (gt_i⁻¹ gt_j)⁻¹ (est_i⁻¹ est_j), the translational error |t(E)| = |t(est_i⁻¹ est_j) − t(gt_i⁻¹ gt_j)|
/// [m] and the rotational error the angle of R(E) [deg]. Alignment-free: any fixed world_T_estimate cancels; a
/// scale does not, so `scale` multiplies the estimate's relative translations (kSim3's, as evo's RPE after
/// `-as`). With no pairs the figures are NaN.
struct RelativePoseError {
  double distance_m = 0.0;         ///< Δ [m]; 0 for a window in frames
  long frames = 0;                 ///< Δ [associated poses] (evo's delta_unit f); 0 for a window in metres
  RpePairing pairing = RpePairing::kEveryPose;  ///< how the pairs were chosen
  long pairs = 0;                  ///< number of pairs (i, j)
  double translation_rmse_m = 0.0;  ///< RMSE of |t(E)| [m] (= translation_m.rmse)
  double rotation_rmse_deg = 0.0;   ///< RMSE of angle(R(E)) [deg] (= rotation_deg.rmse)
  ErrorStatistics translation_m;    ///< statistics of |t(E)| over the pairs [m]
  ErrorStatistics rotation_deg;     ///< statistics of angle(R(E)) over the pairs [deg]
};

/// The RPE over Δ = `distance_m` [m] of path (> 0 and finite, else kInvalidArgument).
Result<RelativePoseError> relativePoseError(const TrajectoryAssociation& association, double distance_m,
                                            double scale = 1.0, RpePairing pairing = RpePairing::kEveryPose);

/// The RPE over Δ = `frames` associated poses (≥ 1, else kInvalidArgument); frames 1 is evo_rpe's default.
Result<RelativePoseError> relativePoseErrorFrames(const TrajectoryAssociation& association, long frames,
                                                  double scale = 1.0, RpePairing pairing = RpePairing::kEveryPose);

}  // namespace dualgraph
