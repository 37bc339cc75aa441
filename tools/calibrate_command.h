// SPDX-License-Identifier: MIT
// `dualgraph calibrate`: the camera's clock offset and mount rotation estimated from a sequence folder.
#pragma once

#include <string>

namespace dualgraph::tools {

/// Options of `dualgraph calibrate`.
struct CalibrateOptions {
  std::string sequence;
  std::string config;         ///< empty: the bundled data/config/default.yaml (the runs inside use it)
  std::string out;            ///< the calibrated camera YAML to write (atomically); empty: none
  std::string json;           ///< the report as one JSON object (atomically); empty: none
  int max_iterations = 6;     ///< runs at most (CalibrationParams::max_iterations)
  double knot_spacing = 0.0;  ///< > 0: the drift correction's knot spacing [s]; 0: the library's default
  bool quiet = false;         ///< no per-run lines and no summary (errors and warnings still go to stderr)
};

/// Runs it; returns the process exit code (0 ok — also when the iteration stopped at max_iterations, with a
/// warning —, 1 bad input or no usable detection).
int runCalibrateCommand(const CalibrateOptions& options);

}  // namespace dualgraph::tools
