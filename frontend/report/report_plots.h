// SPDX-License-Identifier: MIT
// The report's plots beyond Fig. 3 and the error plots (error_plots.h): latency distributions of the two graphs,
// the overlay of several runs on one time base, and the helpers they share. No I/O, no printing.
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
#include "dualgraph/frontend/report/error_plots.h"
#include "dualgraph/frontend/report/xy_plot.h"

namespace dualgraph {

/// A distinct colour for the k-th run of an overlay (cycles after ten).
std::array<std::uint8_t, 3> runColour(size_t k);

/// The empirical distribution (fraction of keyframes at or below x ms) of each named set of durations [ms].
/// Sets without values are left out.
XyPlot latencyDistribution(const std::string& title,
                           const std::vector<std::pair<std::string, std::vector<double>>>& durations_ms);

/// The origin of a run's time axes [s]: 0 when its stamps are small (simulation starts at 0), else the flight's
/// first stamp, the VIO's (recorded data carry Unix times; the estimate's when there is no VIO).
double reportTimeOrigin(const RunReport& run);

/// The one origin of several runs' time axes [s]: the earliest of their reportTimeOrigin, so that overlaid runs
/// share a time base. 0 without runs.
double sharedTimeOrigin(const std::vector<RunReport>& runs);

/// A time axis' label: "t [s]", or "t [s] since <t0> s" when t0 ≠ 0.
std::string timeAxisLabel(double t0);

/// The x, y of every pose [m].
std::vector<Eigen::Vector2d> xyOf(const StampedPoses& poses);

/// The values of (t, value) pairs.
std::vector<double> valuesOf(const std::vector<std::pair<double, double>>& series);

/// Several runs at once: their corrected trajectories over one top view with the first run's ground truth and
/// gates, their position errors over one time axis (sharedTimeOrigin), and their main-graph latency distributions.
struct OverlayPlots {
  XyPlot xy;       ///< [m]
  XyPlot error;    ///< [s, m]; no series without ground truth
  XyPlot latency;  ///< [ms, fraction]
};

/// The overlay of `runs` (≥ 2). Errors of positionErrors, naming the run.
Result<OverlayPlots> makeOverlayPlots(const std::vector<RunReport>& runs);

}  // namespace dualgraph
