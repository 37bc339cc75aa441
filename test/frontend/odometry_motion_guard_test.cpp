// SPDX-License-Identifier: MIT
// OdometryMotionGuard: a pose further than a drone flies from the newest accepted one is held; the motion going on
// drops it; three samples in a row continuing from it make it the VIO's new place; fast real flight, gaps, the first
// sample, samples not after the newest and limits 0 are not its business.
#include <gtest/gtest.h>

#include <cmath>

#include "dualgraph/frontend/pipeline/odometry_motion_guard.h"

namespace dualgraph {
namespace motion_guard_test {

Eigen::Isometry3d poseAt(double x, double yaw = 0.0) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, 2.0, 1.0);
  return pose;
}

// 200 Hz for 1 s at 10 m/s along x from t = 1.7e9 s (an epoch clock), each accepted; returns the last t.
double flySecond(OdometryMotionGuard& guard) {
  double t = 1.7e9;
  for (int k = 0; k <= 200; ++k) {
    t = 1.7e9 + 0.005 * k;
    EXPECT_EQ(guard.check(t, poseAt(0.05 * k)), MotionCheck::kOn) << k;
    guard.accepted(t, poseAt(0.05 * k));
  }
  return t;
}

TEST(OdometryMotionGuard, AGlitchedPoseIsHeldAndTheMotionGoesOn) {
  OdometryMotionGuard guard(50.0, 40.0);
  const double t = flySecond(guard);
  EXPECT_EQ(guard.check(t + 0.005, poseAt(1e6)), MotionCheck::kHeld);
  const Status held = guard.heldStatus();
  EXPECT_EQ(held.code(), StatusCode::kInvalidArgument);
  for (const char* part : {"pose jump", "frontend.max_odometry_speed_mps = 50", "999990 m and 0 rad", "(1 so far)"}) {
    EXPECT_NE(held.message().find(part), std::string::npos) << part << " in " << held.message();
  }
  EXPECT_EQ(guard.check(t + 0.010, poseAt(10.1)), MotionCheck::kOn);  // the flight goes on: the glitch is dropped
  guard.accepted(t + 0.010, poseAt(10.1));
  // Two glitches near each other, then the flight: still two short of a jump.
  EXPECT_EQ(guard.check(t + 0.015, poseAt(-500.0)), MotionCheck::kHeld);
  EXPECT_EQ(guard.check(t + 0.020, poseAt(-500.0)), MotionCheck::kHeld);
  EXPECT_EQ(guard.check(t + 0.025, poseAt(10.25)), MotionCheck::kOn);
  EXPECT_EQ(guard.held(), 3);
  EXPECT_EQ(guard.jumps(), 0);
}

TEST(OdometryMotionGuard, ATurnFasterThanADroneIsHeld) {
  OdometryMotionGuard guard(50.0, 40.0);
  const double t = flySecond(guard);
  EXPECT_EQ(guard.check(t + 0.005, poseAt(10.05, 1.0)), MotionCheck::kHeld);  // 1 rad in 5 ms: 200 rad/s
  EXPECT_NE(guard.heldStatus().message().find("frontend.max_odometry_turn_rate_radps = 40"), std::string::npos);
  EXPECT_EQ(guard.check(t + 0.010, poseAt(10.1)), MotionCheck::kOn);
}

TEST(OdometryMotionGuard, AVioThatReallyJumpsIsTakenAtTheThirdSample) {
  OdometryMotionGuard guard(50.0, 40.0);
  const double t = flySecond(guard);
  EXPECT_EQ(guard.check(t + 0.005, poseAt(13.05)), MotionCheck::kHeld);  // 3 m in one sample (a VIO reset)
  EXPECT_EQ(guard.check(t + 0.010, poseAt(13.10)), MotionCheck::kHeld);
  EXPECT_EQ(guard.check(t + 0.015, poseAt(13.15)), MotionCheck::kJump);
  guard.accepted(t + 0.015, poseAt(13.15));
  EXPECT_EQ(guard.check(t + 0.020, poseAt(13.20)), MotionCheck::kOn);  // the new place is the place now
  // Held samples must continue from each other: three glitches scattered are no jump.
  EXPECT_EQ(guard.check(t + 0.025, poseAt(100.0)), MotionCheck::kHeld);
  EXPECT_EQ(guard.check(t + 0.030, poseAt(-100.0)), MotionCheck::kHeld);
  EXPECT_EQ(guard.check(t + 0.035, poseAt(300.0)), MotionCheck::kHeld);
  EXPECT_EQ(guard.held(), 5);
  EXPECT_EQ(guard.jumps(), 1);
}

TEST(OdometryMotionGuard, FastFlightGapsAndWhatIsNotItsBusinessAreTaken) {
  OdometryMotionGuard guard(50.0, 40.0);
  EXPECT_EQ(guard.check(0.0, poseAt(1e6)), MotionCheck::kOn);  // the first sample: nothing to judge it by
  guard.accepted(0.0, poseAt(0.0));
  // 45 m/s and 35 rad/s, at 200 Hz and at 10 Hz.
  double t = 0.0, x = 0.0, yaw = 0.0;
  for (double dt : {0.005, 0.1}) {
    for (int k = 0; k < 20; ++k) {
      t += dt;
      x += 45.0 * dt;
      yaw = std::remainder(yaw + 35.0 * dt, 2.0 * M_PI);
      ASSERT_EQ(guard.check(t, poseAt(x, yaw)), MotionCheck::kOn) << t;
      guard.accepted(t, poseAt(x, yaw));
    }
  }
  EXPECT_EQ(guard.check(t + 2.0, poseAt(x + 90.0, yaw)), MotionCheck::kOn);  // 90 m after a 2 s gap
  EXPECT_EQ(guard.check(t, poseAt(x + 1e6)), MotionCheck::kOn);        // not after the newest: the order check's
  EXPECT_EQ(guard.check(NAN, poseAt(x + 1e6)), MotionCheck::kOn);      // not finite: the sample check's
  guard.reset();
  EXPECT_EQ(guard.check(t + 0.005, poseAt(x + 1e6)), MotionCheck::kOn);  // a new clock's first sample
  OdometryMotionGuard off(0.0, 0.0);
  off.accepted(0.0, poseAt(0.0));
  EXPECT_EQ(off.check(0.005, poseAt(1e6, 2.0)), MotionCheck::kOn);
  EXPECT_EQ(guard.held() + off.held(), 0);
}

}  // namespace motion_guard_test
}  // namespace dualgraph
