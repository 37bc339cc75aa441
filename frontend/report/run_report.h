// SPDX-License-Identifier: MIT
// The report of one or more `dualgraph run` folders: the paper's Fig. 3 (XY trajectories with the
// gates), position error and optimisation time over time, and the metrics — as one self-contained
// HTML page (inline SVG and CSS, no scripts, nothing fetched) and as PNG files. No printing.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/evaluation/run_folder.h"
#include "dualgraph/frontend/report/error_plots.h"
#include "dualgraph/frontend/report/report_plots.h"
#include "dualgraph/frontend/report/xy_plot.h"

namespace dualgraph {

/// What the report draws beyond the run folders' content.
struct RunReportOptions {
  VioFrame vio_frame = VioFrame::kLock;  ///< the VIO through the frame found at the lock, or raw
};

/// The plots of a run. The error plots are empty (no series) without ground truth.
struct RunPlots {
  XyPlot xy;               ///< Fig. 3: ground truth dashed black, VIO orange, corrected blue, gates grey; equal axes [m]
  XyPlot error;            ///< |p_gt − p| of the corrected estimate and of the VIO as drawn, no alignment, over time [s, m]
  XyPlot error_corrected;  ///< the corrected estimate's error alone, evo-style (errorOverTime) [s, m]
  XyPlot error_vio;        ///< the VIO's error alone (as drawn), evo-style [s, m]
  XyPlot error_map;        ///< the top view coloured by the corrected estimate's error, with a colour bar [m]
  XyPlot opt_ms;           ///< main-graph optimisation time per keyframe over time [s, ms]
  XyPlot latency;          ///< distributions of the main- and temporary-graph times per keyframe [ms]
  bool has_errors = false;
  VioForReport vio;        ///< the VIO as drawn (poses, frame, label, the captions' note)
  double time_origin = 0.0;  ///< of the time axes [s] (reportTimeOrigin)
  ErrorStatistics corrected_stats, vio_stats;          ///< of the two error series, no alignment [m]
  ErrorStatistics corrected_stats_se3, vio_stats_se3;  ///< the same after SE(3) alignment (alignedErrorStatistics) [m]
};

/// Builds the plots. Errors only from associating the estimates with the ground truth by time
/// (associateByTime, e.g. no overlap), naming both files.
Result<RunPlots> makeRunPlots(const RunReport& run, const RunReportOptions& options = {});

/// The HTML page for `runs` (≥ 1): with several, a comparison table and their overlay (report_plots.h); then per
/// run a section with its plots as inline SVG (polylines simplified within 0.25 px), the error statistics without
/// and with SE(3) alignment, the latency percentiles, the metrics table and the per-lap gate corrections.
/// kInvalidArgument without runs; makeRunPlots' errors.
Result<std::string> renderRunReportHtml(const std::vector<RunReport>& runs, const RunReportOptions& options = {});

/// Writes renderRunReportHtml(runs) to `html_path` and, in the same folder, `<name>_xy.png`, `<name>_error.png`,
/// `<name>_error_corrected.png`, `<name>_error_vio.png`, `<name>_error_map.png` (those four with ground truth),
/// `<name>_opt_ms.png` and
/// `<name>_latency.png` per run, and `overlay_xy.png`, `overlay_error.png`, `overlay_latency.png` for several
/// runs, every file atomically.
/// Run names are first made file-name safe and unique (`_2`, `_3`, ...). `written` (optional)
/// receives the paths written. kInvalidArgument without runs; kIoError naming the file that failed.
Status writeRunReport(std::vector<RunReport> runs, const std::string& html_path,
                      std::vector<std::string>* written = nullptr, const RunReportOptions& options = {});

}  // namespace dualgraph
