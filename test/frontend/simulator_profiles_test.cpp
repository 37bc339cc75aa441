// SPDX-License-Identifier: MIT
// The simulation profiles and the field errors they switch on: the VIO in its own frame, the camera clock
// offset, the camera-mount error; clean leaves a race as it was.
#include <gtest/gtest.h>

#include <cmath>

#include "dualgraph/frontend/simulation/race_profiles.h"
#include "test/frontend/simulator_fixtures.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

RaceSimParams twoLaps(const std::string& profile) {
  RaceSimParams params;
  params.seed = 3;
  params.override_laps = true;
  params.flight.laps = 2;
  EXPECT_TRUE(applySimulationProfile(profile, params).ok());
  return params;
}

TEST(SimulationProfiles, RealisticSwitchesOnEveryFieldErrorWithinItsStatedRange) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  const CameraModel camera = simtest::ratmCamera();
  const RaceSimParams params = twoLaps("realistic");
  EXPECT_EQ(params.detection.pixel_sigma, 3.0);
  EXPECT_EQ(params.detection.blur_px_per_rad_s, 0.5);
  EXPECT_TRUE(params.detection.partial_gates);
  EXPECT_EQ(params.flight.lap_speed_variation, 0.05);
  EXPECT_EQ(params.flight.lap_line_variation, 0.3);
  auto race = simulateRace(track, camera, params);
  ASSERT_TRUE(race.ok()) << race.status().toString();
  // The VIO frame: a yaw within ±π and an offset within 10 m, horizontal; the VIO's poses carry it.
  const Eigen::Isometry3d& world_T_odom = race->world_T_odom;
  EXPECT_GT(world_T_odom.translation().norm(), 0.0);
  EXPECT_LE(world_T_odom.translation().head<2>().norm(), 10.0);
  EXPECT_EQ(world_T_odom.translation().z(), 0.0);
  EXPECT_NEAR(std::abs(world_T_odom.linear()(2, 2)), 1.0, 1e-12);  // a turn about z only
  const OdometrySample& first = race->vio.samples.front();
  const Eigen::Isometry3d truth = race->flight.at(first.t).world_T_body;
  EXPECT_LT(((world_T_odom * first.odom_T_body).translation() - truth.translation()).norm(), 0.05);
  // The camera clock: every detection stamped 15 ms after an image instant (a multiple of 1/120 s).
  for (const SimulatedDetection& d : race->detections) {
    const double image = (d.corners.t - 0.015) * params.detection.camera_rate;
    ASSERT_NEAR(image, std::round(image), 1e-6) << d.corners.t;
  }
  // The written camera is off by 1.5° from the one that made the images.
  const double angle = so3Log(camera.body_T_camera.linear().transpose() * race->camera.body_T_camera.linear()).norm();
  EXPECT_NEAR(angle * 180.0 / M_PI, 1.5, 1e-9);
}

TEST(SimulationProfiles, CleanKeepsTheRaceAsTheDefaultsMakeIt) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  const CameraModel camera = simtest::ratmCamera();
  RaceSimParams defaults;
  defaults.seed = 3;
  defaults.override_laps = true;
  defaults.flight.laps = 2;
  auto plain = simulateRace(track, camera, defaults);
  auto clean = simulateRace(track, camera, twoLaps("clean"));
  ASSERT_TRUE(plain.ok() && clean.ok());
  EXPECT_TRUE(clean->world_T_odom.matrix().isIdentity(0.0));
  ASSERT_EQ(plain->vio.samples.size(), clean->vio.samples.size());
  EXPECT_TRUE(plain->vio.samples.back().odom_T_body.matrix() == clean->vio.samples.back().odom_T_body.matrix());
  ASSERT_EQ(plain->detections.size(), clean->detections.size());
  EXPECT_EQ(plain->detections.back().corners.t, clean->detections.back().corners.t);
  EXPECT_TRUE(clean->camera.body_T_camera.matrix() == camera.body_T_camera.matrix());
  EXPECT_EQ(clean->detection_stats.partial_views, 0);
  EXPECT_EQ(clean->flight.duration(), plain->flight.duration());
}

TEST(SimulationProfiles, HarshIsHarsherAndUnknownNamesAreRefused) {
  const RaceSimParams realistic = twoLaps("realistic");
  const RaceSimParams harsh = twoLaps("harsh");
  EXPECT_GT(harsh.detection.pixel_sigma, realistic.detection.pixel_sigma);
  EXPECT_GT(harsh.vio.yaw_rate_bias, realistic.vio.yaw_rate_bias);
  EXPECT_GT(harsh.field.camera_mount_error_deg, realistic.field.camera_mount_error_deg);
  EXPECT_GT(harsh.detection.keep_every, realistic.detection.keep_every);
  EXPECT_GT(harsh.detection.blur_px_per_rad_s, realistic.detection.blur_px_per_rad_s);
  EXPECT_GT(harsh.flight.lap_speed_variation, realistic.flight.lap_speed_variation);
  EXPECT_GT(harsh.flight.lap_line_variation, realistic.flight.lap_line_variation);
  EXPECT_TRUE(harsh.detection.partial_gates);
  RaceSimParams params;
  const Status unknown = applySimulationProfile("rainy", params);
  EXPECT_EQ(unknown.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(unknown.message().find("clean, realistic or harsh"), std::string::npos);
  RaceSimParams negative;
  negative.field.camera_mount_error_deg = -1.0;
  EXPECT_EQ(simulateRace(simtest::shippedTrack("ratm_ellipse.yaml"), simtest::ratmCamera(), negative).status().code(),
            StatusCode::kInvalidArgument);
  RaceSimParams endless;
  endless.field.camera_time_offset = INFINITY;  // a negative offset is a camera clock ahead: allowed
  EXPECT_EQ(simulateRace(simtest::shippedTrack("ratm_ellipse.yaml"), simtest::ratmCamera(), endless).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace dualgraph
