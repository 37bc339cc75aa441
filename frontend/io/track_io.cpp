// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/track_io.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/core/token_reader.h"
#include "dualgraph/frontend/io/yaml_fields.h"

namespace dualgraph {
namespace {

using Marks = std::map<std::string, YAML::Mark>;
using KeySet = std::vector<std::string>;  // in schema order, for messages
using yaml_fields::describe;
using yaml_fields::fieldError;
using yaml_fields::keyName;
using yaml_fields::readInteger;
using yaml_fields::readList;
using yaml_fields::readNumber;
using yaml_fields::readPositive;

const KeySet kTopKeys = {"name", "gates", "path", "laps", "speed"};
const KeySet kGateKeys = {"id", "position", "yaw", "roll", "pitch", "size"};
const KeySet kAnyPathKeys = {"type", "center", "semi_axes", "a", "b", "height", "waypoints"};

/// The keys each path type takes, and those of them it requires.
struct PathSchema {
  TrackPath::Type type;
  KeySet keys;
  KeySet required;
};
const PathSchema kPathSchemas[] = {
    {TrackPath::Type::kEllipse, {"type", "center", "semi_axes", "height"}, {"semi_axes", "height"}},
    {TrackPath::Type::kLemniscate, {"type", "center", "a", "b", "height"}, {"a", "height"}},
    {TrackPath::Type::kWaypoints, {"type", "waypoints"}, {"waypoints"}},
};

bool contains(const KeySet& keys, const std::string& key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

std::string joined(const KeySet& keys) {
  std::string text;
  for (const std::string& key : keys) text += (text.empty() ? "" : ", ") + key;
  return text;
}

/// One entry of a mapping: a key of `allowed`, seen once, with a value.
Status checkEntry(const std::string& source, const YAML::Node& key, const YAML::Node& value, const std::string& field,
                  const KeySet& allowed, Marks& marks) {
  if (!contains(allowed, keyName(key))) {
    return fieldError(source, key.Mark(), field, "unknown key (expected one of: " + joined(allowed) + ")");
  }
  if (!marks.emplace(keyName(key), key.Mark()).second) return fieldError(source, key.Mark(), field, "duplicate key");
  if (value.IsNull()) return fieldError(source, key.Mark(), field, "no value");
  return Status::okStatus();
}

Status readGate(const std::string& source, const std::string& name, const YAML::Node& node, TrackGate& gate) {
  if (!node.IsMap()) {
    return fieldError(source, node.Mark(), name, "expected a mapping {id, position, yaw, ...}, got " + describe(node));
  }
  gate.line = node.Mark().line + 1;
  Marks marks;
  for (const auto& entry : node) {
    const std::string key = keyName(entry.first);
    const std::string field = name + "." + key;
    const YAML::Node& value = entry.second;
    DG_RETURN_IF_ERROR(checkEntry(source, entry.first, value, field, kGateKeys, marks));
    if (key == "id") {
      DG_RETURN_IF_ERROR(readInteger(source, field, value, gate.id));
      if (gate.id < 0) return fieldError(source, value.Mark(), field, "must be >= 0 (got " + value.Scalar() + ")");
    } else if (key == "position") {
      std::vector<double> p;
      DG_RETURN_IF_ERROR(readList(source, field, value, 3, p));
      gate.position << p[0], p[1], p[2];
    } else if (key == "size") {
      DG_RETURN_IF_ERROR(readPositive(source, field, value, gate.size));
    } else {
      DG_RETURN_IF_ERROR(readNumber(source, field, value, key == "yaw" ? gate.yaw : key == "roll" ? gate.roll : gate.pitch));
    }
  }
  for (const char* required : {"id", "position", "yaw"}) {
    if (marks.count(required) == 0) return fieldError(source, node.Mark(), name + "." + required, "missing");
  }
  return Status::okStatus();
}

Status readGates(const std::string& source, const YAML::Node& node, std::vector<TrackGate>& gates) {
  if (!node.IsSequence()) return fieldError(source, node.Mark(), "gates", "expected a list of gates, got " + describe(node));
  if (node.size() < 2) {
    return fieldError(source, node.Mark(), "gates", "expected at least 2 gates, got " + std::to_string(node.size()));
  }
  std::map<int, size_t> first_index;
  gates.assign(node.size(), TrackGate());
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string name = TokenReader::indexedField("gates", static_cast<int>(i));
    DG_RETURN_IF_ERROR(readGate(source, name, node[i], gates[i]));
    const auto [previous, inserted] = first_index.emplace(gates[i].id, i);
    if (!inserted) {
      return fieldError(source, node[i]["id"].Mark(), name + ".id",
                        "duplicate id " + std::to_string(gates[i].id) + " (also gates[" +
                            std::to_string(previous->second) + "], line " + std::to_string(gates[previous->second].line) + ")");
    }
  }
  return Status::okStatus();
}

/// ≥ 3 waypoints of 3 numbers, no two consecutive ones equal, closing pair (last, first) included.
Status readWaypoints(const std::string& source, const std::string& field, const YAML::Node& node,
                     std::vector<Eigen::Vector3d>& waypoints) {
  if (!node.IsSequence() || node.size() < 3) {
    return fieldError(source, node.Mark(), field, "expected a list of at least 3 waypoints [x, y, z], got " + describe(node));
  }
  waypoints.clear();
  for (size_t i = 0; i < node.size(); ++i) {
    std::vector<double> p;
    DG_RETURN_IF_ERROR(readList(source, TokenReader::indexedField(field, static_cast<int>(i)), node[i], 3, p));
    waypoints.emplace_back(p[0], p[1], p[2]);
  }
  for (size_t i = 1; i <= waypoints.size(); ++i) {  // pairs (i - 1, i), the last one (n - 1, 0)
    const bool closing = i == waypoints.size();
    if (waypoints[i - 1] != waypoints[closing ? 0 : i]) continue;
    const size_t later = closing ? i - 1 : i;  // blame the one further down the file
    return fieldError(source, node[later].Mark(), TokenReader::indexedField(field, static_cast<int>(later)),
                      "equal to " + TokenReader::indexedField(field, static_cast<int>(closing ? 0 : i - 1)) +
                          (closing ? " (the path is closed: the last waypoint leads back to the first)"
                                   : " (consecutive waypoints must differ)"));
  }
  return Status::okStatus();
}

Status readPath(const std::string& source, const YAML::Node& node, TrackPath& path) {
  if (!node.IsMap()) return fieldError(source, node.Mark(), "path", "expected a mapping {type, ...}, got " + describe(node));
  const YAML::Node type = node["type"];
  if (!type) return fieldError(source, node.Mark(), "path.type", "missing");
  const auto schema = std::find_if(std::begin(kPathSchemas), std::end(kPathSchemas), [&](const PathSchema& candidate) {
    return type.IsScalar() && type.Scalar() == trackPathTypeName(candidate.type);
  });
  if (schema == std::end(kPathSchemas)) {
    return fieldError(source, type.Mark(), "path.type", "expected ellipse, lemniscate or waypoints, got " + describe(type));
  }
  path.type = schema->type;
  const std::string a_kind = (path.type == TrackPath::Type::kEllipse ? "an " : "a ") + std::string(trackPathTypeName(path.type));
  Marks marks;
  for (const auto& entry : node) {
    const std::string key = keyName(entry.first);
    const std::string field = "path." + key;
    const YAML::Node& value = entry.second;
    if (!contains(schema->keys, key) && contains(kAnyPathKeys, key)) {
      return fieldError(source, entry.first.Mark(), field,
                        "not a key of " + a_kind + " path (expected one of: " + joined(schema->keys) + ")");
    }
    DG_RETURN_IF_ERROR(checkEntry(source, entry.first, value, field, schema->keys, marks));
    std::vector<double> pair;
    if (key == "center") {
      DG_RETURN_IF_ERROR(readList(source, field, value, 2, pair));
      path.center << pair[0], pair[1];
    } else if (key == "semi_axes") {
      DG_RETURN_IF_ERROR(readList(source, field, value, 2, pair));
      DG_RETURN_IF_ERROR(readPositive(source, field + "[0]", value[0], path.semi_axis_x));
      DG_RETURN_IF_ERROR(readPositive(source, field + "[1]", value[1], path.semi_axis_y));
    } else if (key == "a" || key == "b") {
      DG_RETURN_IF_ERROR(readPositive(source, field, value, key == "a" ? path.lemniscate_a : path.lemniscate_b));
    } else if (key == "height") {
      DG_RETURN_IF_ERROR(readNumber(source, field, value, path.height));
    } else if (key == "waypoints") {
      DG_RETURN_IF_ERROR(readWaypoints(source, field, value, path.waypoints));
    }
  }
  for (const std::string& key : schema->required) {
    if (marks.count(key) == 0) return fieldError(source, node.Mark(), "path." + key, "missing (required for " + a_kind + " path)");
  }
  return Status::okStatus();
}

Result<Track> readTrack(const std::string& text, const std::string& source) {
  auto root = yaml_fields::loadDocument(text, source);
  if (!root.ok()) return root.status();
  if (root->IsNull()) return fieldError(source, YAML::Mark(), "gates", "missing (the document is empty)");
  if (!root->IsMap()) {
    return fieldError(source, root->Mark(), "gates", "missing: the document is " + describe(*root) +
                                                         ", not a mapping {name, gates, path, laps, speed}");
  }
  Track track;
  Marks marks;
  for (const auto& entry : *root) {
    const std::string key = keyName(entry.first);
    const YAML::Node& value = entry.second;
    DG_RETURN_IF_ERROR(checkEntry(source, entry.first, value, key, kTopKeys, marks));
    if (key == "name") {
      if (!value.IsScalar()) return fieldError(source, value.Mark(), key, "expected a string, got " + describe(value));
      track.name = value.Scalar();
    } else if (key == "gates") {
      DG_RETURN_IF_ERROR(readGates(source, value, track.gates));
    } else if (key == "path") {
      DG_RETURN_IF_ERROR(readPath(source, value, track.path));
    } else if (key == "laps") {
      DG_RETURN_IF_ERROR(readInteger(source, key, value, track.laps));
      if (track.laps < 1) return fieldError(source, value.Mark(), key, "must be >= 1 (got " + value.Scalar() + ")");
    } else {
      DG_RETURN_IF_ERROR(readPositive(source, key, value, track.speed));
    }
  }
  if (marks.count("gates") == 0) return fieldError(source, root->Mark(), "gates", "missing");
  return track;
}

/// "[v0, v1, ...]" with 17 significant digits (enough for every double to read back the same).
std::string flowList(std::initializer_list<double> values) {
  std::ostringstream out;
  out.precision(17);
  const char* separator = "[";
  for (const double value : values) out << std::exchange(separator, ", ") << value;
  out << ']';
  return out.str();
}

}  // namespace

Result<Track> parseTrackYaml(const std::string& text, const std::string& source_name) {
  // yaml-cpp throws from node access on malformed input (and DeepRecursion past 2000 levels); no input
  // may escape as an exception.
  try {
    return readTrack(text, source_name);
  } catch (const YAML::Exception& e) {
    return yaml_fields::yamlError(source_name, e);
  } catch (const std::exception& e) {
    return Status(StatusCode::kParseError, source_name + ": cannot read the track: " + e.what());
  } catch (...) {
    return Status(StatusCode::kParseError, source_name + ": cannot read the track: unknown exception");
  }
}

Result<Track> loadTrackYaml(const std::string& path) {
  auto text = yaml_fields::readText(path);
  if (!text.ok()) return text.status();
  return parseTrackYaml(*text, path);
}

std::string trackToYaml(const Track& track) {
  std::ostringstream out;
  out.precision(17);
  if (!track.name.empty()) {
    YAML::Emitter name;  // quotes and escapes whatever the name holds
    name << YAML::DoubleQuoted << track.name;
    out << "name: " << name.c_str() << '\n';
  }
  out << "gates:\n";
  for (const TrackGate& g : track.gates) {
    out << "  - {id: " << g.id << ", position: " << flowList({g.position.x(), g.position.y(), g.position.z()})
        << ", yaw: " << g.yaw << ", roll: " << g.roll << ", pitch: " << g.pitch << ", size: " << g.size << "}\n";
  }
  const TrackPath& path = track.path;
  if (path.type != TrackPath::Type::kNone) out << "path:\n  type: " << trackPathTypeName(path.type) << '\n';
  if (path.type == TrackPath::Type::kWaypoints) {
    out << "  waypoints:\n";
    for (const Eigen::Vector3d& p : path.waypoints) out << "    - " << flowList({p.x(), p.y(), p.z()}) << '\n';
  } else if (path.type != TrackPath::Type::kNone) {
    out << "  center: " << flowList({path.center.x(), path.center.y()}) << '\n';
    if (path.type == TrackPath::Type::kEllipse) {
      out << "  semi_axes: " << flowList({path.semi_axis_x, path.semi_axis_y}) << '\n';
    } else {
      out << "  a: " << path.lemniscate_a << "\n  b: " << path.lemniscate_b << '\n';
    }
    out << "  height: " << path.height << '\n';
  }
  out << "laps: " << track.laps << "\nspeed: " << track.speed << '\n';
  return out.str();
}

Status saveTrackYaml(const std::string& path, const Track& track) {
  const std::string text = trackToYaml(track);
  const auto check = parseTrackYaml(text, path);
  if (!check.ok()) return Status(StatusCode::kInvalidArgument, check.status().message() + " (track not written)");
  return writeFileAtomically(path, [&text](std::ostream& out) {
    out << text;
    return Status::okStatus();
  });
}

}  // namespace dualgraph
