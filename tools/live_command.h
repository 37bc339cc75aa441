// SPDX-License-Identifier: MIT
// `dualgraph live`: the onboard pipeline fed from a record stream, one corrected pose line out per odometry sample.
#pragma once

#include <string>

namespace dualgraph::tools {

/// Options of `dualgraph live` (frontend/io/FORMATS.md, "Live stream").
struct LiveOptions {
  std::string input = "-";  ///< the record stream: `-` (stdin), a file or a named pipe
  std::string map;          ///< gates.yaml (required)
  std::string camera;       ///< camera.yaml (needed for corner records)
  std::string config;       ///< empty: the bundled data/config/default.yaml
  std::string gt;           ///< ground truth for the run folder's metrics (optional; any readTrajectory format)
  std::string poses = "-";  ///< where the pose lines go: `-` (stdout), a file or a named pipe
  std::string out;          ///< the run folder written at the end of the stream (optional)
  bool quiet = false;
  double max_lost_share_pct = 20.0;  ///< as `run`'s (exit 4 above it)
};

/// Reads the stream record by record as it arrives, feeds the StreamingLocalizer (caller-thread mode: the run is
/// `run`'s on the same records) and writes `pose t x y z qx qy qz qw state` per accepted odometry sample, flushed at
/// once. At the end (EOF or `end`): the run folder (`run`'s files, the stream recorded as OUT/sequence) and `run`'s
/// warnings. Exit codes as `run` (1: a malformed record, named stdin:LINE, after the outputs of what came before).
int runLiveCommand(const LiveOptions& options);

}  // namespace dualgraph::tools
