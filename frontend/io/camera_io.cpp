// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/camera_io.h"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/core/token_reader.h"
#include "dualgraph/frontend/io/kalibr_camera.h"
#include "dualgraph/frontend/io/yaml_fields.h"

namespace dualgraph {
namespace {

using Marks = std::map<std::string, YAML::Mark>;
using yaml_fields::describe;
using yaml_fields::fieldError;
using yaml_fields::keyName;
using yaml_fields::loadMapping;
using yaml_fields::location;
using yaml_fields::readInteger;
using yaml_fields::readList;
using yaml_fields::readMatrix3;
using yaml_fields::readNumber;
using yaml_fields::readText;
using yaml_fields::readTransform;
using yaml_fields::yamlError;

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
  if (looksLikeKalibrChain(yaml_text)) return parseKalibrCameraYaml(yaml_text, source);  // its cam0
  try {
    auto root = loadMapping(yaml_text, source);
    if (!root.ok()) return root.status();
    CameraModel camera;
    Marks marks;
    double intrinsics[4] = {0, 0, 0, 0};
    const char* kIntrinsicNames[4] = {"fx", "fy", "cx", "cy"};
    std::vector<double> coefficients;
    for (const auto& entry : *root) {
      const std::string key = keyName(entry.first);
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
      } else if (key == "time_offset") {
        DG_RETURN_IF_ERROR(readNumber(source, key, value, camera.time_offset));
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
    return yamlError(source, e);
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
  if (camera.time_offset != 0.0) out << "time_offset: " << camera.time_offset << "\n";
  return out.str();
}

Status saveCameraYaml(const std::string& path, const CameraModel& camera) {
  DG_RETURN_IF_ERROR(camera.validate());
  const std::string text = cameraToYaml(camera);
  return writeFileAtomically(path, [&text](std::ostream& out) {
    out << text;
    return Status();
  });
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
    return yamlError(path, e);
  }
}

}  // namespace dualgraph
