// SPDX-License-Identifier: MIT
// OdometryClockGuard: a stamp far ahead or behind is held; the accepted clock going on drops it; three samples in a
// row on a new clock make it the clock (ahead: the third taken, a jump; behind: once it ran 1 s, a restart); off,
// within the limit, or not finite: not its business.
#include <gtest/gtest.h>

#include <cmath>

#include "dualgraph/frontend/pipeline/odometry_clock_guard.h"

namespace dualgraph {
namespace clock_guard_test {

// Feeds start, start + 0.1, …, start + 1.0 s: each accepted.
void feedSecond(OdometryClockGuard& guard, double start = 0.0) {
  for (int k = 0; k <= 10; ++k) {
    const double t = start + 0.1 * k;
    ASSERT_EQ(guard.check(t), ClockCheck::kOn) << t;
    guard.accepted(t);
  }
}

TEST(OdometryClockGuard, AGlitchedStampIsHeldAndTheClockGoesOn) {
  OdometryClockGuard guard(10.0);
  feedSecond(guard);
  EXPECT_EQ(guard.check(1e9), ClockCheck::kHeld);
  const Status held = guard.heldStatus();
  EXPECT_EQ(held.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(held.message().find("after the newest"), std::string::npos) << held.message();
  EXPECT_NE(held.message().find("frontend.max_odometry_jump_s = 10"), std::string::npos) << held.message();
  EXPECT_NE(held.message().find("(1 so far)"), std::string::npos) << held.message();
  EXPECT_EQ(guard.check(1.1), ClockCheck::kOn);  // the accepted clock goes on: what was held is dropped
  guard.accepted(1.1);
  EXPECT_EQ(guard.check(1e9 + 0.1), ClockCheck::kHeld);  // a new candidate, counted from 1 again
  EXPECT_EQ(guard.check(1e9 + 0.2), ClockCheck::kHeld);
  EXPECT_EQ(guard.check(1.2), ClockCheck::kOn);
  EXPECT_EQ(guard.held(), 3);
  EXPECT_EQ(guard.jumps() + guard.restarts(), 0);
}

TEST(OdometryClockGuard, ThreeSamplesInARowMakeANewClock) {
  OdometryClockGuard guard(10.0);
  feedSecond(guard);
  EXPECT_EQ(guard.check(1000.0), ClockCheck::kHeld);
  EXPECT_EQ(guard.check(1000.1), ClockCheck::kHeld);
  EXPECT_EQ(guard.check(1000.2), ClockCheck::kJump);
  guard.accepted(1000.2);
  EXPECT_EQ(guard.held(), 2);
  EXPECT_EQ(guard.jumps(), 1);
  EXPECT_EQ(guard.check(1000.3), ClockCheck::kOn);  // the new clock is the clock now
  // Samples on the held clock must follow each other within the limit: a second jump starts again.
  guard.accepted(1000.3);
  EXPECT_EQ(guard.check(5000.0), ClockCheck::kHeld);
  EXPECT_EQ(guard.check(9000.0), ClockCheck::kHeld);
  EXPECT_EQ(guard.check(9000.1), ClockCheck::kHeld);
  EXPECT_EQ(guard.check(9000.2), ClockCheck::kJump);
  EXPECT_EQ(guard.held(), 5);
  EXPECT_EQ(guard.jumps(), 2);
  EXPECT_EQ(guard.restarts(), 0);
}

// A looped bag: the clock goes back 100 s and stays there. A single stamp far behind is a glitch and is dropped; so is
// a burst of stale samples spanning less than kRestartSpanS; the clock behind restarts once it ran that long.
TEST(OdometryClockGuard, AClockThatGoesBackAndStaysIsARestart) {
  OdometryClockGuard guard(10.0);
  feedSecond(guard, 100.0);
  EXPECT_EQ(guard.check(3.0), ClockCheck::kHeld);  // one stamp far behind, then the clock goes on: a glitch
  EXPECT_NE(guard.heldStatus().message().find("before the newest"), std::string::npos) << guard.heldStatus().message();
  EXPECT_NE(guard.heldStatus().message().find("clock restart"), std::string::npos) << guard.heldStatus().message();
  EXPECT_NE(guard.heldStatus().message().find("over 1 s"), std::string::npos) << guard.heldStatus().message();
  EXPECT_EQ(guard.check(101.1), ClockCheck::kOn);
  guard.accepted(101.1);
  EXPECT_EQ(guard.check(95.0), ClockCheck::kOn);  // behind by less than the limit: the order check's business
  for (int k = 0; k < 50; ++k) EXPECT_EQ(guard.check(20.0 + 0.01 * k), ClockCheck::kHeld) << k;  // 0.49 s stale
  EXPECT_EQ(guard.check(101.2), ClockCheck::kOn);  // the clock goes on: the burst is dropped
  guard.accepted(101.2);
  EXPECT_EQ(guard.restarts(), 0);
  EXPECT_EQ(guard.check(0.0), ClockCheck::kHeld);
  EXPECT_EQ(guard.check(0.0), ClockCheck::kHeld);  // not after the one before: a new candidate
  for (int k = 1; k < 100; ++k) EXPECT_EQ(guard.check(0.01 * k), ClockCheck::kHeld) << k;
  EXPECT_EQ(guard.check(1.0), ClockCheck::kRestart);  // 1 s of the clock behind
  guard.accepted(1.0);
  EXPECT_EQ(guard.check(1.01), ClockCheck::kOn);
  EXPECT_EQ(guard.held(), 1 + 50 + 2 + 99);
  EXPECT_EQ(guard.restarts(), 1);
  EXPECT_EQ(guard.jumps(), 0);
}

// The very first sample glitched far ahead of the real clock: the real clock behind it restarts after 1 s of it.
TEST(OdometryClockGuard, AGlitchedFirstSampleIsLeftBehind) {
  OdometryClockGuard guard(10.0);
  ASSERT_EQ(guard.check(4e9), ClockCheck::kOn);  // nothing to compare it with: taken
  guard.accepted(4e9);
  for (int k = 0; k < 200; ++k) EXPECT_EQ(guard.check(1.7e9 + 0.005 * k), ClockCheck::kHeld) << k;
  EXPECT_EQ(guard.check(1.7e9 + 1.0), ClockCheck::kRestart);
}

TEST(OdometryClockGuard, WithinTheLimitOffOrNotFiniteIsNotItsBusiness) {
  OdometryClockGuard guard(10.0);
  EXPECT_EQ(guard.check(1.7e9), ClockCheck::kOn);  // the first sample: nothing to jump from
  guard.accepted(1.7e9);
  EXPECT_EQ(guard.check(1.7e9 + 10.0), ClockCheck::kOn);  // exactly the limit on an epoch clock: not beyond it
  EXPECT_EQ(guard.check(1.7e9 - 10.0), ClockCheck::kOn);  // likewise behind (the order check refuses it)
  EXPECT_EQ(guard.check(NAN), ClockCheck::kOn);           // the sample check refuses it as not finite
  EXPECT_EQ(guard.check(1.7e9 - 1.0), ClockCheck::kOn);   // backwards within the limit: the order check's
  OdometryClockGuard off(0.0);
  feedSecond(off, 100.0);
  EXPECT_EQ(off.check(1e9), ClockCheck::kOn);
  EXPECT_EQ(off.check(0.0), ClockCheck::kOn);
  EXPECT_EQ(guard.held() + off.held(), 0);
  EXPECT_TRUE(guard.heldStatus().ok());  // nothing held
}

}  // namespace clock_guard_test
}  // namespace dualgraph
