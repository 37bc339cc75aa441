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

// Flying along +x at `speed` m/s for `seconds`, 100 Hz.
Samples straightLine(double speed, double seconds) {
  Samples samples;
  for (int k = 0; k <= static_cast<int>(seconds * 100); ++k) samples.emplace_back(k / 100.0, pose(speed * k / 100.0, 0, 1.5, 0));
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

// A forward-looking pinhole camera (90° wide, 60° high) on a body whose x axis is the direction it faces.
CameraModel forwardCamera() {
  CameraModel camera = CameraModel::pinhole(320, 320, 320, 240, 640, 480);
  Eigen::Matrix3d body_R_camera;
  body_R_camera << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // camera z (optical axis) = body x, camera x = −body y
  camera.body_T_camera.linear() = body_R_camera;
  return camera;
}

// Around a circle of radius r at `speed` m/s, facing `facing` rad from the direction of travel, 100 Hz.
Samples circle(double r, double speed, double seconds, double facing = 0.0) {
  Samples samples;
  for (int k = 0; k <= static_cast<int>(seconds * 100); ++k) {
    const double a = speed * (k / 100.0) / r;
    samples.emplace_back(k / 100.0, pose(r * std::cos(a), r * std::sin(a), 1.5, a + M_PI / 2 + facing));
  }
  return samples;
}

// The body's offset from a gate's centre when it crosses the gate's plane, in the gate's plane (across, up) [m];
// NaN when the path does not cross it within ±1 s of `t`.
Eigen::Vector2d crossingOffset(const SampledTrajectory& truth, const TrackGate& gate, double t) {
  const Eigen::Isometry3d world_T_gate = gate.worldTGate();
  double before = NAN;
  for (double s = t - 1.0; s <= t + 1.0; s += 0.005) {
    const Eigen::Vector3d p = world_T_gate.inverse() * truth.worldTBody(s).translation();
    if (!std::isnan(before) && (before < 0) != (p.x() < 0)) return p.tail<2>();
    before = p.x();
  }
  return Eigen::Vector2d(NAN, NAN);
}

TEST(GatePlacement, GatesWhereTheDroneFliesThroughAndItsCameraSeesThemOnTheApproach) {
  auto trajectory = SampledTrajectory::create(circle(8.0, 2.0, 30.0));
  ASSERT_TRUE(trajectory.ok());
  const CameraModel camera = forwardCamera();
  const DetectionSimParams detector;
  const GatePlacementParams params;
  std::vector<PlacedGateApproach> approaches;
  auto track = placeGatesOnPath(*trajectory, camera, detector, params, &approaches);
  ASSERT_TRUE(track.ok()) << track.status().message();
  ASSERT_GE(track->gates.size(), 3u);
  ASSERT_EQ(approaches.size(), track->gates.size());
  for (size_t i = 0; i < track->gates.size(); ++i) {
    const TrackGate& gate = track->gates[i];
    EXPECT_EQ(gate.id, static_cast<int>(i));
    EXPECT_EQ(approaches[i].gate_id, gate.id);
    EXPECT_GE(approaches[i].view_s, params.min_approach_view);
    const Eigen::Vector2d offset = crossingOffset(*trajectory, gate, approaches[i].crossing_time);
    ASSERT_TRUE(offset.allFinite()) << "gate " << i << " is not flown through";
    EXPECT_LE(offset.cwiseAbs().maxCoeff(), params.max_passage_offset + 1e-3) << i;  // crossing sampled every 5 ms
    for (size_t j = 0; j < i; ++j) {
      EXPECT_GE((gate.position - track->gates[j].position).norm(), params.min_separation) << i << " " << j;
    }
  }
  // The approach as the detector sees it: noise-free detections of each gate in the second before its crossing.
  DetectionSimParams noise_free = detector;
  noise_free.miss_probability = noise_free.false_gate_probability = 0.0;
  auto detections = simulateDetections(*trajectory, *track, camera, noise_free, 1);
  ASSERT_TRUE(detections.ok());
  for (const PlacedGateApproach& approach : approaches) {
    const auto seen = std::count_if(detections->begin(), detections->end(), [&](const SimulatedDetection& d) {
      return d.true_gate_id == approach.gate_id && d.corners.t < approach.crossing_time &&
             d.corners.t > approach.crossing_time - params.approach_window;
    });
    EXPECT_GE(seen, static_cast<long>(params.min_approach_view * 30.0) - 1) << approach.gate_id;
  }
}

// The same circle flown facing outwards (the camera never looks where the drone goes): no place for a gate, and the
// error says how many there are and how many a lock needs instead of writing a flight that can never lock.
TEST(GatePlacement, AFlightWhoseCameraNeverSeesItsWayAheadGetsNoGatesAndSaysSo) {
  auto trajectory = SampledTrajectory::create(circle(8.0, 2.0, 30.0, -M_PI / 2));
  ASSERT_TRUE(trajectory.ok());
  const Result<Track> track = placeGatesOnPath(*trajectory, forwardCamera(), DetectionSimParams{}, GatePlacementParams{});
  ASSERT_EQ(track.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(track.status().message().find("only 0 place(s)"), std::string::npos) << track.status().message();
  EXPECT_NE(track.status().message().find("3 needed"), std::string::npos) << track.status().message();
}

// A straight line allows gates, but all on one line: the VIO's frame could not be told from them (a turn about the
// line leaves every gate where it was), so it is refused.
TEST(GatePlacement, GatesAllOnOneLineAreRefused) {
  auto trajectory = SampledTrajectory::create(straightLine(2.0, 20.0));
  ASSERT_TRUE(trajectory.ok());
  const Result<Track> track = placeGatesOnPath(*trajectory, forwardCamera(), DetectionSimParams{}, GatePlacementParams{});
  ASSERT_EQ(track.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(track.status().message().find("one line"), std::string::npos) << track.status().message();
}

TEST(GatePlacement, AtMostOneGatePerSpacingOfPathAndNoneWhileHovering) {
  auto trajectory = SampledTrajectory::create(circle(8.0, 2.0, 30.0));
  ASSERT_TRUE(trajectory.ok());
  GatePlacementParams params;
  params.spacing = 12.0;
  std::vector<PlacedGateApproach> approaches;
  auto track = placeGatesOnPath(*trajectory, forwardCamera(), DetectionSimParams{}, params, &approaches);
  ASSERT_TRUE(track.ok()) << track.status().message();
  EXPECT_LE(track->gates.size(), 5u);  // 60 m of path
  for (size_t i = 1; i < approaches.size(); ++i) {
    EXPECT_GE((approaches[i].crossing_time - approaches[i - 1].crossing_time) * 2.0, params.spacing - 0.2);
  }
  Samples hover;
  for (int k = 0; k < 1000; ++k) hover.emplace_back(k / 100.0, pose(0.001 * std::sin(k), 0, 1, 0));
  auto hovering = SampledTrajectory::create(hover);
  ASSERT_TRUE(hovering.ok());
  EXPECT_EQ(placeGatesOnPath(*hovering, forwardCamera(), DetectionSimParams{}, GatePlacementParams{}).status().code(),
            StatusCode::kInvalidArgument);
  GatePlacementParams bad;
  bad.spacing = 0.0;
  EXPECT_EQ(placeGatesOnPath(*trajectory, forwardCamera(), DetectionSimParams{}, bad).status().code(), StatusCode::kInvalidArgument);
  bad = GatePlacementParams{};
  bad.max_passage_offset = bad.size;
  EXPECT_EQ(placeGatesOnPath(*trajectory, forwardCamera(), DetectionSimParams{}, bad).status().code(), StatusCode::kInvalidArgument);
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
