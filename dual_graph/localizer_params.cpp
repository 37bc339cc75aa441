// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/localizer_params.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "dualgraph/core/robust_kernel.h"
#include "dualgraph/dual_graph/observation_model.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
namespace {

// Shortest text that reads back to the same double ("-1", "0.1", "nan", "inf").
std::string formatValue(double value) {
  char buffer[32];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, value);
    if (!std::isfinite(value) || std::strtod(buffer, nullptr) == value) break;
  }
  return buffer;
}

Status invalid(const char* field, const std::string& why) {
  return Status(StatusCode::kInvalidArgument, std::string("field '") + field + "': " + why);
}

Status requirePositiveFinite(const char* field, double value) {
  if (std::isfinite(value) && value > 0.0) return Status::okStatus();
  return invalid(field, "must be finite and > 0, got " + formatValue(value));
}

Status requireNonNegativeFinite(const char* field, double value) {
  if (std::isfinite(value) && value >= 0.0) return Status::okStatus();
  return invalid(field, "must be finite and >= 0, got " + formatValue(value));
}

Status requireFinite(const char* field, double value) {
  if (std::isfinite(value)) return Status::okStatus();
  return invalid(field, "must be finite, got " + formatValue(value));
}

Status requireAtLeastOne(const char* field, int value) {
  if (value >= 1) return Status::okStatus();
  return invalid(field, "must be >= 1, got " + std::to_string(value));
}

Status validateRigid(const char* field, const Eigen::Isometry3d& transform) {
  if (!transform.linear().allFinite() || !transform.translation().allFinite()) {
    return invalid(field, "has a non-finite entry");
  }
  const Eigen::Matrix3d rotation = transform.linear();
  const double orthonormality_error = (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm();
  if (!(orthonormality_error < 1e-6)) {
    return invalid(field, "rotation is not orthonormal (|R^T R - I| = " + formatValue(orthonormality_error) + ")");
  }
  if (!(rotation.determinant() > 0.0)) return invalid(field, "rotation is a reflection (det R < 0)");
  return Status::okStatus();
}

Status validateChoices(const LocalizerParams& params) {
  // Guards against out-of-range casts; every named enumerator has a name other than "unknown".
  if (std::string(localizerModeName(params.mode)) == "unknown") return invalid("mode", "is not a LocalizerMode");
  if (std::string(landmarkModelName(params.landmark)) == "unknown") {
    return invalid("landmark", "is not a LandmarkModel");
  }
  if (std::string(linearSolverKindName(params.linear_solver)) == "unknown") {
    return invalid("linear_solver", "is not a LinearSolverKind");
  }
  if (std::string(lmDampingName(params.lm_damping)) == "unknown") return invalid("lm_damping", "is not an LmDamping");
  if (std::string(temporarySolverKindName(params.temp_solver)) == "unknown") {
    return invalid("temp_solver", "is not a TemporarySolverKind");
  }
  return Status::okStatus();
}

Status validateSpacing(const LocalizerParams& params) {
  DG_RETURN_IF_ERROR(requirePositiveFinite("d_main", params.d_main));
  DG_RETURN_IF_ERROR(requirePositiveFinite("theta_main", params.theta_main));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("keyframe_max_interval_s", params.keyframe_max_interval_s));
  DG_RETURN_IF_ERROR(requirePositiveFinite("d_temp", params.d_temp));
  DG_RETURN_IF_ERROR(requirePositiveFinite("theta_temp", params.theta_temp));
  DG_RETURN_IF_ERROR(requirePositiveFinite("d_single", params.d_single));
  return requirePositiveFinite("theta_single", params.theta_single);
}

Status validateUncertainties(const LocalizerParams& params) {
  DG_RETURN_IF_ERROR(validateSigma("odom_sigma_t", params.odom_sigma_t));
  DG_RETURN_IF_ERROR(validateSigma("odom_sigma_r", params.odom_sigma_r));
  DG_RETURN_IF_ERROR(validateSigma("odom_sigma_tilt", params.odom_sigma_tilt));
  DG_RETURN_IF_ERROR(requirePositiveFinite("odom_min_distance", params.odom_min_distance));
  DG_RETURN_IF_ERROR(requirePositiveFinite("odom_scale_min", params.odom_scale_min));
  DG_RETURN_IF_ERROR(requirePositiveFinite("odom_scale_max", params.odom_scale_max));
  if (params.odom_scale_min > params.odom_scale_max) return invalid("odom_scale_min", "must not exceed odom_scale_max");
  DG_RETURN_IF_ERROR(validateSigma("map_sigma_t", params.map_sigma_t));
  DG_RETURN_IF_ERROR(validateSigma("map_sigma_r", params.map_sigma_r));
  DG_RETURN_IF_ERROR(validateRigid("initial_world_T_odom", params.initial_world_T_odom));
  // σ_t ≤ 0 means "fix the first keyframe", so σ_r only matters (and must be positive) when σ_t > 0.
  DG_RETURN_IF_ERROR(requireFinite("initial_sigma_t", params.initial_sigma_t));
  if (params.initial_sigma_t > 0.0) {
    DG_RETURN_IF_ERROR(validateSigma("initial_sigma_t", params.initial_sigma_t));
    DG_RETURN_IF_ERROR(validateSigma("initial_sigma_r", params.initial_sigma_r));
  } else {
    DG_RETURN_IF_ERROR(requireFinite("initial_sigma_r", params.initial_sigma_r));
  }
  return Status::okStatus();
}

Status validateOptimisation(const LocalizerParams& params) {
  DG_RETURN_IF_ERROR(requireAtLeastOne("main_max_iterations", params.main_max_iterations));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("main_time_budget_ms", params.main_time_budget_ms));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("main_relative_decrease_stop", params.main_relative_decrease_stop));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("temp_relative_decrease_stop", params.temp_relative_decrease_stop));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("temp_model_decrease_stop", params.temp_model_decrease_stop));
  if (params.main_window != 0 && params.main_window < 2) {
    return invalid("main_window", "must be 0 (full batch) or at least 2, got " + std::to_string(params.main_window));
  }
  DG_RETURN_IF_ERROR(requireAtLeastOne("temp_max_iterations", params.temp_max_iterations));
  if (params.robust_kernel != "none") {
    auto kernel = makeRobustKernel(params.robust_kernel);
    if (!kernel.ok()) return invalid("robust_kernel", kernel.status().message() + " (\"none\" for no kernel)");
  }
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("distilled_floor_range", params.distilled_floor_range));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("distilled_floor_lateral", params.distilled_floor_lateral));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("distilled_floor_rotation", params.distilled_floor_rotation));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("chi2_gate_pose", params.chi2_gate_pose));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("chi2_gate_point", params.chi2_gate_point));
  DG_RETURN_IF_ERROR(requirePositiveFinite("lost_after_s", params.lost_after_s));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("detection_latency", params.detection_latency));
  DG_RETURN_IF_ERROR(requireNonNegativeFinite("max_observation_lead_s", params.max_observation_lead_s));
  return requireAtLeastOne("lost_min_failures", params.lost_min_failures);
}

}  // namespace

// 1e200 or 1e-200 pass requirePositiveFinite but make an infinite or zero variance, an information matrix no graph
// can use.
Status validateSigma(const char* field, double sigma) {
  if (std::isfinite(sigma) && sigma > 0.0 && std::isnormal(sigma * sigma) && std::isnormal(1.0 / (sigma * sigma))) {
    return Status::okStatus();
  }
  return invalid(field, "must be a usable standard deviation (finite, > 0, its square and the square's inverse "
                        "finite and non-zero), got " + formatValue(sigma));
}

Status validateLocalizerParams(const LocalizerParams& params) {
  DG_RETURN_IF_ERROR(validateChoices(params));
  DG_RETURN_IF_ERROR(validateSpacing(params));
  DG_RETURN_IF_ERROR(validateUncertainties(params));
  return validateOptimisation(params);
}

const char* localizerModeName(LocalizerMode mode) {
  switch (mode) {
    case LocalizerMode::kDual: return "dual";
    case LocalizerMode::kSingle: return "single";
  }
  return "unknown";
}

const char* landmarkModelName(LandmarkModel model) {
  switch (model) {
    case LandmarkModel::kPose: return "pose";
    case LandmarkModel::kPoint: return "point";
  }
  return "unknown";
}

const char* temporarySolverKindName(TemporarySolverKind kind) {
  switch (kind) {
    case TemporarySolverKind::kBlock: return "block";
    case TemporarySolverKind::kGraph: return "graph";
  }
  return "unknown";
}

Status validateGateMapFor(const LocalizerParams& params, const GateMap& map) {
  if (!params.mapping && map.world_T_gate.empty()) {
    return Status(StatusCode::kInvalidArgument, "localization mode needs a gate map (or set mapping: true)");
  }
  for (const auto& [id, world_T_gate] : map.world_T_gate) {
    if (id < 0) return Status(StatusCode::kInvalidArgument, "gate map: negative gate id " + std::to_string(id));
    DG_RETURN_IF_ERROR(checkRigidTransform(world_T_gate, "gate map: gate " + std::to_string(id)));
  }
  return Status::okStatus();
}

Status checkObservationFor(const LocalizerParams& params, const GateMap& map, const GateObservation& observation,
                           const std::string& what) {
  if (!params.mapping && !map.contains(observation.gate_id)) {
    return Status(StatusCode::kNotFound, what + ": gate " + std::to_string(observation.gate_id) + " is not in the map");
  }
  DG_RETURN_IF_ERROR(observationModel(observation.kind).checkUsable(params, what));
  return Status::okStatus();
}

OdometryNoiseModel noiseModelOf(const LocalizerParams& params) {
  OdometryNoiseModel model;
  model.use_input_covariance = params.use_input_covariance;
  model.sigma_t = params.odom_sigma_t;
  model.sigma_r = params.odom_sigma_r;
  model.sigma_tilt = params.odom_sigma_tilt;
  model.min_distance = params.odom_min_distance;
  return model;
}

}  // namespace dualgraph
