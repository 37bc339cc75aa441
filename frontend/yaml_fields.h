// SPDX-License-Identifier: MIT
#pragma once

// Private to the frontend (not installed, not included by any public header): the strict YAML field
// readers shared by camera_io.cpp and track_io.cpp, so every reader words its errors the same way:
// "source:LINE: field 'NAME': why" (LINE 1-based, from the node's yaml-cpp mark).
// Every function returns a Status instead of throwing on bad input, but yaml-cpp itself may still
// throw while a caller walks a malformed node: callers wrap their parse in a try block.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <vector>

#include "core/status.h"

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

/// {position: [x, y, z], quaternion_xyzw: [qx, qy, qz, qw]} (Hamilton, normalised on reading) as a
/// rigid transform; both keys required, no others.
Status readTransform(const std::string& source, const std::string& field, const YAML::Node& node,
                     Eigen::Isometry3d& out);

/// The whole file as bytes; kIoError "path: why" when it is a directory or cannot be read.
Result<std::string> readText(const std::string& path);

/// The first document of `text` (a null node for an empty one); a YAML syntax error is kParseError
/// "source:LINE: YAML syntax error: msg (column C)".
Result<YAML::Node> loadDocument(const std::string& text, const std::string& source);

/// loadDocument, and kParseError "source:LINE: expected a mapping, got ..." unless it is a mapping.
Result<YAML::Node> loadMapping(const std::string& text, const std::string& source);

/// kParseError "source:LINE: YAML error: msg" for an exception yaml-cpp threw while a node was walked.
Status yamlError(const std::string& source, const YAML::Exception& error);

}  // namespace dualgraph::yaml_fields
