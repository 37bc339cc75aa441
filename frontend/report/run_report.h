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
#include "dualgraph/frontend/report/xy_plot.h"

namespace dualgraph {

/// The three plots of a run. `error` is empty (no series) without ground truth.
struct RunPlots {
  XyPlot xy;      ///< Fig. 3: ground truth dashed black, VIO orange, corrected blue, gates grey; equal axes [m]
  XyPlot error;   ///< |p_gt − p| of the corrected estimate and of VIO, unaligned, over time [s, m]
  XyPlot opt_ms;  ///< main-graph optimisation time per keyframe over time [s, ms]
};

/// Builds the plots. Errors only from associating the estimates with the ground truth by time
/// (associateByTime, e.g. no overlap), naming both files.
Result<RunPlots> makeRunPlots(const RunReport& run);

/// The HTML page for `runs` (≥ 1): a comparison table when there are several, then per run a
/// section with the three plots as inline SVG (polylines simplified within 0.25 px), the metrics
/// table and the per-lap gate corrections. kInvalidArgument without runs; makeRunPlots' errors.
Result<std::string> renderRunReportHtml(const std::vector<RunReport>& runs);

/// Writes renderRunReportHtml(runs) to `html_path` and, in the same folder, `<name>_xy.png`,
/// `<name>_error.png` (with ground truth) and `<name>_opt_ms.png` per run, every file atomically.
/// Run names are first made file-name safe and unique (`_2`, `_3`, ...). `written` (optional)
/// receives the paths written. kInvalidArgument without runs; kIoError naming the file that failed.
Status writeRunReport(std::vector<RunReport> runs, const std::string& html_path,
                      std::vector<std::string>* written = nullptr);

}  // namespace dualgraph
