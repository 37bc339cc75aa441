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
};

/// Runs it; returns the process exit code (0 ok, 1 bad input or failed run).
int runRunCommand(const RunOptions& options);

}  // namespace dualgraph::tools
