// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/field_errors.h"

#include <cmath>
#include <random>

namespace dualgraph {

std::string fieldErrorsProblem(const FieldErrorParams& field, double map_position_sigma, double map_yaw_sigma) {
  if (!(std::isfinite(map_position_sigma) && map_position_sigma >= 0.0) ||
      !(std::isfinite(map_yaw_sigma) && map_yaw_sigma >= 0.0)) {
    return "map perturbation sigmas must be >= 0";
  }
  for (double value : {field.vio_frame_yaw, field.vio_frame_offset, field.camera_mount_error_deg}) {
    if (!std::isfinite(value) || value < 0.0) return "field errors: frame yaw, offset and mount error must be >= 0";
  }
  if (!std::isfinite(field.camera_time_offset)) return "field errors: camera_time_offset must be finite";
  if (!std::isfinite(field.vio_time_offset) || std::abs(field.vio_time_offset) > 1.0) {
    return "field errors: vio_time_offset must be finite and within +-1 s";
  }
  if (!std::isfinite(field.time_origin) || field.time_origin < 0.0 || field.time_origin > 1e10) {
    return "field errors: time_origin must be in [0, 1e10] s";
  }
  return "";
}

std::uint64_t simulationStreamSeed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

CameraModel mountedCamera(const CameraModel& camera, const FieldErrorParams& field, std::uint64_t seed) {
  CameraModel written = camera;
  if (field.camera_mount_error_deg == 0.0) return written;
  std::mt19937_64 rng(simulationStreamSeed(seed, 5));
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng));
  axis.normalize();
  written.body_T_camera.linear() =
      written.body_T_camera.linear() * Eigen::AngleAxisd(field.camera_mount_error_deg * M_PI / 180.0, axis).toRotationMatrix();
  return written;
}

Track perturbedMap(const Track& track, double position_sigma, double yaw_sigma, std::uint64_t seed) {
  Track map;
  map.name = track.name;
  map.gates = track.gates;
  map.laps = track.laps;
  map.speed = track.speed;
  std::mt19937_64 rng(simulationStreamSeed(seed, 3));
  std::normal_distribution<double> normal(0.0, 1.0);
  for (TrackGate& gate : map.gates) {
    for (int axis = 0; axis < 3; ++axis) gate.position[axis] += position_sigma * normal(rng);
    gate.yaw += yaw_sigma * normal(rng);
    gate.line = 0;
  }
  return map;
}

}  // namespace dualgraph
