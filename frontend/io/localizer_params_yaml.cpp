// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/localizer_params_yaml.h"

#include <algorithm>
#include <map>
#include <vector>

#include "dualgraph/core/token_reader.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/frontend/io/localizer_params_node.h"
#include "dualgraph/frontend/io/yaml_fields.h"

namespace dualgraph {
namespace {

using namespace yaml_fields;
using KeyMarks = std::map<std::string, YAML::Mark>;

/// An enum spelled by its name function (`localizerModeName`, ...); the error lists the allowed names.
template <typename Enum, size_t N>
Status readEnum(const std::string& source, const std::string& field, const YAML::Node& node,
                const Enum (&values)[N], const char* (*name)(Enum), Enum& out) {
  std::string text;
  DG_RETURN_IF_ERROR(readString(source, field, node, text));
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
  DG_RETURN_IF_ERROR(readString(source, field, node, text));
  auto kind = parseLinearSolverKind(text);
  if (!kind.ok()) return fieldError(source, node.Mark(), field, kind.status().message());
  out = *kind;
  return Status::okStatus();
}

template <typename T>
struct FieldSlot {
  const char* name;
  T LocalizerParams::*member;
};

constexpr FieldSlot<double> kNumberFields[] = {
    {"d_main", &LocalizerParams::d_main}, {"theta_main", &LocalizerParams::theta_main},
    {"keyframe_max_interval_s", &LocalizerParams::keyframe_max_interval_s},
    {"d_temp", &LocalizerParams::d_temp}, {"theta_temp", &LocalizerParams::theta_temp},
    {"d_single", &LocalizerParams::d_single}, {"theta_single", &LocalizerParams::theta_single},
    {"odom_sigma_t", &LocalizerParams::odom_sigma_t}, {"odom_sigma_r", &LocalizerParams::odom_sigma_r},
    {"odom_sigma_tilt", &LocalizerParams::odom_sigma_tilt},
    {"odom_min_distance", &LocalizerParams::odom_min_distance},
    {"odom_scale_min", &LocalizerParams::odom_scale_min}, {"odom_scale_max", &LocalizerParams::odom_scale_max},
    {"map_sigma_t", &LocalizerParams::map_sigma_t}, {"map_sigma_r", &LocalizerParams::map_sigma_r},
    {"initial_sigma_t", &LocalizerParams::initial_sigma_t}, {"initial_sigma_r", &LocalizerParams::initial_sigma_r},
    {"main_time_budget_ms", &LocalizerParams::main_time_budget_ms},
    {"main_relative_decrease_stop", &LocalizerParams::main_relative_decrease_stop},
    {"temp_relative_decrease_stop", &LocalizerParams::temp_relative_decrease_stop},
    {"temp_model_decrease_stop", &LocalizerParams::temp_model_decrease_stop},
    {"chi2_gate_pose", &LocalizerParams::chi2_gate_pose}, {"chi2_gate_point", &LocalizerParams::chi2_gate_point},
    {"distilled_floor_range", &LocalizerParams::distilled_floor_range},
    {"distilled_floor_lateral", &LocalizerParams::distilled_floor_lateral},
    {"distilled_floor_rotation", &LocalizerParams::distilled_floor_rotation},
    {"lost_after_s", &LocalizerParams::lost_after_s},
    {"detection_latency", &LocalizerParams::detection_latency},
    {"max_observation_lead_s", &LocalizerParams::max_observation_lead_s},
};
constexpr FieldSlot<int> kIntegerFields[] = {
    {"main_max_iterations", &LocalizerParams::main_max_iterations},
    {"main_window", &LocalizerParams::main_window},
    {"temp_max_iterations", &LocalizerParams::temp_max_iterations},
    {"lost_min_failures", &LocalizerParams::lost_min_failures},
};
constexpr FieldSlot<bool> kBoolFields[] = {
    {"mapping", &LocalizerParams::mapping},
    {"use_input_covariance", &LocalizerParams::use_input_covariance},
    {"learn_odometry_noise", &LocalizerParams::learn_odometry_noise},
    {"fix_map_gates", &LocalizerParams::fix_map_gates},
    {"single_all_detections", &LocalizerParams::single_all_detections},
};
constexpr LocalizerMode kModes[] = {LocalizerMode::kDual, LocalizerMode::kSingle};
constexpr LandmarkModel kLandmarks[] = {LandmarkModel::kPose, LandmarkModel::kPoint};
constexpr LmDamping kDampings[] = {LmDamping::kIdentity, LmDamping::kDiagonal};
constexpr TemporarySolverKind kTemporarySolvers[] = {TemporarySolverKind::kBlock, TemporarySolverKind::kGraph};

// The keys read otherwise than as a plain number, integer or flag.
using Text = const std::string&;
struct OtherField {
  const char* name;
  Status (*read)(Text source, Text name, const YAML::Node& value, LocalizerParams& params);
  std::string (*write)(const LocalizerParams& params);  ///< the value as read back; "" when unset (left out)
};
const OtherField kOtherFields[] = {
    {"mode", [](Text s, Text n, const YAML::Node& v,
                LocalizerParams& p) { return readEnum(s, n, v, kModes, &localizerModeName, p.mode); },
     [](const LocalizerParams& p) -> std::string { return localizerModeName(p.mode); }},
    {"landmark", [](Text s, Text n, const YAML::Node& v,
                    LocalizerParams& p) { return readEnum(s, n, v, kLandmarks, &landmarkModelName, p.landmark); },
     [](const LocalizerParams& p) -> std::string { return landmarkModelName(p.landmark); }},
    {"linear_solver", [](Text s, Text n, const YAML::Node& v,
                         LocalizerParams& p) { return readLinearSolver(s, n, v, p.linear_solver); },
     [](const LocalizerParams& p) -> std::string { return linearSolverKindName(p.linear_solver); }},
    {"lm_damping", [](Text s, Text n, const YAML::Node& v,
                      LocalizerParams& p) { return readEnum(s, n, v, kDampings, &lmDampingName, p.lm_damping); },
     [](const LocalizerParams& p) -> std::string { return lmDampingName(p.lm_damping); }},
    {"temp_solver",
     [](Text s, Text n, const YAML::Node& v, LocalizerParams& p) {
       return readEnum(s, n, v, kTemporarySolvers, &temporarySolverKindName, p.temp_solver);
     },
     [](const LocalizerParams& p) -> std::string { return temporarySolverKindName(p.temp_solver); }},
    {"robust_kernel",
     [](Text s, Text n, const YAML::Node& v, LocalizerParams& p) { return readString(s, n, v, p.robust_kernel); },
     [](const LocalizerParams& p) { return p.robust_kernel; }},
    {"initial_world_T_body",
     [](Text s, Text n, const YAML::Node& v, LocalizerParams& p) {
       Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
       DG_RETURN_IF_ERROR(readTransform(s, n, v, start, TransformParts::kBoth));
       p.initial_world_T_body = start;
       return Status::okStatus();
     },
     [](const LocalizerParams& p) { return p.initial_world_T_body ? formatTransform(*p.initial_world_T_body) : ""; }},
    {"initial_world_T_odom",
     [](Text s, Text n, const YAML::Node& v, LocalizerParams& p) {
       return readTransform(s, n, v, p.initial_world_T_odom, TransformParts::kKeepMissing);
     },
     [](const LocalizerParams& p) { return formatTransform(p.initial_world_T_odom); }},
};

/// Reads one `name: value` pair into `params`; an unknown name is an error at the key.
Status readField(const std::string& source, const YAML::Node& key, const YAML::Node& value,
                 LocalizerParams& params) {
  const std::string name = key.Scalar();
  for (const auto& slot : kNumberFields) {
    if (name == slot.name) return readNumber(source, name, value, params.*slot.member);
  }
  for (const auto& slot : kIntegerFields) {
    if (name == slot.name) return readInteger(source, name, value, params.*slot.member);
  }
  for (const auto& slot : kBoolFields) {
    if (name == slot.name) return readBool(source, name, value, params.*slot.member);
  }
  for (const auto& slot : kOtherFields) {
    if (name == slot.name) return slot.read(source, name, value, params);
  }
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

Result<LocalizerParams> readLocalizerParams(const std::string& source, const YAML::Node& root,
                                            const std::vector<std::string>& other_sections) {
  LocalizerParams params;
  KeyMarks marks;
  try {
    if (!root.IsNull()) {
      auto mapping = fieldsMapping(source, root, other_sections);
      if (!mapping.ok()) return mapping.status();
      if (!mapping->IsNull()) DG_RETURN_IF_ERROR(readFields(source, *mapping, params, marks));
    }
  } catch (const YAML::Exception& e) {
    return yamlError(source, e);
  }
  const Status valid = validateLocalizerParams(params);
  if (!valid.ok()) return locateValidationError(source, valid, marks);
  return params;
}

Result<LocalizerParams> parseLocalizerParams(const std::string& yaml_text, const std::string& source_name,
                                             const std::vector<std::string>& other_sections) {
  Result<YAML::Node> root = loadDocument(yaml_text, source_name);
  if (!root.ok()) return root.status();
  return readLocalizerParams(source_name, *root, other_sections);
}

const std::vector<std::string>& localizerParamKeys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> out;
    for (const auto& slot : kNumberFields) out.emplace_back(slot.name);
    for (const auto& slot : kIntegerFields) out.emplace_back(slot.name);
    for (const auto& slot : kBoolFields) out.emplace_back(slot.name);
    for (const auto& slot : kOtherFields) out.emplace_back(slot.name);
    return out;
  }();
  return keys;
}

std::string localizerParamsYaml(const LocalizerParams& params, const std::string& indent) {
  std::string out;
  const auto line = [&](const char* name, const std::string& value) {
    if (!value.empty()) out += indent + name + ": " + value + "\n";
  };
  for (const auto& slot : kNumberFields) line(slot.name, formatExactNumber(params.*slot.member));
  for (const auto& slot : kIntegerFields) line(slot.name, std::to_string(params.*slot.member));
  for (const auto& slot : kBoolFields) line(slot.name, params.*slot.member ? "true" : "false");
  for (const auto& slot : kOtherFields) line(slot.name, slot.write(params));
  return out;
}

Result<LocalizerParams> loadLocalizerParams(const std::string& path) {
  Result<std::string> text = readText(path);
  if (!text.ok()) return text.status();
  return parseLocalizerParams(*text, path);
}

}  // namespace dualgraph
