// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/yaml_fields.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "dualgraph/core/token_reader.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph::yaml_fields {
namespace {

/// Counts documents and keeps the mark of the first node of each (no node is built).
class DocumentMarks : public YAML::EventHandler {
 public:
  int documents() const { return documents_; }
  const YAML::Mark& rootMark() const { return root_mark_; }

  void OnDocumentStart(const YAML::Mark& mark) override {
    ++documents_;
    root_mark_ = mark;
    root_seen_ = false;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { node(mark); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { node(mark); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t, const std::string&) override { node(mark); }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(mark);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(mark);
  }
  void OnMapEnd() override {}

 private:
  void node(const YAML::Mark& mark) {
    if (!root_seen_) root_mark_ = mark;
    root_seen_ = true;
  }
  int documents_ = 0;
  bool root_seen_ = false;
  YAML::Mark root_mark_ = YAML::Mark::null_mark();
};

/// "source:LINE: YAML syntax error: msg (column C)".
Status syntaxError(const std::string& source, const YAML::Exception& e) {
  const std::string column = e.mark.is_null() ? "" : " (column " + std::to_string(e.mark.column + 1) + ")";
  return Status(StatusCode::kParseError, location(source, e.mark) + ": YAML syntax error: " + e.msg + column);
}

}  // namespace

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

Status readBool(const std::string& source, const std::string& field, const YAML::Node& node, bool& out) {
  if (node.IsScalar() && (node.Scalar() == "true" || node.Scalar() == "false")) {
    out = node.Scalar() == "true";
    return Status::okStatus();
  }
  return fieldError(source, node.Mark(), field, "expected true or false, got " + describe(node));
}

Status readString(const std::string& source, const std::string& field, const YAML::Node& node, std::string& out) {
  if (node.IsScalar()) {
    out = node.Scalar();
    return Status::okStatus();
  }
  return fieldError(source, node.Mark(), field, "expected a string, got " + describe(node));
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
                     Eigen::Isometry3d& out, TransformParts parts) {
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
    if (entry.second.IsNull()) return fieldError(source, entry.first.Mark(), sub, "no value");
    DG_RETURN_IF_ERROR(readList(source, sub, entry.second, key == "position" ? 3 : 4, key == "position" ? p : q));
  }
  if (parts == TransformParts::kBoth && (p.empty() || q.empty())) {
    return fieldError(source, node.Mark(), field, std::string("missing '") + (p.empty() ? "position" : "quaternion_xyzw") + "'");
  }
  Eigen::Isometry3d transform = out;
  if (!q.empty()) {
    Eigen::Quaterniond rotation = quatFromXyzw(q[0], q[1], q[2], q[3]);
    const double norm = rotation.norm();
    if (!(norm > 1e-12) || !std::isfinite(norm)) {
      return fieldError(source, node["quaternion_xyzw"].Mark(), field + ".quaternion_xyzw",
                        "zero (or non-finite) norm; cannot normalise");
    }
    rotation.coeffs() /= norm;
    transform.linear() = rotation.toRotationMatrix();
  }
  if (!p.empty()) transform.translation() << p[0], p[1], p[2];
  out = transform;
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
    YAML::Node node = YAML::Load(text);
    std::istringstream in(text);
    YAML::Parser parser(in);
    DocumentMarks marks;
    // Two documents at most: the bounded loop is the point (LoadAll's unbounded one can spin for ever).
    while (marks.documents() < 2 && parser.HandleNextDocument(marks)) {
    }
    if (marks.documents() >= 2) {
      return Status(StatusCode::kParseError,
                    location(source, marks.rootMark()) + ": a second YAML document; put everything in one");
    }
    return node;
  } catch (const YAML::Exception& e) {
    return syntaxError(source, e);
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

std::string formatExactNumber(double value) {
  if (std::isnan(value)) return ".nan";
  if (std::isinf(value)) return value > 0.0 ? ".inf" : "-.inf";
  char text[32];
  if (value == std::round(value) && std::abs(value) < 1e15) {  // 50, not 5e+01
    std::snprintf(text, sizeof(text), "%.0f", value);
    return text;
  }
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

std::string formatTransform(const Eigen::Isometry3d& transform) {
  const Eigen::Vector3d p = transform.translation();
  const Eigen::Quaterniond q(transform.rotation());
  return "{position: [" + formatExactNumber(p.x()) + ", " + formatExactNumber(p.y()) + ", " + formatExactNumber(p.z()) +
         "], quaternion_xyzw: [" + formatExactNumber(q.x()) + ", " + formatExactNumber(q.y()) + ", " + formatExactNumber(q.z()) +
         ", " + formatExactNumber(q.w()) + "]}";
}

}  // namespace dualgraph::yaml_fields
