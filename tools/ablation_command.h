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
  /// Simulation profiles (frontend/simulation/race_profiles.h), side by side in Table IV; Tables I–III on the first.
  std::vector<std::string> profiles{"realistic", "clean", "harsh"};
  std::string out;
  std::string config;  ///< empty: the bundled data/config/default.yaml
  int laps = 0;        ///< 0: the tracks' own (shorter flights for quick checks)
  /// Given sequence folders (e.g. real flights) run as they are instead of simulated flights: profile "given",
  /// one Table III row each; exclusive with tracks, seeds, profiles and laps.
  std::vector<std::string> sequences;
  bool quiet = false;
};

/// Simulates every profile × track × seed (or takes the given sequence folders), runs the paper's configurations
/// and writes Tables I–IV as Markdown (tables.md) and CSV (table1.csv … table4.csv, runs.csv) into `out`.
int runAblationCommand(const AblationOptions& options);

}  // namespace dualgraph::tools
