// SPDX-License-Identifier: MIT
#include "frontend/yaml_fields.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "core/token_reader.h"
#include "types/se3_math.h"

namespace dualgraph::yaml_fields {

std::string location(const std::string& source, const YAML::Mark& mark) {
  return mark.is_null() ? source : source + ":" + std::to_string(mark.line + 1);
}

Status fieldError(const std::string& source, const YAML::Mark& mark, const std::string& field, const std::string& why) {
  return Status(StatusCode::kParseError, location(source, mark) + ": field " + TokenReader::quoted(field) + ": " + why);
}

std::string describe(const YAML::Node& node) {
  if (node.IsScalar()) return TokenReader::quoted(node.Scalar());
  if (node.IsSequence()) return "a list of " + std::to_string(node.size());
  return node.IsMap() ? "a mapping" : "nothing";
}

std::string keyName(const YAML::Node& key) { return key.IsScalar() ? key.Scalar() : describe(key); }

Status readNumber(const std::string& source, const std::string& field, const YAML::Node& node, double& out) {
  double value = 0.0;
  if (node.IsScalar() && YAML::convert<double>::decode(node, value) && std::isfinite(value)) {
    out = value;
    return Status::okStatus();
  }
  return fieldError(source, node.Mark(), field, "expected a finite number, got " + describe(node));
}

Status readPositive(const std::string& source, const std::string& field, const YAML::Node& node, double& out) {
  DG_RETURN_IF_ERROR(readNumber(source, field, node, out));
  if (out > 0.0) return Status::okStatus();
  return fieldError(source, node.Mark(), field, "must be > 0 (got " + node.Scalar() + ")");
}

Status readInteger(const std::string& source, const std::string& field, const YAML::Node& node, int& out) {
  const std::string text = node.IsScalar() ? node.Scalar() : std::string();
  const char* first = text.c_str() + (text.size() > 1 && text[0] == '+' ? 1 : 0);
  const char* last = text.c_str() + text.size();
  const auto [end, error] = std::from_chars(first, last, out);
  if (text.empty() || error != std::errc() || end != last) {
    return fieldError(source, node.Mark(), field, "expected an integer, got " + describe(node));
  }
  return Status::okStatus();
}

Status readList(const std::string& source, const std::string& field, const YAML::Node& node, size_t count,
                std::vector<double>& out) {
  if (!node.IsSequence() || (count != 0 && node.size() != count)) {
    const std::string expected = count != 0 ? "a list of " + std::to_string(count) + " numbers" : "a list of numbers";
    return fieldError(source, node.Mark(), field, "expected " + expected + ", got " + describe(node));
  }
  out.assign(node.size(), 0.0);
  for (size_t i = 0; i < node.size(); ++i) {
    DG_RETURN_IF_ERROR(readNumber(source, TokenReader::indexedField(field, static_cast<int>(i)), node[i], out[i]));
  }
  return Status::okStatus();
}

Status readMatrix3(const std::string& source, const std::string& field, const YAML::Node& node, Eigen::Matrix3d& out) {
  if (!node.IsSequence() || node.size() != 3) {
    return fieldError(source, node.Mark(), field, "expected 3 rows of 3 numbers, got " + describe(node));
  }
  for (size_t r = 0; r < 3; ++r) {
    std::vector<double> row;
    DG_RETURN_IF_ERROR(readList(source, TokenReader::indexedField(field, static_cast<int>(r)), node[r], 3, row));
    out.row(static_cast<Eigen::Index>(r)) << row[0], row[1], row[2];
  }
  return Status::okStatus();
}

Status readTransform(const std::string& source, const std::string& field, const YAML::Node& node,
                     Eigen::Isometry3d& out) {
  if (!node.IsMap()) {
    return fieldError(source, node.Mark(), field,
                      "expected {position: [x, y, z], quaternion_xyzw: [qx, qy, qz, qw]}, got " + describe(node));
  }
  std::vector<double> p;
  std::vector<double> q;
  for (const auto& entry : node) {
    const std::string key = keyName(entry.first);
    const std::string sub = field + "." + key;
    if (key != "position" && key != "quaternion_xyzw") return fieldError(source, entry.first.Mark(), sub, "unknown key");
    if ((key == "position" ? p : q).size() != 0) return fieldError(source, entry.first.Mark(), sub, "duplicate key");
    DG_RETURN_IF_ERROR(readList(source, sub, entry.second, key == "position" ? 3 : 4, key == "position" ? p : q));
  }
  if (p.empty() || q.empty()) {
    return fieldError(source, node.Mark(), field, std::string("missing '") + (p.empty() ? "position" : "quaternion_xyzw") + "'");
  }
  const Eigen::Quaterniond rotation = quatFromXyzw(q[0], q[1], q[2], q[3]);
  if (!(rotation.norm() > 1e-12)) {
    return fieldError(source, node.Mark(), field + ".quaternion_xyzw", "zero norm; cannot normalise");
  }
  out = Eigen::Isometry3d::Identity();
  out.linear() = rotation.normalized().toRotationMatrix();
  out.translation() << p[0], p[1], p[2];
  return Status::okStatus();
}

Result<std::string> readText(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) return Status(StatusCode::kIoError, path + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(StatusCode::kIoError, path + ": cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Status(StatusCode::kIoError, path + ": read failed");
  return text.str();
}

Result<YAML::Node> loadDocument(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    const std::string column = e.mark.is_null() ? "" : " (column " + std::to_string(e.mark.column + 1) + ")";
    return Status(StatusCode::kParseError, location(source, e.mark) + ": YAML syntax error: " + e.msg + column);
  }
}

Result<YAML::Node> loadMapping(const std::string& text, const std::string& source) {
  auto root = loadDocument(text, source);
  if (root.ok() && !root->IsMap()) {
    return Status(StatusCode::kParseError, location(source, root->Mark()) + ": expected a mapping, got " + describe(*root));
  }
  return root;
}

Status yamlError(const std::string& source, const YAML::Exception& error) {
  return Status(StatusCode::kParseError, location(source, error.mark) + ": YAML error: " + error.msg);
}

}  // namespace dualgraph::yaml_fields
