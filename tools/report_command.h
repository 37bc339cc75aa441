// SPDX-License-Identifier: MIT
// `dualgraph report`: the HTML report (and PNG plots) of one or more run folders.
#pragma once

#include <string>
#include <vector>

namespace dualgraph::tools {

/// Options of `dualgraph report`.
struct ReportOptions {
  std::vector<std::string> runs;  ///< run folders of `dualgraph run`, in the order shown
  std::string out;                ///< the HTML file; the PNGs go next to it
  std::string sequence;           ///< replaces every run's run.yaml sequence folder when set
  std::string vio_frame = "lock"; ///< `--vio-frame`: "lock" (through the frame found at the lock) or "raw"
};

/// Runs it; returns the process exit code (0 ok, 1 a missing or malformed file, named on stderr).
int runReportCommand(const ReportOptions& options);

}  // namespace dualgraph::tools
