// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/run_config.h"

#include <cmath>
#include <map>

#include "dualgraph/frontend/io/localizer_params_node.h"
#include "dualgraph/frontend/io/localizer_params_yaml.h"
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

// Every key of the `frontend:` section and how it is read: the one table runConfigFrontendKeys lists.
using Text = const std::string&;
using Node = const YAML::Node&;
struct FrontendField {
  const char* name;
  Status (*read)(Text source, Text field, Node value, SequenceRunParams& params);
  std::string (*write)(const SequenceRunParams& params);  ///< the value as read back; "" when unset (left out)
};
std::string numberText(double value) { return formatExactNumber(value); }
std::string flagText(bool value) { return value ? "true" : "false"; }
const FrontendField kFrontendFields[] = {
    {"trust_ids", [](Text s, Text f, Node v, SequenceRunParams& p) { return readBool(s, f, v, p.frontend.trust_ids); },
     [](const SequenceRunParams& p) { return flagText(p.frontend.trust_ids); }},
    {"pixel_sigma",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readPositive(s, f, v, p.frontend.pnp.pixel_sigma); },
     [](const SequenceRunParams& p) { return numberText(p.frontend.pnp.pixel_sigma); }},
    {"adaptive_pixel_sigma",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readBool(s, f, v, p.frontend.adaptive_pixel_sigma); },
     [](const SequenceRunParams& p) { return flagText(p.frontend.adaptive_pixel_sigma); }},
    {"partial_gates",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readBool(s, f, v, p.frontend.partial_gates); },
     [](const SequenceRunParams& p) { return flagText(p.frontend.partial_gates); }},
    {"full_gate_rays",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readBool(s, f, v, p.frontend.full_gate_rays); },
     [](const SequenceRunParams& p) { return flagText(p.frontend.full_gate_rays); }},
    {"upright_prior_sigma_deg",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       const Status read = readNumber(s, f, v, p.frontend.upright_prior_sigma_deg);
       if (!read.ok() || p.frontend.upright_prior_sigma_deg >= 0.0) return read;
       return fieldError(s, v.Mark(), f, "must be >= 0 (0: no upright prior)");
     },
     [](const SequenceRunParams& p) { return numberText(p.frontend.upright_prior_sigma_deg); }},
    {"max_reprojection_rms",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readPositive(s, f, v, p.frontend.pnp.max_reprojection_rms);
     },
     [](const SequenceRunParams& p) { return numberText(p.frontend.pnp.max_reprojection_rms); }},
    {"min_range",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.frontend.pnp.min_range); },
     [](const SequenceRunParams& p) { return numberText(p.frontend.pnp.min_range); }},
    {"max_range",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readPositive(s, f, v, p.frontend.pnp.max_range); },
     [](const SequenceRunParams& p) { return numberText(p.frontend.pnp.max_range); }},
    {"min_corner_angle_deg",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readNumber(s, f, v, p.frontend.pnp.min_corner_angle_deg);
     },
     [](const SequenceRunParams& p) { return numberText(p.frontend.pnp.min_corner_angle_deg); }},
    {"max_condition_number",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readPositive(s, f, v, p.frontend.pnp.max_condition_number);
     },
     [](const SequenceRunParams& p) { return numberText(p.frontend.pnp.max_condition_number); }},
    {"pnp_covariance",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readPnpCovariance(s, f, v, p.frontend.pnp.covariance_model);
     },
     [](const SequenceRunParams& p) { return std::string(p.frontend.pnp.covariance_model == PnpCovarianceModel::kLaplace ? "laplace" : "tilt_posterior"); }},
    {"max_refinement_iterations",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readNonNegativeInt(s, f, v, p.frontend.pnp.max_refinement_iterations, 0);
     },
     [](const SequenceRunParams& p) { return std::to_string(p.frontend.pnp.max_refinement_iterations); }},
    {"max_association_distance",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readPositive(s, f, v, p.frontend.association.max_distance);
     },
     [](const SequenceRunParams& p) { return numberText(p.frontend.association.max_distance); }},
    {"max_normal_angle",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readNumber(s, f, v, p.frontend.association.max_normal_angle);
     },
     [](const SequenceRunParams& p) { return numberText(p.frontend.association.max_normal_angle); }},
    {"allow_reversed", [](Text s, Text f, Node v,
                          SequenceRunParams& p) { return readBool(s, f, v, p.frontend.association.allow_reversed); },
     [](const SequenceRunParams& p) { return flagText(p.frontend.association.allow_reversed); }},
    {"mapping_min_sightings",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readNonNegativeInt(s, f, v, p.frontend.association.mapping_min_sightings, 1);
     },
     [](const SequenceRunParams& p) { return std::to_string(p.frontend.association.mapping_min_sightings); }},
    {"mapping_consistency",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readPositive(s, f, v, p.frontend.association.mapping_consistency);
     },
     [](const SequenceRunParams& p) { return numberText(p.frontend.association.mapping_consistency); }},
    {"initialization",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readInitialization(s, f, v, p.auto_initialize); },
     [](const SequenceRunParams& p) { return std::string(p.auto_initialize ? "auto" : "given"); }},
    {"initialization_min_inliers",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readNonNegativeInt(s, f, v, p.initialization.min_inliers, 1);
     },
     [](const SequenceRunParams& p) { return std::to_string(p.initialization.min_inliers); }},
    {"initialization_memory_m",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.initialization.memory_m); },
     [](const SequenceRunParams& p) { return numberText(p.initialization.memory_m); }},
    {"initialization_corner_fit",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readBool(s, f, v, p.initialization.refine_on_corners); },
     [](const SequenceRunParams& p) { return flagText(p.initialization.refine_on_corners); }},
    {"pose_detection_sigma_t",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readPositive(s, f, v, p.pose_detection_sigma_t); },
     [](const SequenceRunParams& p) { return numberText(p.pose_detection_sigma_t); }},
    {"pose_detection_sigma_r",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readPositive(s, f, v, p.pose_detection_sigma_r); },
     [](const SequenceRunParams& p) { return numberText(p.pose_detection_sigma_r); }},
    {"relocalization_sigma_t",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readPositive(s, f, v, p.relocalization.sigma_t); },
     [](const SequenceRunParams& p) { return numberText(p.relocalization.sigma_t); }},
    {"relocalization_sigma_r",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readPositive(s, f, v, p.relocalization.sigma_r); },
     [](const SequenceRunParams& p) { return numberText(p.relocalization.sigma_r); }},
    {"relocalization_global_after_s",
     [](Text s, Text f, Node v, SequenceRunParams& p) {
       return readPositive(s, f, v, p.relocalization.global_after_s);
     },
     [](const SequenceRunParams& p) { return numberText(p.relocalization.global_after_s); }},
    {"relocalization_replace_ratio",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readShare(s, f, v, p.relocalization.replace_ratio); },
     [](const SequenceRunParams& p) { return numberText(p.relocalization.replace_ratio); }},
    {"time_offset",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readTimeOffset(s, f, v, p.time_offset); },
     [](const SequenceRunParams& p) { return p.time_offset ? numberText(*p.time_offset) : std::string(); }},
    {"max_detection_lead_s",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readPositive(s, f, v, p.max_detection_lead_s); },
     [](const SequenceRunParams& p) { return numberText(p.max_detection_lead_s); }},
    {"max_odometry_gap_s",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.max_odometry_gap_s); },
     [](const SequenceRunParams& p) { return numberText(p.max_odometry_gap_s); }},
    {"bridge_odometry_gap_s",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.bridge_odometry_gap_s); },
     [](const SequenceRunParams& p) { return numberText(p.bridge_odometry_gap_s); }},
    {"max_odometry_jump_s",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.max_odometry_jump_s); },
     [](const SequenceRunParams& p) { return numberText(p.max_odometry_jump_s); }},
    {"max_odometry_speed_mps",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.max_odometry_speed_mps); },
     [](const SequenceRunParams& p) { return numberText(p.max_odometry_speed_mps); }},
    {"max_odometry_turn_rate_radps",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.max_odometry_turn_rate_radps); },
     [](const SequenceRunParams& p) { return numberText(p.max_odometry_turn_rate_radps); }},
    {"estimate_odometry_scale",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readBool(s, f, v, p.odometry_scale.enabled); },
     [](const SequenceRunParams& p) { return flagText(p.odometry_scale.enabled); }},
    {"odometry_scale_min_error",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.odometry_scale.min_error); },
     [](const SequenceRunParams& p) { return numberText(p.odometry_scale.min_error); }},
    {"self_calibration_after_s",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.self_calibration_after_s); },
     [](const SequenceRunParams& p) { return numberText(p.self_calibration_after_s); }},
    {"self_calibration_budget_s",
     [](Text s, Text f, Node v, SequenceRunParams& p) { return readNumber(s, f, v, p.self_calibration_budget_s); },
     [](const SequenceRunParams& p) { return numberText(p.self_calibration_budget_s); }},
};

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
    const FrontendField* known = nullptr;
    for (const FrontendField& candidate : kFrontendFields) {
      if (key == candidate.name) known = &candidate;
    }
    if (known == nullptr) return fieldError(source, entry.first.Mark(), field, "unknown key");
    const Status status = known->read(source, field, value, params);
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
  if (!(params.self_calibration_budget_s >= 0.0)) {
    return fieldError(source, markOf("self_calibration_budget_s"), "frontend.self_calibration_budget_s",
                      "must be >= 0 [s] (0: on the pipeline's thread)");
  }
  const std::string scale_bar = params.odometry_scale.minErrorProblem(params.odometry_scale.min_error);
  if (!scale_bar.empty()) {
    return fieldError(source, markOf("odometry_scale_min_error"), "frontend.odometry_scale_min_error",
                      scale_bar + " [-] (the scale's bound, OdometryScaleParams::max_error)");
  }
  if (!(params.max_odometry_gap_s >= 0.0) || !std::isfinite(params.max_odometry_gap_s)) {
    return fieldError(source, markOf("max_odometry_gap_s"), "frontend.max_odometry_gap_s", "must be >= 0 [s] (0: off)");
  }
  if (!(params.initialization.memory_m >= 0.0) || !std::isfinite(params.initialization.memory_m)) {
    return fieldError(source, markOf("initialization_memory_m"), "frontend.initialization_memory_m", "must be >= 0 [m] (0: off)");
  }
  if (!(params.bridge_odometry_gap_s >= 0.0) || !std::isfinite(params.bridge_odometry_gap_s)) {
    return fieldError(source, markOf("bridge_odometry_gap_s"), "frontend.bridge_odometry_gap_s", "must be >= 0 [s] (0: never)");
  }
  if (!(params.max_odometry_jump_s >= 0.0) || !std::isfinite(params.max_odometry_jump_s)) {
    return fieldError(source, markOf("max_odometry_jump_s"), "frontend.max_odometry_jump_s", "must be >= 0 [s] (0: off)");
  }
  if (!(params.max_odometry_speed_mps >= 0.0) || !std::isfinite(params.max_odometry_speed_mps)) {
    return fieldError(source, markOf("max_odometry_speed_mps"), "frontend.max_odometry_speed_mps",
                      "must be >= 0 [m/s] (0: off)");
  }
  if (!(params.max_odometry_turn_rate_radps >= 0.0) || !std::isfinite(params.max_odometry_turn_rate_radps)) {
    return fieldError(source, markOf("max_odometry_turn_rate_radps"), "frontend.max_odometry_turn_rate_radps",
                      "must be >= 0 [rad/s] (0: off)");
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

const std::vector<std::string>& runConfigFrontendKeys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> out;
    for (const FrontendField& field : kFrontendFields) out.emplace_back(field.name);
    return out;
  }();
  return keys;
}

std::string runConfigYaml(const SequenceRunParams& params) {
  std::string out = "localizer:\n" + localizerParamsYaml(params.localizer, "  ") + "frontend:\n";
  for (const FrontendField& field : kFrontendFields) {
    const std::string value = field.write(params);
    if (!value.empty()) out += std::string("  ") + field.name + ": " + value + "\n";
  }
  return out;
}

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

Status validatePipelineLimits(const SequenceRunParams& params) {
  const auto limit = [](double value) { return value >= 0.0 && std::isfinite(value); };
  if (params.max_detection_lead_s > 0.0 && limit(params.max_odometry_gap_s) && limit(params.max_odometry_jump_s) &&
      limit(params.max_odometry_speed_mps) && limit(params.max_odometry_turn_rate_radps) &&
      limit(params.bridge_odometry_gap_s) && limit(params.initialization.memory_m) &&
      limit(params.self_calibration_after_s) && limit(params.self_calibration_budget_s)) {
    return Status();
  }
  return Status(StatusCode::kInvalidArgument, "pipeline: max_detection_lead_s must be > 0 [s]; max_odometry_gap_s, "
                                              "bridge_odometry_gap_s, max_odometry_jump_s [s], max_odometry_speed_mps "
                                              "[m/s], max_odometry_turn_rate_radps [rad/s], initialization.memory_m "
                                              "[m], self_calibration_after_s and self_calibration_budget_s [s] finite "
                                              "and >= 0");
}

}  // namespace dualgraph
