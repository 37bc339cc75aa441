// SPDX-License-Identifier: MIT
// Track YAML files: strict reading with line-numbered errors, and writing that reads back exactly.
#pragma once

#include <string>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/gates/track.h"

namespace dualgraph {

/// Reads our track YAML (frontend/io/FORMATS.md; complete examples in data/tracks/):
///
///     name: ratm_ellipse            # optional string
///     gates:                        # required, >= 2 gates, ids unique
///       - {id: 1, position: [4.009444, 1.307730, 1.163745], yaw: 0.000170, size: 1.5}
///         # id: integer >= 0; position [m] of the inner square's centre; yaw [rad] of the gate normal;
///         # roll, pitch [rad] optional (0); size: inner square side [m] > 0, optional (1.5)
///     path:                         # optional (a map-only file has none); the simulated flight
///       type: ellipse               # ellipse | lemniscate | waypoints (TrackPath, formulas in track.h)
///       center: [0.0, 0.0]          # ellipse, lemniscate: optional (0, 0) [m]
///       semi_axes: [9.0, 1.5]       # ellipse: a (along x), b (along y) [m], both > 0, required
///       height: 0.7                 # ellipse, lemniscate: z [m], required
///       # lemniscate: a: 6.0 [m] (> 0, required), b: 0.708 (lateral stretch > 0, optional, 1)
///       # waypoints: [[x, y, z], ...] [m], >= 3, closed (last -> first), no two consecutive ones
///       #            equal (last and first included); required, and the only key besides type
///     laps: 12                      # optional integer >= 1 (1)
///     speed: 8.0                    # optional top speed [m/s] > 0 (8)
///
/// TrackGate::line is set to the 1-based line where each gate starts. Unknown or duplicate keys,
/// keys of another path type (e.g. `semi_axes` under a lemniscate), missing required keys, lists of
/// the wrong length, non-numeric or non-finite values, integers written as 1.5, and every range
/// rule above are kParseError "path:LINE: field 'NAME': why", e.g.
/// "track.yaml:7: field 'gates[2].size': must be > 0 (got -1.5)" (list indices from 0); an
/// unreadable file is kIoError. Never throws, whatever the input.
Result<Track> loadTrackYaml(const std::string& path);
/// The same from text; `source_name` stands for the file in messages.
Result<Track> parseTrackYaml(const std::string& text, const std::string& source_name);
/// The YAML text of `track` in the schema above: one flow mapping per gate with every field
/// (roll, pitch and size included), 17 significant digits, so parseTrackYaml gives the same doubles
/// back bit for bit. No validation: see saveTrackYaml.
std::string trackToYaml(const Track& track);
/// Writes trackToYaml(track) to `path` atomically (`path.tmp`, then a rename). kInvalidArgument,
/// with the reader's reason, and nothing written if the text would not read back (bad sizes, ids,
/// laps, a non-finite value, ...); kIoError if the file cannot be written.
Status saveTrackYaml(const std::string& path, const Track& track);

}  // namespace dualgraph
