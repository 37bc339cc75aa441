// SPDX-License-Identifier: MIT
// The run folder `dualgraph run` writes and `dualgraph report` reads, in one place: estimate.tum,
// keyframes.tum, stats.csv, run.yaml and metrics.json (formats below). No printing.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/frontend/replay/self_calibration.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/evaluation/trajectory_metrics.h"
#include "dualgraph/frontend/gates/track.h"
#include "dualgraph/frontend/replay/sequence_run.h"

namespace dualgraph {

/// Writes a run's files into the existing folder `dir` (e.g. a staging folder), each atomically:
///   estimate.tum   world_T_body at every accepted odometry sample that is a map pose, i.e. not initialising
///                  (TUM: t [s], m, quaternion xyzw)
///   tracking_state.csv  `t,state` at every accepted odometry sample: initialising, tracking or lost
///   keyframes.tum  the keyframes' final estimates (TUM)
///   stats.csv      one row per keyframe: `t,keyframe,nodes,edges,iterations,optimization_ms,distilled_edges,
///                  rejected_edges,skipped_gates,observations,temp_nodes,temp_edges,temp_iterations,temp_ms,
///                  termination` (row 0: the first keyframe, not optimised)
///   run.yaml       `sequence:` (absolute), `vio:` (absolute; only when `vio_path` is given: the odometry file read
///                  instead of SEQUENCE/vio.tum), `gt:` (absolute; only when `gt_path` is given: the ground truth read
///                  instead of SEQUENCE/gt.tum), `mode:` and the keyframe thresholds (`d_main`, `d_temp` or `d_single`)
///   config.yaml    the whole configuration the run used (runConfigYaml: every key, the file's and the defaults), so
///                  `--config DIR/config.yaml` runs it again
///   metrics.json   RunMetrics' figures, always: `has_ground_truth` 1/0, the ATE figures null without ground truth
///                  (non-finite values as null), `lock_world_T_odom_{x,y,z}_m, _q{x,y,z,w}` the VIO's frame in the
///                  map as the run first had it (the search's lock, or the given frame; null without a map pose); frontend/evaluation/OUTPUTS.md lists every key
/// kIoError naming the file that could not be written.
/// With `self_calibration` (a self-calibrating run), metrics.json also holds `self_calibration_applied` (1/0,
/// −1 not attempted), `self_calibration_at_s`, `_time_offset_before_s`, `_time_offset_s`, `_time_offset_sigma_s`,
/// `_mount_change_deg`, `_iterations` and `_why_not` (a string, empty when applied).
Status writeRunFolder(const std::string& dir, const std::string& sequence_dir, const SequenceRunParams& config,
                      const SequenceRunResult& run, const RunMetrics& metrics,
                      const SelfCalibrationReport* self_calibration = nullptr, const std::string& vio_path = "",
                      const std::string& gt_path = "");

/// What `dualgraph report` shows of one run folder, read by loadRunReport.
struct RunReport {
  std::string name;          ///< the run folder's name (unique and file-name safe after writeRunReport)
  std::string run_dir;       ///< as given
  std::string sequence_dir;  ///< from run.yaml, or the override
  std::string vio_path;      ///< run.yaml's `vio:` (a run given --vio), or empty: SEQUENCE/vio.tum
  std::string gt_path;       ///< run.yaml's `gt:` (a run given --gt), or empty: SEQUENCE/gt.tum when it exists
  std::string mode;          ///< "dual", "single", or empty when unknown (no run.yaml)
  std::string thresholds;    ///< e.g. "d_main 2 m, d_temp 0.1 m" (run.yaml), or empty
  StampedPoses ground_truth;  ///< world_T_body [s, m]; empty when the sequence has no gt.tum
  StampedPoses vio;           ///< odom_T_body [s, m]; odom taken as world (simulation, unaligned)
  StampedPoses estimate;      ///< world_T_body [s, m] at every odometry sample (estimate.tum)
  std::vector<TrackGate> gates;                     ///< from the sequence's gates.yaml [m, rad]
  std::vector<std::pair<double, double>> opt_ms;    ///< (t [s], main-graph optimisation [ms]) per stats.csv row
  std::vector<std::pair<double, double>> temp_ms;   ///< (t [s], temporary graph [ms]) per row (empty: no column)
  std::vector<std::pair<std::string, double>> metrics;  ///< metrics.json numbers in file order (null: NaN)
  std::vector<LapCorrection> gate_corrections;      ///< metrics.json `gate_corrections` [m]
  /// metrics.json `lock_world_T_odom_*`: the VIO's frame in the map as the run first had it (the frame search's
  /// lock, or the frame the configuration gave) [m]; empty when the run never locked or its metrics.json predates
  /// the keys.
  std::optional<Eigen::Isometry3d> lock_world_T_odom;
  double lock_at_s = std::numeric_limits<double>::quiet_NaN();  ///< metrics.json `initialized_at_s` [s], with it
};

/// Reads run folder `run_dir` — estimate.tum, stats.csv, metrics.json (required when the sequence has
/// gt.tum; its `lock_world_T_odom_*` all numbers or all null, else kParseError) and run.yaml (`sequence:`
/// folder, absolute or relative to the run folder; `mode:`; the keyframe thresholds; `vio:` when the run read
/// another odometry file) — and from the sequence folder gates.yaml,
/// vio.tum (or run.yaml's `vio:`) and gt.tum (optional), each in any format readTrajectory recognises.
/// A non-empty `sequence_dir` replaces run.yaml's (which may then be absent). Errors: kNotFound
/// naming a missing folder or file; the readers' own errors (file:line) for malformed ones.
Result<RunReport> loadRunReport(const std::string& run_dir, const std::string& sequence_dir = "");

}  // namespace dualgraph
