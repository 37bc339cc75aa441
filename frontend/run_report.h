// SPDX-License-Identifier: MIT
// The report of one or more `dualgraph run` folders: the paper's Fig. 3 (XY trajectories with the
// gates), position error and optimisation time over time, and the metrics — as one self-contained
// HTML page (inline SVG and CSS, no scripts, nothing fetched) and as PNG files. No printing.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/status.h"
#include "frontend/run_metrics.h"
#include "frontend/trajectory_metrics.h"
#include "frontend/xy_plot.h"

namespace dualgraph {

/// What the report shows of one run folder, read by loadRunReport.
struct RunReport {
  std::string name;          ///< the run folder's name (unique and file-name safe after writeRunReport)
  std::string run_dir;       ///< as given
  std::string sequence_dir;  ///< from run.yaml, or the override
  std::string mode;          ///< "dual", "single", or empty when unknown (no run.yaml)
  std::string thresholds;    ///< e.g. "d_main 2 m, d_temp 0.1 m" (run.yaml), or empty
  StampedPoses ground_truth;  ///< world_T_body [s, m]; empty when the sequence has no gt.tum
  StampedPoses vio;           ///< odom_T_body [s, m]; odom taken as world (simulation, unaligned)
  StampedPoses estimate;      ///< world_T_body [s, m] at every odometry sample (estimate.tum)
  std::vector<PlotGate> gates;                      ///< from the sequence's gates.yaml [m, rad]
  std::vector<std::pair<double, double>> opt_ms;    ///< (t [s], main-graph optimisation [ms]) per stats.csv row
  std::vector<std::pair<std::string, double>> metrics;  ///< metrics.json numbers in file order (null: NaN)
  std::vector<LapCorrection> gate_corrections;      ///< metrics.json `gate_corrections` [m]
};

/// Reads run folder `run_dir` — estimate.tum, stats.csv, metrics.json (required when the sequence has
/// gt.tum) and run.yaml (`sequence:` folder, absolute or relative to the run folder; `mode:`; the
/// keyframe thresholds) — and from the sequence folder gates.yaml, vio.tum and gt.tum (optional).
/// A non-empty `sequence_dir` replaces run.yaml's (which may then be absent). Errors: kNotFound
/// naming a missing folder or file; the readers' own errors (file:line) for malformed ones.
Result<RunReport> loadRunReport(const std::string& run_dir, const std::string& sequence_dir = "");

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
