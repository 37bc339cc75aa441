// SPDX-License-Identifier: MIT
// The errors of a real flight that the sensor models leave out (camera clock and mount, map), and the seed streams.
#pragma once

#include <cstdint>
#include <string>

#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/track.h"

namespace dualgraph {

/// The errors of a real flight that the sensor models leave out; 0 turns each off (the `clean` profile).
struct FieldErrorParams {
  /// VIO in its own frame: odom is world turned by a yaw drawn uniformly in [−v, v] [rad] ...
  double vio_frame_yaw = 0.0;
  /// ... and moved by an offset drawn uniformly in a horizontal disc of this radius [m] (VIO is gravity aligned).
  double vio_frame_offset = 0.0;
  /// The detections are stamped this much later than the instant the image shows [s] (camera vs VIO clock;
  /// negative: earlier).
  double camera_time_offset = 0.0;
  /// The VIO's samples are stamped this much later than the instant they show [s] (VIO vs ground-truth clock;
  /// negative: the VIO's clock runs behind). The camera's stamps keep the ground truth's clock.
  double vio_time_offset = 0.0;
  /// Every written stamp (ground truth, VIO, detections) is the flight's time plus this [s]: 0 starts the files at
  /// take-off; a Unix time (≈ 1.76e9) writes them as a ROS bag or OpenVINS would.
  double time_origin = 0.0;
  /// The written camera's body_T_camera is off from the one that made the images by a rotation of this angle
  /// about a random axis [deg] (a camera-mount calibration error).
  double camera_mount_error_deg = 0.0;
};

/// What is out of range in `field` and the map perturbation σs (empty when nothing is): every value finite; the
/// VIO frame's yaw and offset, the mount error and both σs ≥ 0.
std::string fieldErrorsProblem(const FieldErrorParams& field, double map_position_sigma, double map_yaw_sigma);

/// Independent random streams from one seed: SplitMix64's finaliser of the seed and a stream number. The
/// simulators' streams: 1 VIO drift, 2 detections, 3 map perturbation, 4 VIO frame, 5 camera mount, 6 lap variation.
std::uint64_t simulationStreamSeed(std::uint64_t seed, std::uint64_t stream);

/// The camera as written: body_T_camera turned by `field.camera_mount_error_deg` about a random axis (stream 5 of
/// `seed`); the camera unchanged, without a draw, when the error is 0.
CameraModel mountedCamera(const CameraModel& camera, const FieldErrorParams& field, std::uint64_t seed);

/// The map as written: every gate centre moved by N(0, position_sigma²) per axis [m] and its yaw by
/// N(0, yaw_sigma²) [rad] (stream 3 of `seed`), line numbers cleared.
Track perturbedMap(const Track& track, double position_sigma, double yaw_sigma, std::uint64_t seed);

}  // namespace dualgraph
