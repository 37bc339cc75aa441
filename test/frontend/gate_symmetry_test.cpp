// SPDX-License-Identifier: MIT
// nearestGateSymmetry: the square gate's relabelling nearest a reference, whatever the frame both are given in; and
// the simulated pose detector's gates turned with it, their mirrored tilt too.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "dualgraph/frontend/gates/gate_symmetry.h"
#include "dualgraph/frontend/simulation/race_simulator.h"
#include "test/frontend/simulator_fixtures.h"

namespace dualgraph {
namespace {

Eigen::Matrix3d rotation(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Eigen::Matrix3d symmetry(int side, int quarter) {
  return rotation(side * M_PI, Eigen::Vector3d::UnitZ()) * rotation(quarter * M_PI / 2, Eigen::Vector3d::UnitX());
}

double angleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

TEST(GateSymmetry, FindsTheRelabellingOfADetectedGateUpToItsNoise) {
  const Eigen::Matrix3d reference = rotation(0.7, Eigen::Vector3d(0.2, -0.4, 1.0));
  const Eigen::Matrix3d noise = rotation(0.15, Eigen::Vector3d(1.0, 2.0, -0.5));  // 8.6 deg: a poor PnP
  for (int side = 0; side < 2; ++side) {
    for (int quarter = 0; quarter < 4; ++quarter) {
      const Eigen::Matrix3d truth = symmetry(side, quarter);
      // Detected with its labels off by `truth`: relabelled by it, it is the reference but for the noise.
      const Eigen::Matrix3d detected = reference * noise * truth.transpose();
      const Eigen::Matrix3d found = nearestGateSymmetry(reference, detected, GateSides::kEither);
      EXPECT_LT(angleBetween(found, truth), 1e-9) << "side " << side << ", quarter " << quarter;
      if (side == 0) {
        EXPECT_LT(angleBetween(nearestGateSymmetry(reference, detected, GateSides::kKnown), truth), 1e-9) << quarter;
      }
    }
  }
}

TEST(GateSymmetry, AKnownSideIsNeverSwappedAndTheFrameDoesNotMatter) {
  const Eigen::Matrix3d reference = rotation(-1.2, Eigen::Vector3d(0.0, 0.3, 1.0));
  const Eigen::Matrix3d seen_from_behind = reference * symmetry(1, 1).transpose();
  // With the side known only quarter turns about the normal are candidates: x stays x.
  const Eigen::Matrix3d turn = nearestGateSymmetry(reference, seen_from_behind, GateSides::kKnown);
  EXPECT_NEAR(turn(0, 0), 1.0, 1e-12);
  EXPECT_LT(angleBetween(nearestGateSymmetry(reference, seen_from_behind, GateSides::kEither), symmetry(1, 1)), 1e-9);
  // The same two orientations in another frame (body instead of world): the same relabelling.
  const Eigen::Matrix3d body_R_world = rotation(2.1, Eigen::Vector3d(1.0, -1.0, 0.4));
  for (GateSides sides : {GateSides::kKnown, GateSides::kEither}) {
    const Eigen::Matrix3d detected = reference * rotation(0.2, Eigen::Vector3d::UnitY()) * symmetry(0, 3).transpose();
    EXPECT_LT(angleBetween(nearestGateSymmetry(reference, detected, sides),
                           nearestGateSymmetry(body_R_world * reference, body_R_world * detected, sides)),
              1e-12);
  }
}

// The simulator's pose detector reports the quarter turn nearest the true gate; an ambiguous view's mirrored tilt
// is the same gate seen with the other tilt, so it turns with the pose (it stayed behind once, a quarter turn off).
TEST(GateSymmetry, ASimulatedPoseDetectionsMirroredTiltTurnsWithIt) {
  const Track track = simtest::shippedTrack("ratm_lemniscate.yaml");
  RaceSimParams params;
  params.seed = 3;
  params.override_laps = true;
  params.flight.laps = 2;
  params.output = RaceSimParams::DetectionOutput::kPoses;
  const auto race = simulateRace(track, simtest::ratmCamera(), params);
  ASSERT_TRUE(race.ok()) << race.status().toString();
  const GateMap map = track.gateMap().value();
  int alternatives = 0, turned = 0;
  for (const GateObservation& o : race->pose_detections) {
    const Eigen::Matrix3d truth = (race->flight.at(o.t).world_T_body.inverse() * map.world_T_gate.at(o.gate_id)).linear();
    EXPECT_TRUE(nearestGateSymmetry(truth, o.body_T_gate.linear(), GateSides::kKnown).isIdentity(0.0)) << o.t;
    if (!o.has_alternative) continue;
    ++alternatives;
    const Eigen::Matrix3d turn = nearestGateSymmetry(truth, o.alternative_body_T_gate.linear(), GateSides::kKnown);
    if (!turn.isIdentity(0.0)) ++turned;
  }
  ASSERT_GT(alternatives, 50);
  EXPECT_EQ(turned, 0) << "of " << alternatives << " mirrored tilts, labelled otherwise than their pose";
}

}  // namespace
}  // namespace dualgraph
