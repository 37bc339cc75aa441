// SPDX-License-Identifier: MIT
// A drone that waits on the ground (or hovers) before take-off moves less than d_main for seconds: with
// keyframe_max_interval_s its detections still close keyframes and correct a wrong start frame; without, nothing
// corrects it until it flies; a requested keyframe (after a frame search) corrects it at the next sample.
#include <gtest/gtest.h>

#include "test/dual_graph/localizer_fixtures.h"

namespace dualgraph {
namespace {

struct Hover {
  Eigen::Isometry3d last_corrected = Eigen::Isometry3d::Identity();
  size_t keyframes = 0;
};

// 5 s still at the origin of a VIO that is exact, a gate 6 m ahead seen at 30 Hz (exact pose, 5 cm / 1 deg
// covariance); the start frame is guessed 0.5 m off.
Hover hover(double keyframe_max_interval_s) {
  GateMap map;
  Eigen::Isometry3d world_T_gate = Eigen::Isometry3d::Identity();
  world_T_gate.translation() << 6.0, 0.0, 1.5;
  map.world_T_gate[0] = world_T_gate;
  LocalizerParams params;
  params.keyframe_max_interval_s = keyframe_max_interval_s;
  // Exact detections of one gate 6 m away: no systematic error for a floor to stand for, so the correction is
  // the keyframes' alone.
  params.distilled_floor_range = params.distilled_floor_lateral = params.distilled_floor_rotation = 0.0;
  params.initial_world_T_odom.translation() << 0.3, -0.4, 0.0;
  std::unique_ptr<Localizer> localizer = testing::makeLocalizer(params, map);
  Hover out;
  if (!localizer) return out;
  Matrix6d covariance = Matrix6d::Zero();
  covariance.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 3e-4, 3e-4, 3e-4;
  for (int k = 0; k <= 500; ++k) {
    const double t = k / 100.0;
    if (k % 3 == 0 && k > 0) {
      EXPECT_TRUE(localizer->addObservation(GateObservation::pose(t, 0, world_T_gate, covariance)).ok());
    }
    OdometrySample sample;
    sample.t = t;
    Result<CorrectedPose> pose = localizer->addOdometry(sample);
    EXPECT_TRUE(pose.ok()) << pose.status().message();
    if (pose.ok()) out.last_corrected = pose->world_T_body;
  }
  out.keyframes = localizer->keyframeTrajectory().size();
  return out;
}

TEST(HoverKeyframes, DetectionsWhileStillCorrectTheFrameEverySecond) {
  const Hover corrected = hover(1.0);
  EXPECT_GE(corrected.keyframes, 5u);
  EXPECT_LT(corrected.last_corrected.translation().norm(), 0.05);  // the truth is the origin

  const Hover uncorrected = hover(0.0);
  EXPECT_EQ(uncorrected.keyframes, 1u);
  EXPECT_NEAR(uncorrected.last_corrected.translation().norm(), 0.5, 1e-9);
}

// requestKeyframe: the first sample covering the observations given so far closes a keyframe at once, whatever the
// VIO moved and whatever keyframe_max_interval_s says; the start frame is corrected then, not when the drone flies.
TEST(HoverKeyframes, ARequestedKeyframeClosesAtTheNextSampleThatCoversTheObservations) {
  GateMap map;
  Eigen::Isometry3d world_T_gate = Eigen::Isometry3d::Identity();
  world_T_gate.translation() << 6.0, 0.0, 1.5;
  map.world_T_gate[0] = world_T_gate;
  LocalizerParams params;
  params.keyframe_max_interval_s = 0.0;  // no keyframe from waiting: only the request makes one
  params.detection_latency = 0.0;        // closed at the sample that covers it, not 0.1 s later
  params.distilled_floor_range = params.distilled_floor_lateral = params.distilled_floor_rotation = 0.0;
  params.initial_world_T_odom.translation() << 0.3, -0.4, 0.0;
  std::unique_ptr<Localizer> localizer = testing::makeLocalizer(params, map);
  ASSERT_TRUE(localizer);
  Matrix6d covariance = Matrix6d::Zero();
  covariance.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 3e-4, 3e-4, 3e-4;
  OdometrySample sample;
  auto step = [&](double t) {
    sample.t = t;
    Result<CorrectedPose> pose = localizer->addOdometry(sample);
    EXPECT_TRUE(pose.ok()) << pose.status().message();
    return pose.ok() ? pose->world_T_body.translation().norm() : -1.0;
  };
  step(0.0);
  for (int k = 1; k <= 10; ++k) {
    ASSERT_TRUE(localizer->addObservation(GateObservation::pose(k * 0.03, 0, world_T_gate, covariance)).ok());
    step(k * 0.03);
  }
  EXPECT_EQ(localizer->keyframeTrajectory().size(), 1u);
  // An observation newer than the newest sample, then the request: the sample before it closes nothing yet.
  ASSERT_TRUE(localizer->addObservation(GateObservation::pose(0.335, 0, world_T_gate, covariance)).ok());
  localizer->requestKeyframe();
  EXPECT_NEAR(step(0.33), 0.5, 1e-9);
  EXPECT_EQ(localizer->keyframeTrajectory().size(), 1u);
  EXPECT_LT(step(0.34), 0.05);  // covers it: the keyframe closes, the 0.5 m start error is corrected
  EXPECT_EQ(localizer->keyframeTrajectory().size(), 2u);
  step(0.37);
  EXPECT_EQ(localizer->keyframeTrajectory().size(), 2u);  // one request, one keyframe
}

TEST(HoverKeyframes, ARequestWhileInitialisingIsIgnored) {
  GateMap map;
  map.world_T_gate[0] = Eigen::Isometry3d::Identity();
  Result<std::unique_ptr<Localizer>> localizer = Localizer::create(LocalizerParams{}, map, TrackingState::kInitialising);
  ASSERT_TRUE(localizer.ok());
  OdometrySample sample;
  ASSERT_TRUE((*localizer)->addOdometry(sample).ok());
  (*localizer)->requestKeyframe();
  sample.t = 0.1;
  ASSERT_TRUE((*localizer)->addOdometry(sample).ok());
  EXPECT_TRUE((*localizer)->keyframeTrajectory().empty());
  EXPECT_TRUE((*localizer)->keyframeStats().empty());
}

}  // namespace
}  // namespace dualgraph
