// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/kalibr_camera.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <vector>

#include "dualgraph/core/token_reader.h"
#include "dualgraph/frontend/io/yaml_fields.h"

namespace dualgraph {
namespace {

using yaml_fields::fieldError;

// A 4×4 rigid transform given as four rows of four numbers; `field` names it in messages.
Status readRigid(const std::string& source, const std::string& field, const YAML::Node& node, Eigen::Isometry3d& out) {
  if (!node.IsSequence() || node.size() != 4) return fieldError(source, node.Mark(), field, "expected 4 rows of 4 numbers");
  Eigen::Matrix4d m;
  for (size_t r = 0; r < 4; ++r) {
    std::vector<double> row;
    DG_RETURN_IF_ERROR(yaml_fields::readList(source, field + "[" + std::to_string(r) + "]", node[r], 4, row));
    for (size_t c = 0; c < 4; ++c) m(static_cast<int>(r), static_cast<int>(c)) = row[c];
  }
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if (!m.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1), 1e-12) || !(R.transpose() * R).isIdentity(1e-6) ||
      !(R.determinant() > 0.0)) {
    return fieldError(source, node.Mark(), field, "not a rigid transform (rotation orthonormal to 1e-6, det +1, last row 0 0 0 1)");
  }
  out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  out.translation() = m.topRightCorner<3, 1>();
  return Status();
}

}  // namespace

std::string withoutOpenCvYamlDirective(const std::string& yaml_text) {
  const size_t start = yaml_text.find_first_not_of(" \t\r\n");
  if (start == std::string::npos || yaml_text.compare(start, 6, "%YAML:") != 0) return yaml_text;
  std::string text = yaml_text;
  text[start] = '#';
  return text;
}

bool looksLikeKalibrChain(const std::string& yaml_text) {
  auto root = yaml_fields::loadMapping(withoutOpenCvYamlDirective(yaml_text), "camera");
  try {
    return root.ok() && (*root)["cam0"] && (*root)["cam0"].IsMap() && !(*root)["model"];
  } catch (const YAML::Exception&) {
    return false;
  }
}

Result<CameraModel> parseKalibrCameraYaml(const std::string& yaml_text, const std::string& source, const std::string& name) {
  try {
    auto root = yaml_fields::loadMapping(withoutOpenCvYamlDirective(yaml_text), source);
    if (!root.ok()) return root.status();
    const YAML::Node chain = *root;
    if (!chain[name] || !chain[name].IsMap()) {
      return fieldError(source, chain.Mark(), name, "missing: not a Kalibr camera chain with this camera");
    }
    const YAML::Node cam = chain[name];
    std::map<std::string, YAML::Mark> marks;
    CameraModel camera;
    std::vector<double> intrinsics, coefficients, resolution;
    std::string projection, distortion;
    bool have_transform = false;
    double shift = 0.0;
    for (const auto& entry : cam) {
      const std::string key = yaml_fields::keyName(entry.first);
      const std::string field = name + "." + key;
      const YAML::Node& value = entry.second;
      if (!marks.emplace(key, entry.first.Mark()).second) return fieldError(source, entry.first.Mark(), field, "duplicate key");
      if (key == "camera_model") {
        DG_RETURN_IF_ERROR(yaml_fields::readString(source, field, value, projection));
      } else if (key == "intrinsics") {
        DG_RETURN_IF_ERROR(yaml_fields::readList(source, field, value, 0, intrinsics));
      } else if (key == "distortion_model") {
        DG_RETURN_IF_ERROR(yaml_fields::readString(source, field, value, distortion));
      } else if (key == "distortion_coeffs") {
        DG_RETURN_IF_ERROR(yaml_fields::readList(source, field, value, 0, coefficients));
      } else if (key == "resolution") {
        DG_RETURN_IF_ERROR(yaml_fields::readList(source, field, value, 2, resolution));
      } else if (key == "T_cam_imu" || key == "T_imu_cam") {
        if (have_transform) return fieldError(source, entry.first.Mark(), field, "give T_cam_imu or T_imu_cam, not both");
        Eigen::Isometry3d T;
        DG_RETURN_IF_ERROR(readRigid(source, field, value, T));
        camera.body_T_camera = key == "T_cam_imu" ? T.inverse() : T;
        have_transform = true;
      } else if (key == "timeshift_cam_imu") {
        DG_RETURN_IF_ERROR(yaml_fields::readNumber(source, field, value, shift));
      } else if (key != "rostopic" && key != "cam_overlaps" && key != "T_cn_cnm1") {
        return fieldError(source, entry.first.Mark(), field, "unknown key");
      }
    }
    for (const char* required : {"camera_model", "intrinsics", "distortion_model", "distortion_coeffs", "resolution"}) {
      if (marks.count(required) == 0) return fieldError(source, cam.Mark(), name + "." + required, "missing");
    }
    const auto at = [&](const char* key) { return marks.at(key); };
    if (projection != "pinhole") {
      return fieldError(source, at("camera_model"), name + ".camera_model",
                        TokenReader::quoted(projection) + " is not supported (pinhole with radtan or equidistant)");
    }
    if (intrinsics.size() != 4) {
      return fieldError(source, at("intrinsics"), name + ".intrinsics",
                        "expected 4 values [fu, fv, pu, pv] for pinhole, got " + std::to_string(intrinsics.size()));
    }
    if (distortion == "radtan" || distortion == "none") {
      camera.model = CameraModel::Distortion::kRadTan;
      if (distortion == "none" && coefficients.empty()) coefficients.assign(4, 0.0);
    } else if (distortion == "equidistant") {
      camera.model = CameraModel::Distortion::kEquidistant;
    } else {
      return fieldError(source, at("distortion_model"), name + ".distortion_model",
                        TokenReader::quoted(distortion) + " is not supported (radtan, equidistant or none)");
    }
    const size_t expected = camera.model == CameraModel::Distortion::kEquidistant ? 4 : coefficients.size() == 5 ? 5 : 4;
    if (coefficients.size() != expected) {
      return fieldError(source, at("distortion_coeffs"), name + ".distortion_coeffs",
                        "expected " + std::to_string(expected) + " values for " + distortion + ", got " +
                            std::to_string(coefficients.size()));
    }
    for (size_t k = 0; k < 2; ++k) {
      if (resolution[k] != std::floor(resolution[k]) || !(resolution[k] > 0.0) || resolution[k] > 1e6) {
        return fieldError(source, at("resolution"), name + ".resolution[" + std::to_string(k) + "]",
                          "expected a positive whole number of pixels");
      }
    }
    camera.width = static_cast<int>(resolution[0]);
    camera.height = static_cast<int>(resolution[1]);
    camera.K << intrinsics[0], 0.0, intrinsics[2], 0.0, intrinsics[1], intrinsics[3], 0.0, 0.0, 1.0;
    camera.distortion = Eigen::Map<const Eigen::VectorXd>(coefficients.data(), static_cast<Eigen::Index>(coefficients.size()));
    camera.time_offset = -shift;
    const Status valid = camera.validate();
    if (!valid.ok()) return Status(StatusCode::kParseError, yaml_fields::location(source, cam.Mark()) + ": " + name + ": " + valid.message());
    return camera;
  } catch (const YAML::Exception& e) {
    return yaml_fields::yamlError(source, e);
  }
}

}  // namespace dualgraph
