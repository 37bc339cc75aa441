// SPDX-License-Identifier: MIT
#include "frontend/camera_io.h"

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "core/token_reader.h"
#include "types/se3_math.h"

namespace dualgraph {
namespace {

using Marks = std::map<std::string, YAML::Mark>;

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

Status readNumber(const std::string& source, const std::string& field, const YAML::Node& node, double& out) {
  double value = 0.0;
  if (node.IsScalar() && YAML::convert<double>::decode(node, value) && std::isfinite(value)) {
    out = value;
    return Status::okStatus();
  }
  return fieldError(source, node.Mark(), field, "expected a finite number, got " + describe(node));
}

/// Decimal only (yaml-cpp would read "010" as octal).
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

/// A list of numbers; exactly `count` of them unless count is 0.
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
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : describe(entry.first);
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

/// The one mapping document of a file; YAML syntax errors as kParseError with line and column.
Result<YAML::Node> loadMapping(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    const std::string column = e.mark.is_null() ? "" : " (column " + std::to_string(e.mark.column + 1) + ")";
    return Status(StatusCode::kParseError, location(source, e.mark) + ": YAML syntax error: " + e.msg + column);
  }
  if (!root.IsMap()) {
    return Status(StatusCode::kParseError, location(source, root.Mark()) + ": expected a mapping, got " + describe(root));
  }
  return root;
}

/// CameraModel::validate's "camera: field 'NAME': why" placed at NAME's key (aliases: fx → K, K → mtx).
Status locateInvalid(const std::string& source, const Status& status, const Marks& marks, const YAML::Mark& fallback) {
  const std::string& message = status.message();
  const std::string prefix = "camera: field '";
  std::string field;
  if (message.rfind(prefix, 0) == 0) field = message.substr(prefix.size(), message.find('\'', prefix.size()) - prefix.size());
  YAML::Mark mark = fallback;
  const bool intrinsic = field == "fx" || field == "fy" || field == "cx" || field == "cy" || field == "K";
  for (const std::string& name : {field, std::string(intrinsic ? "K" : ""), std::string(intrinsic ? "mtx" : "")}) {
    const auto found = marks.find(name);
    if (!name.empty() && found != marks.end()) {
      mark = found->second;
      break;
    }
  }
  return Status(StatusCode::kParseError, location(source, mark) + ": " + message.substr(message.rfind("camera: ", 0) == 0 ? 8 : 0));
}

}  // namespace

Result<CameraModel> parseCameraYaml(const std::string& yaml_text, const std::string& source) {
  try {
    auto root = loadMapping(yaml_text, source);
    if (!root.ok()) return root.status();
    CameraModel camera;
    Marks marks;
    double intrinsics[4] = {0, 0, 0, 0};
    const char* kIntrinsicNames[4] = {"fx", "fy", "cx", "cy"};
    std::vector<double> coefficients;
    for (const auto& entry : *root) {
      const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : describe(entry.first);
      const YAML::Mark mark = entry.first.Mark();
      const YAML::Node& value = entry.second;
      if (!marks.emplace(key, mark).second) return fieldError(source, mark, key, "duplicate key");
      if (value.IsNull()) return fieldError(source, mark, key, "no value");
      if (key == "model") {
        const std::string text = value.IsScalar() ? value.Scalar() : describe(value);
        if (text != "radtan" && text != "equidistant") {
          return fieldError(source, value.Mark(), key, "expected radtan or equidistant, got " + TokenReader::quoted(text));
        }
        camera.model = text == "radtan" ? CameraModel::Distortion::kRadTan : CameraModel::Distortion::kEquidistant;
      } else if (key == "width" || key == "height") {
        DG_RETURN_IF_ERROR(readInteger(source, key, value, key == "width" ? camera.width : camera.height));
      } else if (key == "K") {
        DG_RETURN_IF_ERROR(readMatrix3(source, key, value, camera.K));
      } else if (key == "distortion") {
        DG_RETURN_IF_ERROR(readList(source, key, value, 0, coefficients));
      } else if (key == "body_T_camera") {
        DG_RETURN_IF_ERROR(readTransform(source, key, value, camera.body_T_camera));
      } else {
        int i = 0;
        while (i < 4 && key != kIntrinsicNames[i]) ++i;
        if (i == 4) return fieldError(source, mark, key, "unknown key");
        DG_RETURN_IF_ERROR(readNumber(source, key, value, intrinsics[i]));
      }
    }
    int given = 0;
    for (const char* name : kIntrinsicNames) given += static_cast<int>(marks.count(name));
    if (marks.count("K") != 0 && given != 0) {
      return fieldError(source, marks.at("K"), "K", "give either K or fx fy cx cy, not both");
    }
    if (marks.count("K") == 0) {
      for (const char* name : kIntrinsicNames) {
        if (marks.count(name) == 0) return fieldError(source, root->Mark(), name, "missing (or give K)");
      }
      camera.K << intrinsics[0], 0.0, intrinsics[2], 0.0, intrinsics[1], intrinsics[3], 0.0, 0.0, 1.0;
    }
    for (const char* required : {"model", "width", "height", "distortion"}) {
      if (marks.count(required) == 0) return fieldError(source, root->Mark(), required, "missing");
    }
    camera.distortion = Eigen::Map<const Eigen::VectorXd>(coefficients.data(), static_cast<Eigen::Index>(coefficients.size()));
    const Status valid = camera.validate();
    if (!valid.ok()) return locateInvalid(source, valid, marks, root->Mark());
    return camera;
  } catch (const YAML::Exception& e) {  // yaml-cpp can throw while iterating a malformed node
    return Status(StatusCode::kParseError, location(source, e.mark) + ": YAML error: " + e.msg);
  }
}

Result<CameraModel> loadCameraYaml(const std::string& path) {
  auto text = readText(path);
  if (!text.ok()) return text.status();
  return parseCameraYaml(*text, path);
}

std::string cameraToYaml(const CameraModel& camera) {
  std::ostringstream out;
  out.precision(17);
  out << "model: " << distortionModelName(camera.model) << "\nwidth: " << camera.width << "\nheight: " << camera.height
      << "\nfx: " << camera.fx() << "\nfy: " << camera.fy() << "\ncx: " << camera.cx() << "\ncy: " << camera.cy()
      << "\ndistortion: [";
  for (Eigen::Index i = 0; i < camera.distortion.size(); ++i) out << (i == 0 ? "" : ", ") << camera.distortion[i];
  const Eigen::Vector3d p = camera.body_T_camera.translation();
  const Eigen::Quaterniond q(camera.body_T_camera.linear());
  out << "]\nbody_T_camera:\n  position: [" << p.x() << ", " << p.y() << ", " << p.z() << "]\n  quaternion_xyzw: ["
      << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n";
  return out.str();
}

Status saveCameraYaml(const std::string& path, const CameraModel& camera) {
  DG_RETURN_IF_ERROR(camera.validate());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return Status(StatusCode::kIoError, path + ": cannot open for writing");
  out << cameraToYaml(camera);
  out.flush();
  if (!out) return Status(StatusCode::kIoError, path + ": write failed");
  return Status::okStatus();
}

Result<CameraModel> loadRatmCalibrationJson(const std::string& path, CameraModel::Distortion model, int width,
                                            int height) {
  if (width <= 0 || height <= 0) {
    return Status(StatusCode::kInvalidArgument, path + ": image size must be positive, got " + std::to_string(width) +
                                                    "x" + std::to_string(height));
  }
  auto text = readText(path);
  if (!text.ok()) return text.status();
  try {
    auto root = loadMapping(*text, path);
    if (!root.ok()) return root.status();
    CameraModel camera;
    camera.model = model;
    camera.width = width;
    camera.height = height;
    Marks marks;
    for (const char* key : {"mtx", "dist"}) {
      if (!(*root)[key]) return fieldError(path, root->Mark(), key, "missing");
      marks.emplace(key, (*root)[key].Mark());
    }
    DG_RETURN_IF_ERROR(readMatrix3(path, "mtx", (*root)["mtx"], camera.K));
    // cv::calibrateCamera writes dist as a 1×N matrix, i.e. [[k1, ...]]; a flat list is accepted too.
    YAML::Node dist = (*root)["dist"];
    std::string field = "dist";
    if (dist.IsSequence() && dist.size() == 1 && dist[0].IsSequence()) {
      dist = dist[0];
      field = "dist[0]";
    }
    const size_t expected = model == CameraModel::Distortion::kRadTan ? 5 : 4;
    std::vector<double> coefficients;
    DG_RETURN_IF_ERROR(readList(path, field, dist, expected, coefficients));
    camera.distortion = Eigen::Map<const Eigen::VectorXd>(coefficients.data(), static_cast<Eigen::Index>(expected));
    const Status valid = camera.validate();
    if (!valid.ok()) return locateInvalid(path, valid, marks, root->Mark());
    return camera;
  } catch (const YAML::Exception& e) {
    return Status(StatusCode::kParseError, location(path, e.mark) + ": YAML error: " + e.msg);
  }
}

}  // namespace dualgraph
