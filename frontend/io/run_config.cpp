// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/run_config.h"

#include <cmath>
#include <map>

#include "dualgraph/frontend/io/localizer_params_node.h"
#include "dualgraph/frontend/io/yaml_fields.h"

namespace dualgraph {
namespace {

using namespace yaml_fields;

Status readPnpCovariance(const std::string& source, const std::string& field, const YAML::Node& node,
                         PnpCovarianceModel& out) {
  if (node.IsScalar() && (node.Scalar() == "tilt_posterior" || node.Scalar() == "laplace")) {
    out = node.Scalar() == "laplace" ? PnpCovarianceModel::kLaplace : PnpCovarianceModel::kTiltPosterior;
    return Status();
  }
  return fieldError(source, node.Mark(), field, "expected tilt_posterior or laplace, got " + describe(node));
}

Status readInitialization(const std::string& source, const std::string& field, const YAML::Node& node, bool& automatic) {
  if (node.IsScalar() && (node.Scalar() == "auto" || node.Scalar() == "given")) {
    automatic = node.Scalar() == "auto";
    return Status();
  }
  return fieldError(source, node.Mark(), field, "expected auto or given, got " + describe(node));
}

Status readNonNegativeInt(const std::string& source, const std::string& field, const YAML::Node& node, int& out, int min) {
  DG_RETURN_IF_ERROR(readInteger(source, field, node, out));
  if (out < min) return fieldError(source, node.Mark(), field, "must be >= " + std::to_string(min));
  return Status();
}

Status readShare(const std::string& source, const std::string& field, const YAML::Node& node, double& out) {
  DG_RETURN_IF_ERROR(readNumber(source, field, node, out));
  if (!(out >= 0.0 && out <= 1.0)) return fieldError(source, node.Mark(), field, "must be in [0, 1]");
  return Status();
}

Status readTimeOffset(const std::string& source, const std::string& field, const YAML::Node& node,
                      std::optional<double>& out) {
  double offset = 0.0;
  DG_RETURN_IF_ERROR(readNumber(source, field, node, offset));
  if (std::abs(offset) > 1.0) return fieldError(source, node.Mark(), field, "must be at most 1 s in magnitude [s]");
  out = offset;
  return Status();
}

Status readFrontend(const std::string& source, const YAML::Node& section, SequenceRunParams& params) {
  if (!section.IsMap()) return fieldError(source, section.Mark(), "frontend", "expected a mapping, got " + describe(section));
  GatePnpParams& pnp = params.frontend.pnp;
  AssociationParams& association = params.frontend.association;
  std::map<std::string, YAML::Mark> marks;  // where each key was: the checks across keys name its line
  for (const auto& entry : section) {
    const std::string key = keyName(entry.first);
    const std::string field = "frontend." + key;
    const YAML::Node& value = entry.second;
    if (!marks.emplace(key, entry.first.Mark()).second) return fieldError(source, entry.first.Mark(), field, "duplicate key");
    Status status;
    if (key == "trust_ids") status = readBool(source, field, value, params.frontend.trust_ids);
    else if (key == "pixel_sigma") status = readPositive(source, field, value, pnp.pixel_sigma);
    else if (key == "adaptive_pixel_sigma") status = readBool(source, field, value, params.frontend.adaptive_pixel_sigma);
    else if (key == "partial_gates") status = readBool(source, field, value, params.frontend.partial_gates);
    else if (key == "upright_prior_sigma_deg") {
      status = readNumber(source, field, value, params.frontend.upright_prior_sigma_deg);
      if (status.ok() && params.frontend.upright_prior_sigma_deg < 0.0) {
        status = fieldError(source, value.Mark(), field, "must be >= 0 (0: no upright prior)");
      }
    }
    else if (key == "max_reprojection_rms") status = readPositive(source, field, value, pnp.max_reprojection_rms);
    else if (key == "min_range") status = readNumber(source, field, value, pnp.min_range);
    else if (key == "max_range") status = readPositive(source, field, value, pnp.max_range);
    else if (key == "min_corner_angle_deg") status = readNumber(source, field, value, pnp.min_corner_angle_deg);
    else if (key == "max_condition_number") status = readPositive(source, field, value, pnp.max_condition_number);
    else if (key == "pnp_covariance") status = readPnpCovariance(source, field, value, pnp.covariance_model);
    else if (key == "max_refinement_iterations") status = readNonNegativeInt(source, field, value, pnp.max_refinement_iterations, 0);
    else if (key == "max_association_distance") status = readPositive(source, field, value, association.max_distance);
    else if (key == "max_normal_angle") status = readNumber(source, field, value, association.max_normal_angle);
    else if (key == "allow_reversed") status = readBool(source, field, value, association.allow_reversed);
    else if (key == "mapping_min_sightings") status = readNonNegativeInt(source, field, value, association.mapping_min_sightings, 1);
    else if (key == "mapping_consistency") status = readPositive(source, field, value, association.mapping_consistency);
    else if (key == "initialization") status = readInitialization(source, field, value, params.auto_initialize);
    else if (key == "initialization_min_inliers") status = readNonNegativeInt(source, field, value, params.initialization.min_inliers, 1);
    else if (key == "pose_detection_sigma_t") status = readPositive(source, field, value, params.pose_detection_sigma_t);
    else if (key == "pose_detection_sigma_r") status = readPositive(source, field, value, params.pose_detection_sigma_r);
    else if (key == "relocalization_sigma_t") status = readPositive(source, field, value, params.relocalization.sigma_t);
    else if (key == "relocalization_sigma_r") status = readPositive(source, field, value, params.relocalization.sigma_r);
    else if (key == "relocalization_global_after_s") status = readPositive(source, field, value, params.relocalization.global_after_s);
    else if (key == "relocalization_replace_ratio") status = readShare(source, field, value, params.relocalization.replace_ratio);
    else if (key == "time_offset") status = readTimeOffset(source, field, value, params.time_offset);
    else if (key == "max_detection_lead_s") status = readPositive(source, field, value, params.max_detection_lead_s);
    else if (key == "max_odometry_gap_s") status = readNumber(source, field, value, params.max_odometry_gap_s);
    else if (key == "self_calibration_after_s") status = readNumber(source, field, value, params.self_calibration_after_s);
    else return fieldError(source, entry.first.Mark(), field, "unknown key");
    DG_RETURN_IF_ERROR(status);
  }
  auto markOf = [&](const std::string& key) {
    const auto found = marks.find(key);
    return found != marks.end() ? found->second : section.Mark();
  };
  if (pnp.min_range < 0.0 || pnp.min_range >= pnp.max_range) {
    const std::string key = marks.count("min_range") != 0 || marks.count("max_range") == 0 ? "min_range" : "max_range";
    return fieldError(source, markOf(key), "frontend." + key, "min_range must be >= 0 and below max_range");
  }
  if (!(params.self_calibration_after_s >= 0.0)) {
    return fieldError(source, markOf("self_calibration_after_s"), "frontend.self_calibration_after_s",
                      "must be >= 0 [s] (0: off)");
  }
  if (!(params.max_odometry_gap_s >= 0.0) || !std::isfinite(params.max_odometry_gap_s)) {
    return fieldError(source, markOf("max_odometry_gap_s"), "frontend.max_odometry_gap_s", "must be >= 0 [s] (0: off)");
  }
  if (pnp.min_corner_angle_deg < 0.0 || pnp.min_corner_angle_deg >= 90.0) {
    return fieldError(source, markOf("min_corner_angle_deg"), "frontend.min_corner_angle_deg", "must be in [0, 90)");
  }
  if (!(association.max_normal_angle >= 0.0 && association.max_normal_angle <= M_PI)) {
    return fieldError(source, markOf("max_normal_angle"), "frontend.max_normal_angle", "must be in [0, pi] [rad]");
  }
  const Status association_valid = validateAssociationParams(association);
  if (!association_valid.ok()) {
    return Status(StatusCode::kParseError, location(source, section.Mark()) + ": " + association_valid.message());
  }
  return Status();
}

}  // namespace

Matrix6d SequenceRunParams::defaultPoseDetectionCovariance() const {
  Vector6d variance;
  variance << Eigen::Vector3d::Constant(pose_detection_sigma_t * pose_detection_sigma_t),
      Eigen::Vector3d::Constant(pose_detection_sigma_r * pose_detection_sigma_r);
  return variance.asDiagonal();
}

Result<SequenceRunParams> parseRunConfig(const std::string& yaml_text, const std::string& source_name) {
  SequenceRunParams params;
  auto root = loadDocument(yaml_text, source_name);  // once, for both sections
  if (!root.ok()) return root.status();
  auto localizer = readLocalizerParams(source_name, *root, {"frontend"});
  if (!localizer.ok()) return localizer.status();
  params.localizer = *localizer;
  try {
    if (root->IsMap() && (*root)["frontend"]) DG_RETURN_IF_ERROR(readFrontend(source_name, (*root)["frontend"], params));
  } catch (const YAML::Exception& e) {
    return yamlError(source_name, e);
  }
  return params;
}

Result<SequenceRunParams> loadRunConfig(const std::string& path) {
  auto text = readText(path);
  if (!text.ok()) return text.status();
  return parseRunConfig(*text, path);
}

}  // namespace dualgraph
