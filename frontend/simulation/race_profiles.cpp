// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/race_profiles.h"

#include <cmath>

namespace dualgraph {
namespace {

constexpr double kDegree = M_PI / 180.0;

// VIO drift `factor` times the model's defaults (biases, random walks, scale error).
VioDriftParams scaledDrift(double factor) {
  VioDriftParams vio;
  vio.yaw_rate_bias *= factor;
  vio.yaw_random_walk *= factor;
  vio.velocity_bias *= factor;
  vio.vertical_velocity_bias *= factor;
  vio.velocity_bias_random_walk *= factor;
  vio.scale_error_sigma *= factor;
  return vio;
}

}  // namespace

const std::vector<std::string>& simulationProfileNames() {
  static const std::vector<std::string> names = {"clean", "realistic", "harsh"};
  return names;
}

Status applySimulationProfile(const std::string& name, RaceSimParams& params) {
  const bool realistic = name == "realistic";
  const bool harsh = name == "harsh";
  if (name != "clean" && !realistic && !harsh) {
    return Status(StatusCode::kInvalidArgument, "unknown simulation profile '" + name + "' (clean, realistic or harsh)");
  }
  DetectionSimParams detection;  // the clean models
  FieldErrorParams field;
  VioDriftParams vio;
  double map_position_sigma = 0.0, map_yaw_sigma = 0.0;
  double lap_speed_variation = 0.0, lap_line_variation = 0.0;
  if (realistic || harsh) {
    detection.pixel_sigma = harsh ? 4.0 : 3.0;
    detection.blur_px_per_rad_s = harsh ? 1.0 : 0.5;
    detection.partial_gates = true;  // real detectors report the visible corners of a gate cut by the image border
    lap_speed_variation = harsh ? 0.10 : 0.05;
    lap_line_variation = harsh ? 0.5 : 0.3;
    detection.displaced_corner_probability = harsh ? 0.05 : 0.03;
    detection.miss_probability = harsh ? 0.3 : 0.2;
    if (harsh) detection.keep_every = 8;  // 120 Hz camera, 15 Hz detector
    field.camera_mount_error_deg = harsh ? 2.0 : 1.5;
    field.camera_time_offset = 0.015;
    field.vio_frame_yaw = M_PI;
    field.vio_frame_offset = 10.0;
    vio = scaledDrift(harsh ? 3.0 : 2.0);
    map_position_sigma = 0.05 / std::sqrt(3.0);  // 5 cm in 3-D
    map_yaw_sigma = 1.5 * kDegree;
  }
  params.detection = detection;
  params.field = field;
  params.vio = vio;
  params.map_position_sigma = map_position_sigma;
  params.map_yaw_sigma = map_yaw_sigma;
  params.flight.lap_speed_variation = lap_speed_variation;
  params.flight.lap_line_variation = lap_line_variation;
  return Status();
}

const std::vector<std::string>& simulationRegimeNames() {
  static const std::vector<std::string> names = {"good_vio", "mono_scale", "vio_clock", "epoch", "big_hall"};
  return names;
}

Status applySimulationRegime(const std::string& name, RaceSimParams& params) {
  if (name == "good_vio") {
    VioDriftParams good = scaledDrift(0.2);  // the drift only: white noise and a scale bias (mono_scale) kept
    good.position_noise = params.vio.position_noise;
    good.rotation_noise = params.vio.rotation_noise;
    good.scale_error_bias = params.vio.scale_error_bias;
    params.vio = good;
  } else if (name == "mono_scale") {
    params.vio.scale_error_bias = 0.075;
  } else if (name == "vio_clock") {
    params.field.vio_time_offset = -0.050;
  } else if (name == "epoch") {
    params.field.time_origin = 1764288000.125;  // 2025-11-28 00:00:00.125 UTC; a multiple of 2^-3 s, exact in a double
  } else if (name == "big_hall") {
    params.track_scale = 2.5;
  } else {
    return Status(StatusCode::kInvalidArgument,
                  "unknown simulation regime '" + name + "' (good_vio, mono_scale, vio_clock, epoch or big_hall)");
  }
  return Status();
}

}  // namespace dualgraph
