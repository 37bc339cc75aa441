// SPDX-License-Identifier: MIT
// `dualgraph run`: the Localizer over a sequence folder, written as a run folder.
#pragma once

#include <string>

namespace dualgraph::tools {

/// Options of `dualgraph run`.
struct RunOptions {
  std::string sequence;
  std::string vio;     ///< empty: SEQUENCE/vio.tum; otherwise the odometry file read instead (any readTrajectory format)
  std::string gt;      ///< empty: SEQUENCE/gt.tum when it exists; otherwise the ground truth read instead
  std::string config;  ///< empty: the bundled data/config/default.yaml
  std::string out;
  std::string mode;    ///< empty: the config's; dual | single
  double d_main = -1.0, d_temp = -1.0, d_single = -1.0;  ///< < 0: the config's [m]
  bool quiet = false;
  bool skip_unknown_gates = false;  ///< drop detections naming a gate the map lacks (a warning) instead of exit 1
  /// Exit kExitMostlyLost when the run was lost for more than this share of its time after the first lock [%].
  double max_lost_share_pct = 20.0;
};

/// Exit code of a run that completed but used no detection: its outputs are written, but the estimate is
/// the raw odometry (e.g. the VIO in a frame the map does not share, every detection outside the VIO's time
/// span, every detection refused by PnP). Distinct from 1 (bad input) so that scripts can tell them apart.
constexpr int kExitNothingLocalised = 3;
/// Exit code of a run that completed but was lost (gates seen, none fitting the estimate) for more than
/// RunOptions::max_lost_share_pct of its time after the VIO's frame was found, or that ended lost: its
/// outputs are written and tracking_state.csv says when the estimate was not to be trusted.
constexpr int kExitMostlyLost = 4;

/// Runs it; returns the process exit code (0 ok, 1 bad input or failed run, 3 = kExitNothingLocalised,
/// 4 = kExitMostlyLost).
int runRunCommand(const RunOptions& options);

}  // namespace dualgraph::tools
