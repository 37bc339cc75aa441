// SPDX-License-Identifier: MIT
// A drone that waits on the ground (or hovers) before take-off moves less than d_main for seconds: with
// keyframe_max_interval_s its detections still close keyframes and correct a wrong start frame; without, nothing
// corrects it until it flies.
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

}  // namespace
}  // namespace dualgraph
