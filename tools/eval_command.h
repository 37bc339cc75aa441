// SPDX-License-Identifier: MIT
// `dualgraph eval`: an estimate TUM file against ground truth (ATE, RPE), optionally as JSON.
#pragma once

#include <string>

namespace dualgraph::tools {

/// Options of `dualgraph eval`: an estimate (TUM, estimate_T_body) against ground truth (TUM,
/// world_T_body); times in s, positions in m.
struct EvalOptions {
  std::string gt;           ///< ground-truth TUM file
  std::string est;          ///< estimate TUM file (covariance columns allowed, ignored)
  std::string align = "se3";  ///< se3, 4dof or none: the alignment of the rotation ATE
  std::string json;         ///< write the metrics here as one JSON object (atomically) when set
  double max_gap_s = 0.1;   ///< association gap [s]
};

/// Runs it; returns the process exit code (0 ok, 1 bad input or no usable overlap).
int runEvalCommand(const EvalOptions& options);

}  // namespace dualgraph::tools
