// SPDX-License-Identifier: MIT
#include "dual_graph/localizer_params_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <type_traits>
#include <vector>

#include "core/token_reader.h"
#include "dual_graph/yaml_document.h"
#include "types/se3_math.h"

namespace dualgraph {
namespace {

using KeyMarks = std::map<std::string, YAML::Mark>;

/// "source:LINE" (1-based), or just "source" when yaml-cpp has no position for the node.
std::string location(const std::string& source, const YAML::Mark& mark) {
  return mark.is_null() ? source : source + ":" + std::to_string(mark.line + 1);
}

Status fieldError(const std::string& source, const YAML::Mark& mark, const std::string& field,
                  const std::string& why) {
  // Quoted printably: an unknown key may hold newlines or binary garbage; the message stays one line.
  return Status(StatusCode::kParseError, location(source, mark) + ": field " + TokenReader::quoted(field) + ": " + why);
}

/// What a node holds, for "expected X, got Y".
std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar: return TokenReader::quoted(node.Scalar());
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Map: return "a mapping";
    default: return "nothing";
  }
}

/// A double (finite), bool (yaml-cpp's true/false/yes/no/on/off) or string scalar.
template <typename T>
Status readScalar(const std::string& source, const std::string& field, const YAML::Node& node, T& out) {
  T value{};
  bool good = node.IsScalar() && YAML::convert<T>::decode(node, value);
  if constexpr (std::is_floating_point_v<T>) good = good && std::isfinite(value);
  if (good) {
    out = value;
    return Status::okStatus();
  }
  const char* expected = std::is_same_v<T, bool> ? "true or false" : std::is_same_v<T, double> ? "a finite number"
                                                                                                  : "a string";
  return fieldError(source, node.Mark(), field, std::string("expected ") + expected + ", got " + describe(node));
}

/// Decimal only: yaml-cpp's own conversion would read "010" as octal 8.
Status readInteger(const std::string& source, const std::string& field, const YAML::Node& node, int& out) {
  const std::string text = node.IsScalar() ? node.Scalar() : std::string();
  const char* first = text.c_str() + (text.size() > 1 && text[0] == '+' ? 1 : 0);
  const char* last = text.c_str() + text.size();
  int value = 0;
  const auto [end, error] = std::from_chars(first, last, value);
  if (text.empty() || error != std::errc() || end != last) {
    return fieldError(source, node.Mark(), field, "expected an integer, got " + describe(node));
  }
  out = value;
  return Status::okStatus();
}

/// An enum spelled by its name function (`localizerModeName`, ...); the error lists the allowed names.
template <typename Enum, size_t N>
Status readEnum(const std::string& source, const std::string& field, const YAML::Node& node,
                const Enum (&values)[N], const char* (*name)(Enum), Enum& out) {
  std::string text;
  DG_RETURN_IF_ERROR(readScalar(source, field, node, text));
  std::string allowed;
  for (const Enum value : values) {
    if (text == name(value)) {
      out = value;
      return Status::okStatus();
    }
    allowed += (allowed.empty() ? "" : " or ") + std::string(name(value));
  }
  return fieldError(source, node.Mark(), field, "unknown value " + TokenReader::quoted(text) + " (expected " +
                                                    allowed + ")");
}

Status readLinearSolver(const std::string& source, const std::string& field, const YAML::Node& node,
                        LinearSolverKind& out) {
  std::string text;
  DG_RETURN_IF_ERROR(readScalar(source, field, node, text));
  auto kind = parseLinearSolverKind(text);
  if (!kind.ok()) return fieldError(source, node.Mark(), field, kind.status().message());
  out = *kind;
  return Status::okStatus();
}

Status readNumbers(const std::string& source, const std::string& field, const YAML::Node& node, size_t count,
                   double* out) {
  if (!node.IsSequence() || node.size() != count) {
    return fieldError(source, node.Mark(), field,
                      "expected a list of " + std::to_string(count) + " numbers, got " +
                          (node.IsSequence() ? "a list of " + std::to_string(node.size()) : describe(node)));
  }
  for (size_t i = 0; i < count; ++i) {
    DG_RETURN_IF_ERROR(readScalar(source, TokenReader::indexedField(field, static_cast<int>(i)), node[i], out[i]));
  }
  return Status::okStatus();
}

/// {position: [x, y, z], quaternion_xyzw: [qx, qy, qz, qw]}; a missing part keeps its current value.
Status readTransform(const std::string& source, const std::string& field, const YAML::Node& node,
                     Eigen::Isometry3d& out) {
  if (!node.IsMap()) {
    return fieldError(source, node.Mark(), field,
                      "expected a mapping {position: [x, y, z], quaternion_xyzw: [qx, qy, qz, qw]}, got " +
                          describe(node));
  }
  Eigen::Isometry3d transform = out;
  KeyMarks seen;
  for (const auto& entry : node) {
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : describe(entry.first);
    const std::string sub_field = field + "." + key;
    if (key != "position" && key != "quaternion_xyzw") {
      return fieldError(source, entry.first.Mark(), sub_field, "unknown key");
    }
    if (!seen.emplace(key, entry.first.Mark()).second) {
      return fieldError(source, entry.first.Mark(), sub_field, "duplicate key");
    }
    if (entry.second.IsNull()) return fieldError(source, entry.first.Mark(), sub_field, "no value");
    if (key == "position") {
      double p[3];
      DG_RETURN_IF_ERROR(readNumbers(source, sub_field, entry.second, 3, p));
      transform.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    } else {
      double q[4];
      DG_RETURN_IF_ERROR(readNumbers(source, sub_field, entry.second, 4, q));
      Eigen::Quaterniond rotation = quatFromXyzw(q[0], q[1], q[2], q[3]);
      const double norm = rotation.norm();
      if (!(norm > 1e-12) || !std::isfinite(norm)) {
        return fieldError(source, entry.second.Mark(), sub_field, "zero (or non-finite) norm; cannot normalise");
      }
      rotation.coeffs() /= norm;
      transform.linear() = rotation.toRotationMatrix();
    }
  }
  out = transform;
  return Status::okStatus();
}

template <typename T>
struct FieldSlot {
  const char* name;
  T LocalizerParams::*member;
};

constexpr FieldSlot<double> kNumberFields[] = {
    {"d_main", &LocalizerParams::d_main}, {"theta_main", &LocalizerParams::theta_main},
    {"d_temp", &LocalizerParams::d_temp}, {"theta_temp", &LocalizerParams::theta_temp},
    {"d_single", &LocalizerParams::d_single}, {"theta_single", &LocalizerParams::theta_single},
    {"odom_sigma_t", &LocalizerParams::odom_sigma_t}, {"odom_sigma_r", &LocalizerParams::odom_sigma_r},
    {"odom_min_distance", &LocalizerParams::odom_min_distance},
    {"map_sigma_t", &LocalizerParams::map_sigma_t}, {"map_sigma_r", &LocalizerParams::map_sigma_r},
    {"initial_sigma_t", &LocalizerParams::initial_sigma_t}, {"initial_sigma_r", &LocalizerParams::initial_sigma_r},
    {"main_time_budget_ms", &LocalizerParams::main_time_budget_ms},
    {"main_relative_decrease_stop", &LocalizerParams::main_relative_decrease_stop},
    {"temp_relative_decrease_stop", &LocalizerParams::temp_relative_decrease_stop},
    {"temp_model_decrease_stop", &LocalizerParams::temp_model_decrease_stop},
    {"chi2_gate_pose", &LocalizerParams::chi2_gate_pose}, {"chi2_gate_point", &LocalizerParams::chi2_gate_point},
};
constexpr FieldSlot<int> kIntegerFields[] = {
    {"main_max_iterations", &LocalizerParams::main_max_iterations},
    {"main_window", &LocalizerParams::main_window},
    {"temp_max_iterations", &LocalizerParams::temp_max_iterations},
};
constexpr FieldSlot<bool> kBoolFields[] = {
    {"mapping", &LocalizerParams::mapping},
    {"use_input_covariance", &LocalizerParams::use_input_covariance},
    {"fix_map_gates", &LocalizerParams::fix_map_gates},
    {"single_all_detections", &LocalizerParams::single_all_detections},
};
constexpr LocalizerMode kModes[] = {LocalizerMode::kDual, LocalizerMode::kSingle};
constexpr LandmarkModel kLandmarks[] = {LandmarkModel::kPose, LandmarkModel::kPoint};
constexpr LmDamping kDampings[] = {LmDamping::kIdentity, LmDamping::kDiagonal};
constexpr TemporarySolverKind kTemporarySolvers[] = {TemporarySolverKind::kBlock, TemporarySolverKind::kGraph};

/// Reads one `name: value` pair into `params`; an unknown name is an error at the key.
Status readField(const std::string& source, const YAML::Node& key, const YAML::Node& value,
                 LocalizerParams& params) {
  const std::string name = key.Scalar();
  for (const auto& slot : kNumberFields) {
    if (name == slot.name) return readScalar(source, name, value, params.*slot.member);
  }
  for (const auto& slot : kIntegerFields) {
    if (name == slot.name) return readInteger(source, name, value, params.*slot.member);
  }
  for (const auto& slot : kBoolFields) {
    if (name == slot.name) return readScalar(source, name, value, params.*slot.member);
  }
  if (name == "mode") return readEnum(source, name, value, kModes, &localizerModeName, params.mode);
  if (name == "landmark") return readEnum(source, name, value, kLandmarks, &landmarkModelName, params.landmark);
  if (name == "linear_solver") return readLinearSolver(source, name, value, params.linear_solver);
  if (name == "lm_damping") return readEnum(source, name, value, kDampings, &lmDampingName, params.lm_damping);
  if (name == "temp_solver") {
    return readEnum(source, name, value, kTemporarySolvers, &temporarySolverKindName, params.temp_solver);
  }
  if (name == "robust_kernel") return readScalar(source, name, value, params.robust_kernel);
  if (name == "initial_world_T_odom") return readTransform(source, name, value, params.initial_world_T_odom);
  return fieldError(source, key.Mark(), name, "unknown key");
}

/// Reads every field of a mapping; `marks` records where each key was, for validation messages.
Status readFields(const std::string& source, const YAML::Node& mapping, LocalizerParams& params, KeyMarks& marks) {
  for (const auto& entry : mapping) {
    if (!entry.first.IsScalar()) {
      const std::string where = location(source, entry.first.Mark());
      return Status(StatusCode::kParseError, where + ": a key must be a field name, got " + describe(entry.first));
    }
    const std::string name = entry.first.Scalar();
    const auto [previous, inserted] = marks.emplace(name, entry.first.Mark());
    if (!inserted) {
      return fieldError(source, entry.first.Mark(), name,
                        "duplicate key (first at " + location(source, previous->second) + ")");
    }
    // A key without a value: yaml-cpp places the null on the next line, so report the key's line.
    if (entry.second.IsNull()) return fieldError(source, entry.first.Mark(), name, "no value");
    DG_RETURN_IF_ERROR(readField(source, entry.first, entry.second, params));
  }
  return Status::okStatus();
}

/// The mapping that holds the fields: the document itself, or the value of its only key `localizer`.
bool isOtherSection(const YAML::Node& key, const std::vector<std::string>& other_sections) {
  return key.IsScalar() && std::find(other_sections.begin(), other_sections.end(), key.Scalar()) != other_sections.end();
}

Result<YAML::Node> fieldsMapping(const std::string& source, const YAML::Node& root,
                                 const std::vector<std::string>& other_sections) {
  if (!root.IsMap()) {
    return Status(StatusCode::kParseError,
                  location(source, root.Mark()) +
                      ": the document must be a mapping of LocalizerParams fields (optionally under 'localizer:'), "
                      "got " + describe(root));
  }
  const YAML::Node nested = root["localizer"];
  if (!nested) {
    if (other_sections.empty()) return root;
    YAML::Node fields(YAML::NodeType::Map);
    for (const auto& entry : root) {
      if (!isOtherSection(entry.first, other_sections)) fields.force_insert(entry.first, entry.second);
    }
    return fields;
  }
  int localizer_keys = 0;
  for (const auto& entry : root) {
    if (isOtherSection(entry.first, other_sections)) continue;
    const bool is_localizer = entry.first.IsScalar() && entry.first.Scalar() == "localizer";
    if (is_localizer && ++localizer_keys == 1) continue;
    return fieldError(source, entry.first.Mark(), entry.first.IsScalar() ? entry.first.Scalar() : describe(entry.first),
                      is_localizer ? "duplicate key"
                                   : "unknown key (with 'localizer:' at the top level, every field goes under it)");
  }
  if (!nested.IsNull() && !nested.IsMap()) {
    return fieldError(source, nested.Mark(), "localizer",
                      "expected a mapping of LocalizerParams fields, got " + describe(nested));
  }
  return nested;
}

/// validateLocalizerParams' message ("field 'NAME': ...") prefixed with "source:LINE: " of NAME's key.
Status locateValidationError(const std::string& source, const Status& status, const KeyMarks& marks) {
  const std::string& message = status.message();
  const std::string prefix = "field '";
  YAML::Mark mark = YAML::Mark::null_mark();
  if (message.compare(0, prefix.size(), prefix) == 0) {
    const size_t end = message.find('\'', prefix.size());
    const auto found = marks.find(message.substr(prefix.size(), end - prefix.size()));
    if (end != std::string::npos && found != marks.end()) mark = found->second;
  }
  return Status(status.code(), location(source, mark) + ": " + message);
}

}  // namespace

Result<LocalizerParams> parseLocalizerParams(const std::string& yaml_text, const std::string& source_name,
                                             const std::vector<std::string>& other_sections) {
  LocalizerParams params;
  KeyMarks marks;
  try {
    // Not YAML::LoadAll: yaml-cpp 0.7's spins for ever on "[1]," (dual_graph/yaml_document.h).
    const FirstYamlDocument document = loadFirstYamlDocument(yaml_text);
    if (document.has_second) {
      return Status(StatusCode::kParseError, location(source_name, document.second_mark) +
                                                 ": a second YAML document; put every field in one");
    }
    if (!document.node.IsNull()) {
      auto mapping = fieldsMapping(source_name, document.node, other_sections);
      if (!mapping.ok()) return mapping.status();
      if (!mapping->IsNull()) DG_RETURN_IF_ERROR(readFields(source_name, *mapping, params, marks));
    }
  } catch (const YAML::Exception& e) {
    const std::string column = e.mark.is_null() ? "" : " (column " + std::to_string(e.mark.column + 1) + ")";
    return Status(StatusCode::kParseError, location(source_name, e.mark) + ": YAML syntax error: " + e.msg + column);
  }
  const Status valid = validateLocalizerParams(params);
  if (!valid.ok()) return locateValidationError(source_name, valid, marks);
  return params;
}

Result<LocalizerParams> loadLocalizerParams(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    return Status(StatusCode::kIoError, path + ": is a directory, not a YAML file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(StatusCode::kIoError, path + ": cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Status(StatusCode::kIoError, path + ": read failed");
  return parseLocalizerParams(text.str(), path);
}

}  // namespace dualgraph
