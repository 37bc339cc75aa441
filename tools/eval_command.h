// SPDX-License-Identifier: MIT
// `dualgraph eval`: an estimate against ground truth (ATE, RPE with evo's statistics), optionally as JSON.
#pragma once

#include <string>
#include <vector>

namespace dualgraph::tools {

/// Options of `dualgraph eval`: an estimate (estimate_T_body) against ground truth (world_T_body), each a TUM
/// file (t in s, covariance columns ignored), an OpenVINS traj_estimate or a EuRoC/ASL CSV (t in ns), recognised
/// from its content (readTrajectory, frontend/io/odometry_io.h); m. Every figure uses the one alignment asked for.
struct EvalOptions {
  std::string gt;           ///< ground-truth file
  std::string est;          ///< estimate file
  std::string align = "se3";  ///< se3, sim3, 4dof, origin or none: the alignment of every figure
  std::string json;         ///< write the metrics here as one JSON object (atomically) when set
  /// interpolated, nearest (from every estimate pose) or evo (from the trajectory with fewer poses, as evo_ape);
  /// empty: nearest when max_dt_s > 0, else interpolated.
  std::string association;
  double max_gap_s = 0.1;   ///< association gap [s] (interpolated ground truth)
  double max_dt_s = 0.0;    ///< nearest / evo: the largest |Δt| of a pair [s]; 0: evo's 0.01 s (> 0 alone: nearest)
  std::vector<double> rpe_distances_m{1.0, 10.0};  ///< RPE windows [m of path]
  std::vector<long> rpe_frames;                    ///< RPE windows [associated poses] (evo_rpe's default: 1)
  std::string rpe_pairs = "every";  ///< every (a pair from each pose) or evo (evo_rpe's consecutive pairs)
  /// Below this share of the estimate's poses with ground truth: an error naming both files' time spans.
  double min_associated = 0.5;
};

/// Runs it; returns the process exit code (0 ok, 1 bad input or no usable overlap).
int runEvalCommand(const EvalOptions& options);

}  // namespace dualgraph::tools
