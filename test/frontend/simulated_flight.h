// SPDX-License-Identifier: MIT
// A simulated race as a sequence folder would hold it: a bundled track, a simulation profile, a seed, some laps.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>

#include "dualgraph/frontend/gates/frame_initializer.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/simulation/race_profiles.h"
#include "dualgraph/frontend/simulation/race_sequence.h"
#include "test/testing/shared_data.h"

namespace dualgraph::flighttest {

/// `laps` laps of data/tracks/`track_name` seen by the RATM piloted camera, on `profile` ("clean", "realistic",
/// "harsh") with `seed`; `adjust` may change the parameters after the profile. Failures are test failures.
inline Sequence simulatedFlight(const std::string& track_name, const std::string& profile, std::uint64_t seed,
                                int laps, const std::function<void(RaceSimParams&)>& adjust = {}) {
  auto track = loadTrackYaml(testing::sourcePath("data/tracks/" + track_name));
  auto camera = loadCameraYaml(testing::sourcePath("data/cameras/ratm_piloted.yaml"));
  EXPECT_TRUE(track.ok() && camera.ok());
  if (!track.ok() || !camera.ok()) return Sequence{};
  RaceSimParams params;
  params.seed = seed;
  params.override_laps = true;
  params.flight.laps = laps;
  EXPECT_TRUE(applySimulationProfile(profile, params).ok()) << profile;
  if (adjust) adjust(params);
  auto race = simulateRace(*track, *camera, params);
  EXPECT_TRUE(race.ok()) << race.status().message();
  if (!race.ok()) return Sequence{};
  if (profile != "clean") {
    EXPECT_GT(race->world_T_odom.translation().norm(), 0.5);  // the VIO in its own frame
  }
  auto sequence = raceSequence(*race, params, track_name);
  EXPECT_TRUE(sequence.ok());
  return sequence.ok() ? std::move(sequence).value() : Sequence{};
}

/// The pose of the first sample at or after t (the last one when none is).
inline Eigen::Isometry3d poseAtOrAfter(const std::vector<OdometrySample>& samples, double t) {
  const auto it = std::lower_bound(samples.begin(), samples.end(), t,
                                   [](const OdometrySample& sample, double time) { return sample.t < time; });
  return it == samples.end() ? samples.back().odom_T_body : it->odom_T_body;
}

/// Where the frame the run locked on puts the drone at the lock, and where the truth has it then (world_T_body):
/// the odometry and the ground truth at their first stamps at or after the lock.
inline std::pair<Eigen::Isometry3d, Eigen::Isometry3d> droneAtTheLock(const Sequence& sequence,
                                                                     const FrameInitialization& lock) {
  return {lock.world_T_odom * poseAtOrAfter(sequence.odometry.samples, lock.locked_at),
          poseAtOrAfter(sequence.ground_truth->samples, lock.locked_at)};
}

}  // namespace dualgraph::flighttest
