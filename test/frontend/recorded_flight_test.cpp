// SPDX-License-Identifier: MIT
// Recorded-flight mode (frontend/simulation/recorded_flight.h, body_trajectory.h): a sampled trajectory
// interpolates as a pose should, gates go where the path says, and the detector looking from a recorded copy of a
// flight sees what it sees from the flight itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dualgraph/frontend/simulation/recorded_flight.h"
#include "dualgraph/types/se3_math.h"
#include "test/frontend/simulator_fixtures.h"

namespace dualgraph {
namespace {

using Samples = std::vector<std::pair<double, Eigen::Isometry3d>>;

Eigen::Isometry3d pose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  out.translation() << x, y, z;
  return out;
}

// Flying along +x at `speed` m/s for `seconds`, 100 Hz, then (when `back`) the same way back 0.5 m to the side.
Samples straightLine(double speed, double seconds, bool back = false) {
  Samples samples;
  for (int k = 0; k <= static_cast<int>(seconds * 100); ++k) samples.emplace_back(k / 100.0, pose(speed * k / 100.0, 0, 1.5, 0));
  if (back) {
    const double end = speed * seconds;
    for (int k = 1; k <= static_cast<int>(seconds * 100); ++k) {
      samples.emplace_back(seconds + k / 100.0, pose(end - speed * k / 100.0, 0.5, 1.5, M_PI));
    }
  }
  return samples;
}

TEST(SampledTrajectory, InterpolatesPositionLinearlyAndAttitudeBySlerpAndClampsOutside) {
  auto trajectory = SampledTrajectory::create({{10.0, pose(0, 0, 0, 0)}, {12.0, pose(2, 4, 0, 1.0)}});
  ASSERT_TRUE(trajectory.ok()) << trajectory.status().message();
  const Eigen::Isometry3d mid = trajectory->worldTBody(11.5);
  EXPECT_TRUE(mid.translation().isApprox(Eigen::Vector3d(1.5, 3.0, 0.0), 1e-12));
  EXPECT_NEAR(so3Log(mid.linear()).z(), 0.75, 1e-12);
  EXPECT_TRUE(trajectory->worldTBody(5.0).isApprox(pose(0, 0, 0, 0)));
  EXPECT_TRUE(trajectory->worldTBody(99.0).isApprox(pose(2, 4, 0, 1.0)));
  EXPECT_NEAR(bodyAngularRate(*trajectory, 11.0), 0.5, 1e-9);
}

TEST(SampledTrajectory, RefusesTooFewNonIncreasingOrNonFiniteSamples) {
  EXPECT_EQ(SampledTrajectory::create({{0.0, pose(0, 0, 0, 0)}}).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(SampledTrajectory::create({{1.0, pose(0, 0, 0, 0)}, {1.0, pose(1, 0, 0, 0)}}).status().code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(SampledTrajectory::create({{0.0, pose(0, 0, 0, 0)}, {1.0, pose(NAN, 0, 0, 0)}}).status().code(),
            StatusCode::kInvalidArgument);
}

TEST(GatePlacement, OneGateEverySpacingAlongTheDirectionOfTravel) {
  auto trajectory = SampledTrajectory::create(straightLine(1.0, 20.0));
  ASSERT_TRUE(trajectory.ok());
  auto track = placeGatesOnPath(*trajectory, GatePlacementParams{});  // every 4 m, the first after 2 m
  ASSERT_TRUE(track.ok()) << track.status().message();
  ASSERT_EQ(track->gates.size(), 5u);
  for (size_t i = 0; i < track->gates.size(); ++i) {
    EXPECT_EQ(track->gates[i].id, static_cast<int>(i));
    EXPECT_NEAR(track->gates[i].position.x(), 2.0 + 4.0 * static_cast<double>(i), 0.011);
    EXPECT_NEAR(track->gates[i].yaw, 0.0, 1e-9);
  }
}

// The way back runs 0.5 m beside the way out: no two gates closer than min_separation (the way back's go between
// the way out's where there is room), and with a separation below 0.5 m every 4 m of both ways has one.
TEST(GatePlacement, NoTwoGatesCloserThanTheSeparation) {
  auto trajectory = SampledTrajectory::create(straightLine(1.0, 20.0, true));
  ASSERT_TRUE(trajectory.ok());
  GatePlacementParams params;
  for (double separation : {2.0, 3.0, 5.0}) {
    params.min_separation = separation;
    auto track = placeGatesOnPath(*trajectory, params);
    ASSERT_TRUE(track.ok());
    // The way out alone: one every max(spacing, separation) metres of its 20 m, the first after 2 m.
    EXPECT_GE(track->gates.size(), static_cast<size_t>(18.0 / std::max(4.0, separation)) + 1) << separation;
    EXPECT_LT(track->gates.size(), 10u);
    for (size_t i = 0; i < track->gates.size(); ++i) {
      for (size_t j = 0; j < i; ++j) {
        EXPECT_GE((track->gates[i].position - track->gates[j].position).norm(), separation) << i << " " << j;
      }
    }
  }
  params.min_separation = 0.4;
  auto track = placeGatesOnPath(*trajectory, params);
  ASSERT_TRUE(track.ok());
  ASSERT_EQ(track->gates.size(), 10u);
  EXPECT_NEAR(std::abs(track->gates.back().yaw), M_PI, 1e-9);  // flown through the other way
}

TEST(GatePlacement, AHoveringPathAllowsNoGate) {
  Samples hover;
  for (int k = 0; k < 1000; ++k) hover.emplace_back(k / 100.0, pose(0.001 * std::sin(k), 0, 1, 0));
  auto trajectory = SampledTrajectory::create(hover);
  ASSERT_TRUE(trajectory.ok());
  const Result<Track> track = placeGatesOnPath(*trajectory, GatePlacementParams{});
  EXPECT_EQ(track.status().code(), StatusCode::kInvalidArgument);
  GatePlacementParams bad;
  bad.spacing = 0.0;
  EXPECT_EQ(placeGatesOnPath(*trajectory, bad).status().code(), StatusCode::kInvalidArgument);
}

// The ground truth of a simulated flight, recorded at 200 Hz, seen through SampledTrajectory: the same gates in
// the same images, corners within a fraction of a pixel of the flight's own (interpolation between samples).
TEST(RecordedFlight, TheDetectorSeesARecordedCopyOfAFlightAsTheFlightItself) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  const Flight flight = simtest::ratmFlight("ratm_ellipse.yaml", 1);
  OdometryLog truth, vio;
  for (long k = 0; k / 200.0 <= flight.duration(); ++k) {
    OdometrySample sample;
    sample.t = k / 200.0;
    sample.odom_T_body = flight.at(sample.t).world_T_body;
    truth.samples.push_back(sample);
    if (k % 2 == 0) vio.samples.push_back(sample);
  }
  DetectionSimParams noise_free;
  noise_free.pixel_sigma = 0.0;
  noise_free.miss_probability = noise_free.displaced_corner_probability = 0.0;
  noise_free.wrong_id_probability = noise_free.false_gate_probability = 0.0;
  auto direct = simulateDetections(flight, track, simtest::ratmCamera(), noise_free, 1);
  ASSERT_TRUE(direct.ok());
  RecordedFlightParams params;
  params.detection = noise_free;
  auto recorded = simulateRecordedFlight(truth, vio, &track, simtest::ratmCamera(), params);
  ASSERT_TRUE(recorded.ok()) << recorded.status().message();
  EXPECT_FALSE(recorded->gates_placed);
  ASSERT_EQ(recorded->detections.size(), direct->size());
  double worst = 0.0;
  for (size_t i = 0; i < direct->size(); ++i) {
    EXPECT_EQ(recorded->detections[i].true_gate_id, (*direct)[i].true_gate_id);
    EXPECT_DOUBLE_EQ(recorded->detections[i].corners.t, (*direct)[i].corners.t);
    worst = std::max(worst, ((*direct)[i].true_pixels - recorded->detections[i].true_pixels).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 0.5);  // [px]
  EXPECT_EQ(recorded->sequence.corners.size(), direct->size());
  EXPECT_EQ(recorded->sequence.odometry.samples.size(), vio.samples.size());
}

TEST(RecordedFlight, RefusesAVioFrameErrorAndTrajectoriesThatDoNotOverlap) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  OdometryLog truth, vio;
  for (int k = 0; k < 500; ++k) {
    OdometrySample sample;
    sample.t = k / 100.0;
    sample.odom_T_body = pose(k / 100.0, 0, 1, 0);
    truth.samples.push_back(sample);
    sample.t += 100.0;
    vio.samples.push_back(sample);
  }
  const Result<RecordedFlight> apart = simulateRecordedFlight(truth, vio, &track, simtest::ratmCamera(), {});
  ASSERT_EQ(apart.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(apart.status().message().find("overlap"), std::string::npos) << apart.status().message();
  RecordedFlightParams params;
  params.field.vio_frame_yaw = 0.1;
  EXPECT_EQ(simulateRecordedFlight(truth, truth, &track, simtest::ratmCamera(), params).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace dualgraph
