// SPDX-License-Identifier: MIT
// The report's plots beyond Fig. 3: position errors with their statistics, the top view coloured by error,
// latency distributions of the two graphs, and the overlay of several runs. No I/O, no printing.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
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

/// A distinct colour for the k-th run of an overlay (cycles after ten).
std::array<std::uint8_t, 3> runColour(size_t k);

/// The top view with the trajectory coloured by its error: five bins between the minimum and the maximum
/// error (dark blue to red, one legend entry each, "0.02-0.05" in metres, the unit in the title), the ground truth
/// dashed under them, gates grey.
XyPlot errorColouredTopView(const std::string& title, const PositionErrors& errors, const StampedPoses& ground_truth,
                            const std::vector<TrackGate>& gates);

/// The empirical distribution (fraction of keyframes at or below x ms) of each named set of durations [ms].
/// Sets without values are left out.
XyPlot latencyDistribution(const std::string& title,
                           const std::vector<std::pair<std::string, std::vector<double>>>& durations_ms);

/// The origin of a run's time axes [s]: 0 when its stamps are small (simulation starts at 0), else the first
/// estimate stamp (recorded data carry Unix times).
double reportTimeOrigin(const RunReport& run);

/// The x, y of every pose [m].
std::vector<Eigen::Vector2d> xyOf(const StampedPoses& poses);

/// The values of (t, value) pairs.
std::vector<double> valuesOf(const std::vector<std::pair<double, double>>& series);

/// Several runs at once: their corrected trajectories over one top view with the first run's ground truth and
/// gates, their position errors over time, and their main-graph latency distributions.
struct OverlayPlots {
  XyPlot xy;       ///< [m]
  XyPlot error;    ///< [s, m]; no series without ground truth
  XyPlot latency;  ///< [ms, fraction]
};

/// The overlay of `runs` (≥ 2). Errors of positionErrors, naming the run.
Result<OverlayPlots> makeOverlayPlots(const std::vector<RunReport>& runs);

}  // namespace dualgraph
