// SPDX-License-Identifier: MIT
// The report's error plots: position errors against ground truth, the VIO put in the map through the frame
// found at the lock, evo-style error-over-time plots (rmse, mean, median, ±std) and the top view coloured by error.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/evaluation/run_folder.h"
#include "dualgraph/frontend/evaluation/trajectory_metrics.h"
#include "dualgraph/frontend/report/xy_plot.h"

namespace dualgraph {

/// Position errors |p_gt − p| [m] of a trajectory at its own stamps (ground truth interpolated, no alignment:
/// the map frame is the one that matters onboard).
struct PositionErrors {
  std::vector<Eigen::Vector2d> over_time;  ///< (t − t0 [s], error [m])
  std::vector<Eigen::Vector2d> xy;         ///< the trajectory's x, y [m] at the same stamps
  std::vector<double> errors;              ///< the errors alone [m]
  ErrorStatistics stats;                   ///< evo's statistics of `errors` [m]
};

/// The errors of `poses` against `ground_truth` (associateByTime's errors, e.g. no overlap).
Result<PositionErrors> positionErrors(const StampedPoses& ground_truth, const StampedPoses& poses, double t0);

/// evo's statistics of the position errors after an SE(3) alignment (Umeyama, as `evo_ape -a`) [m]; every field
/// NaN when the association or the alignment fails (e.g. fewer than 3 poses).
ErrorStatistics alignedErrorStatistics(const StampedPoses& ground_truth, const StampedPoses& poses);

/// Which frame the report draws the VIO in.
enum class VioFrame {
  kLock,  ///< through the frame the run found at its first lock (metrics.json lock_world_T_odom_*), when it has one
  kRaw,   ///< as the VIO gave it, in its own frame
};
/// "lock" or "raw".
const char* vioFrameName(VioFrame frame);
/// The inverse of vioFrameName; kInvalidArgument naming the text otherwise.
Result<VioFrame> parseVioFrame(const std::string& name);

/// The VIO as the report draws it.
struct VioForReport {
  StampedPoses poses;         ///< lock_world_T_odom · odom_T_body, or odom_T_body as read [s, m]
  bool through_lock = false;  ///< whether the lock frame was applied
  std::string label;          ///< the legend's: "VIO (lock frame)" or "VIO (raw)"
  std::string note;           ///< a caption's sentence saying which frame, and why when raw
};

/// `run.vio` in the frame asked for: through run.lock_world_T_odom with kLock when the run has one, else raw (the
/// note then says the run never locked or its metrics.json has no lock frame). The note gives the lock's time
/// from `t0` [s] (the plots' time origin).
VioForReport vioForReport(const RunReport& run, VioFrame frame, double t0);

/// evo_ape's plot of one error series [s, m]: the errors over time in `rgb`, horizontal lines at their rmse (red),
/// mean (green) and median (purple), and the band mean ± std (grey); each labelled with its value [m].
XyPlot errorOverTime(const std::string& title, const std::string& label, const PositionErrors& errors,
                     const std::array<std::uint8_t, 3>& rgb);

/// The top view with the trajectory coloured by its error: each segment in colourMapRgb of its first point's error
/// between the minimum and the maximum (64 levels, unlabelled series), a ColourBar "error [m]" over that range,
/// the ground truth dashed under them (the legend's one entry), gates grey.
XyPlot errorColouredTopView(const std::string& title, const PositionErrors& errors, const StampedPoses& ground_truth,
                            const std::vector<TrackGate>& gates);

}  // namespace dualgraph
