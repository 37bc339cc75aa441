// SPDX-License-Identifier: MIT
// `dualgraph ablation`: every track × seed × configuration, written as the paper's Tables I–III.
#pragma once

#include <string>
#include <vector>

namespace dualgraph::tools {

/// Options of `dualgraph ablation`.
struct AblationOptions {
  std::vector<std::string> tracks;  ///< empty: the bundled RATM ellipse and lemniscate
  std::vector<int> seeds{1, 2, 3};
  std::string out;
  std::string config;  ///< empty: the bundled data/config/default.yaml
  int laps = 0;        ///< 0: the tracks' own (shorter flights for quick checks)
  bool quiet = false;
};

/// Simulates every track × seed, runs the paper's configurations and writes Tables I–III as
/// Markdown (tables.md) and CSV (table1.csv, table2.csv, table3.csv, runs.csv) into `out`.
int runAblationCommand(const AblationOptions& options);

}  // namespace dualgraph::tools
