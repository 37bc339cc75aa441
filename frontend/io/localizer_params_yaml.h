// SPDX-License-Identifier: MIT
// LocalizerParams from YAML text or a file, with "source:LINE: field 'NAME': why" errors.
#pragma once

#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer_params.h"

namespace dualgraph {

// The YAML form of LocalizerParams (the `localizer:` section of data/config/default.yaml lists every key with its default):
//
//   localizer:                 # optional; the keys may also sit at the top level
//     mode: dual               # dual | single
//     landmark: pose           # pose | point
//     linear_solver: auto      # auto | cholmod | eigen
//     d_main: 2.0              # every other key is named exactly as its field
//     initial_world_T_odom: {position: [0, 0, 0], quaternion_xyzw: [0, 0, 0, 1]}
//
// A missing key keeps its default (so does a missing `position` / `quaternion_xyzw`); the quaternion is
// normalised. Errors are kParseError, one line "SOURCE:LINE: field 'NAME': why" (1-based line): a YAML
// syntax error, a wrong type, NaN/Inf, an unknown or duplicate key, an unknown enum value, a document that
// is not a mapping. The parsed values are then checked with validateLocalizerParams; its kInvalidArgument
// comes back prefixed with "SOURCE:LINE: " (the line of the offending key, or "SOURCE: " when the field was
// not in the text).

/// Reads LocalizerParams from YAML text; keys are the field names; a missing key keeps its default.
/// `source_name` (usually the file name) starts every error message. Never throws.
/// `other_sections`: top-level keys that belong to the caller (e.g. `frontend` in `dualgraph run`'s
/// config) and are skipped here instead of being reported as unknown.
Result<LocalizerParams> parseLocalizerParams(const std::string& yaml_text, const std::string& source_name,
                                             const std::vector<std::string>& other_sections = {});

/// Every key parseLocalizerParams accepts (data/config/default.yaml lists each with its default and unit, tested).
const std::vector<std::string>& localizerParamKeys();

/// Every field as `INDENT key: value` lines that parseLocalizerParams reads back to the same parameters (numbers in
/// the fewest digits that round-trip; initial_world_T_body left out when unset).
std::string localizerParamsYaml(const LocalizerParams& params, const std::string& indent = "");

/// Reads the file (kIoError naming it when unreadable) and parses it.
Result<LocalizerParams> loadLocalizerParams(const std::string& path);

}  // namespace dualgraph
