// SPDX-License-Identifier: MIT
// The strict YAML field readers every file reader shares: one error format "source:LINE: field 'NAME': why".
#pragma once

// The one strict YAML field layer of the project: every YAML reader (camera, track, run config, localizer
// parameters, run folder) reads its fields through these, so every error reads the same way:
// "source:LINE: field 'NAME': why" (LINE 1-based, from the node's yaml-cpp mark). Private to the frontend
// (not installed, not included by any public header).
// Every function returns a Status instead of throwing on bad input, but yaml-cpp itself may still
// throw while a caller walks a malformed node: callers wrap their parse in a try block.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"

namespace dualgraph::yaml_fields {

/// "source:LINE" for a node's mark (1-based), or `source` alone when the mark is null.
std::string location(const std::string& source, const YAML::Mark& mark);

/// kParseError "source:LINE: field 'NAME': why".
Status fieldError(const std::string& source, const YAML::Mark& mark, const std::string& field, const std::string& why);

/// A node for a message: its scalar quoted, "a list of N", "a mapping" or "nothing".
std::string describe(const YAML::Node& node);

/// The text of a mapping key: its scalar, or describe() of a key that is not a scalar.
std::string keyName(const YAML::Node& key);

/// A finite double (rejects .nan, .inf, text and non-scalars).
Status readNumber(const std::string& source, const std::string& field, const YAML::Node& node, double& out);

/// `true` or `false` (YAML 1.2's booleans; yaml-cpp's yes/no/on/off are refused).
Status readBool(const std::string& source, const std::string& field, const YAML::Node& node, bool& out);

/// A scalar as text (a list or a mapping is refused).
Status readString(const std::string& source, const std::string& field, const YAML::Node& node, std::string& out);

/// A finite number > 0; "must be > 0 (got TEXT)" quotes the number as written.
Status readPositive(const std::string& source, const std::string& field, const YAML::Node& node, double& out);

/// A decimal int: optional sign, digits only (yaml-cpp would read "010" as octal and "1.5" as 1).
Status readInteger(const std::string& source, const std::string& field, const YAML::Node& node, int& out);

/// A list of finite numbers; exactly `count` of them unless count is 0. Elements are named
/// `field[i]` in messages.
Status readList(const std::string& source, const std::string& field, const YAML::Node& node, size_t count,
                std::vector<double>& out);

/// 3 rows of 3 numbers, [[a, b, c], [d, e, f], [g, h, i]], row-major.
Status readMatrix3(const std::string& source, const std::string& field, const YAML::Node& node, Eigen::Matrix3d& out);

/// Whether readTransform needs both parts of a transform.
enum class TransformParts {
  kBoth,         ///< `position` and `quaternion_xyzw` are both required (a camera, a gate)
  kKeepMissing,  ///< a missing part keeps the value `out` holds (a configuration over its defaults)
};

/// {position: [x, y, z], quaternion_xyzw: [qx, qy, qz, qw]} (Hamilton, normalised on reading) as a
/// rigid transform; no other keys, none twice, none without a value.
Status readTransform(const std::string& source, const std::string& field, const YAML::Node& node,
                     Eigen::Isometry3d& out, TransformParts parts = TransformParts::kBoth);

/// A number as YAML text that reads back to the same double: the fewest significant digits that do ("0.1",
/// "1e-06", "22.458"); non-finite values as .nan / .inf / -.inf (which the readers refuse).
std::string formatExactNumber(double value);

/// A transform as readTransform reads it: {position: [x, y, z], quaternion_xyzw: [qx, qy, qz, qw]}.
std::string formatTransform(const Eigen::Isometry3d& transform);

/// The whole file as bytes; kIoError "path: why" when it is a directory or cannot be read.
Result<std::string> readText(const std::string& path);

/// The first document of `text` (a null node for an empty one); a YAML syntax error is kParseError
/// "source:LINE: YAML syntax error: msg (column C)", and so is a second document ("a second YAML document;
/// put everything in one"). Never YAML::LoadAll: yaml-cpp 0.7's (Debian bookworm) returns an empty document
/// for ever after a stray ',' behind a flow collection, e.g. "[1],", allocating until the process dies
/// (jbeder/yaml-cpp#1040, fixed upstream in 2024 by #1319; found by test/fuzz/fuzz_run_config): at most two
/// documents are read, whatever the text.
Result<YAML::Node> loadDocument(const std::string& text, const std::string& source);

/// loadDocument, and kParseError "source:LINE: expected a mapping, got ..." unless it is a mapping.
Result<YAML::Node> loadMapping(const std::string& text, const std::string& source);

/// kParseError "source:LINE: YAML error: msg" for an exception yaml-cpp threw while a node was walked.
Status yamlError(const std::string& source, const YAML::Exception& error);

}  // namespace dualgraph::yaml_fields
