// SPDX-License-Identifier: MIT
#pragma once

// Shared by the camera-calibration tests: realistic simulated flights with a chosen clock offset, and the
// error of a calibrated camera against the camera that made the images. Deterministic (fixed seeds).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/simulation/race_profiles.h"
#include "dualgraph/frontend/simulation/race_sequence.h"
#include "test/testing/shared_data.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph::caltest {

/// data/cameras/ratm_piloted.yaml, the camera that takes the simulated images (its mount is the truth).
inline CameraModel trueCamera() {
  auto camera = loadCameraYaml(testing::sourcePath("data/cameras/ratm_piloted.yaml"));
  EXPECT_TRUE(camera.ok()) << camera.status().toString();
  return camera.ok() ? *camera : CameraModel();
}

/// A flight under the `realistic` profile (its 1.5° mount error in the written camera.yaml, 3 px corners, map
/// error, drifting VIO in its own frame) with the detections stamped `time_offset` [s] late.
inline Sequence realisticFlight(const std::string& track_name, std::uint64_t seed, int laps, double time_offset) {
  auto track = loadTrackYaml(testing::sourcePath("data/tracks/" + track_name));
  EXPECT_TRUE(track.ok()) << track.status().toString();
  RaceSimParams params;
  params.seed = seed;
  params.override_laps = laps > 0;
  params.flight.laps = laps;
  EXPECT_TRUE(applySimulationProfile("realistic", params).ok());
  params.field.camera_time_offset = time_offset;
  auto race = simulateRace(*track, trueCamera(), params);
  EXPECT_TRUE(race.ok()) << race.status().toString();
  auto sequence = raceSequence(*race, params, track_name + " seed " + std::to_string(seed));
  EXPECT_TRUE(sequence.ok()) << sequence.status().toString();
  return std::move(sequence).value();
}

/// Angle between two cameras' mount rotations [deg].
inline double mountErrorDeg(const CameraModel& a, const CameraModel& b) {
  return so3Log(a.body_T_camera.linear().transpose() * b.body_T_camera.linear()).norm() * 180.0 / M_PI;
}

/// The default configuration with the self-calibration off: the run a calibrated one is compared with.
inline SequenceRunParams uncalibrated() {
  SequenceRunParams params;
  params.self_calibration_after_s = 0.0;
  return params;
}

}  // namespace dualgraph::caltest
