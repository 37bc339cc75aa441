// SPDX-License-Identifier: MIT
// Feeding a synthetic race to a Localizer the way it runs onboard: one merged stream in time order
// (an observation before the odometry sample of the same instant).
#pragma once

#include <gtest/gtest.h>

#include "dualgraph/dual_graph/localizer.h"
#include "test/testing/synthetic_race.h"

namespace dualgraph::testing {

struct RunOutput {
  std::vector<Eigen::Isometry3d> corrected;  ///< one per odometry sample
  std::vector<Eigen::Isometry3d> odometry;   ///< the raw VIO, in the world frame it started in
};

inline RunOutput runRace(Localizer& localizer, const SyntheticRace& race) {
  RunOutput out;
  size_t next_observation = 0;
  for (const OdometrySample& sample : race.odometry) {
    while (next_observation < race.observations.size() && race.observations[next_observation].t <= sample.t) {
      const Status accepted = localizer.addObservation(race.observations[next_observation++]);
      EXPECT_TRUE(accepted.ok()) << accepted.toString();
    }
    Result<CorrectedPose> pose = localizer.addOdometry(sample);
    EXPECT_TRUE(pose.ok()) << pose.status().toString();
    out.corrected.push_back(pose.ok() ? pose->world_T_body : Eigen::Isometry3d::Identity());
    out.odometry.push_back(sample.odom_T_body);
  }
  EXPECT_TRUE(localizer.finish().ok());
  return out;
}

inline std::unique_ptr<Localizer> makeLocalizer(const LocalizerParams& params, const GateMap& map) {
  Result<std::unique_ptr<Localizer>> localizer = Localizer::create(params, map);
  EXPECT_TRUE(localizer.ok()) << localizer.status().toString();
  return localizer.ok() ? std::move(*localizer) : nullptr;
}

}  // namespace dualgraph::testing
