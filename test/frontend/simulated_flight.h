// SPDX-License-Identifier: MIT
// A simulated race as a sequence folder would hold it: a bundled track, a simulation profile, a seed, some laps.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>

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

}  // namespace dualgraph::flighttest
