// SPDX-License-Identifier: MIT
// `dualgraph optimize`: optimises a g2o file, prints a summary (or JSON), writes the result with -o (and marginals).
#pragma once

#include <string>

namespace dualgraph::tools {

/// Options of `dualgraph optimize`.
struct OptimizeOptions {
  std::string input;
  std::string output;
  /// With a path: after the optimisation, every free vertex's marginal covariance as CSV (`--marginals`).
  std::string marginals;
  int iterations = 100;
  std::string algorithm = "lm";
  std::string linear = "cholmod";
  std::string damping = "diagonal";
  std::string init = "auto";  ///< auto (chordal on pure pose graphs without robust kernels) | chordal | none
  std::string robust;
  bool json = false;
  bool list_types = false;
  bool repair_information = false;
  bool skip_unknown_tags = false;
  std::string gauge = "highest";
  bool verbose = false;
  double relative_decrease = 1e-9;
  double time_budget_ms = 0.0;
};

/// Runs it; returns the process exit code.
int runOptimizeCommand(const OptimizeOptions& options);

}  // namespace dualgraph::tools
