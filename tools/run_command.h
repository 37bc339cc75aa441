// SPDX-License-Identifier: MIT
// `dualgraph run`: the Localizer over a sequence folder, written as a run folder.
#pragma once

#include <string>

namespace dualgraph::tools {

/// Options of `dualgraph run`.
struct RunOptions {
  std::string sequence;
  std::string config;  ///< empty: the bundled data/config/default.yaml
  std::string out;
  std::string mode;    ///< empty: the config's; dual | single
  double d_main = -1.0, d_temp = -1.0, d_single = -1.0;  ///< < 0: the config's [m]
  bool quiet = false;
  bool skip_unknown_gates = false;  ///< drop detections naming a gate the map lacks (a warning) instead of exit 1
};

/// Exit code of a run that completed but used no detection: its outputs are written, but the estimate is
/// the raw odometry (e.g. the VIO in a frame the map does not share, every detection outside the VIO's time
/// span, every detection refused by PnP). Distinct from 1 (bad input) so that scripts can tell them apart.
constexpr int kExitNothingLocalised = 3;

/// Runs it; returns the process exit code (0 ok, 1 bad input or failed run, 3 = kExitNothingLocalised).
int runRunCommand(const RunOptions& options);

}  // namespace dualgraph::tools
