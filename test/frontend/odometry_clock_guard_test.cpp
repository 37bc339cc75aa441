// SPDX-License-Identifier: MIT
// OdometryClockGuard: a stamp far ahead is held; the accepted clock going on drops it; three samples in a row on a
// new clock make it the clock (the third taken); off, or within the limit, or not finite: not its business.
#include <gtest/gtest.h>

#include <cmath>

#include "dualgraph/frontend/pipeline/odometry_clock_guard.h"

namespace dualgraph {
namespace clock_guard_test {

// Feeds 0, 0.1, …, 1.0 s: each accepted.
void feedSecond(OdometryClockGuard& guard, double start = 0.0) {
  for (int k = 0; k <= 10; ++k) {
    const double t = start + 0.1 * k;
    ASSERT_TRUE(guard.check(t).ok()) << t;
    guard.accepted(t);
  }
}

TEST(OdometryClockGuard, AGlitchedStampIsHeldAndTheClockGoesOn) {
  OdometryClockGuard guard(10.0);
  feedSecond(guard);
  const Status held = guard.check(1e9);
  EXPECT_EQ(held.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(held.message().find("frontend.max_odometry_jump_s = 10"), std::string::npos) << held.message();
  EXPECT_NE(held.message().find("(1 so far)"), std::string::npos) << held.message();
  EXPECT_TRUE(guard.check(1.1).ok());  // the accepted clock goes on: what was held is dropped
  guard.accepted(1.1);
  EXPECT_FALSE(guard.check(1e9 + 0.1).ok());  // a new candidate, counted from 1 again
  EXPECT_FALSE(guard.check(1e9 + 0.2).ok());
  EXPECT_TRUE(guard.check(1.2).ok());
  EXPECT_EQ(guard.held(), 3);
  EXPECT_EQ(guard.jumps(), 0);
}

TEST(OdometryClockGuard, ThreeSamplesInARowMakeANewClock) {
  OdometryClockGuard guard(10.0);
  feedSecond(guard);
  EXPECT_FALSE(guard.check(1000.0).ok());
  EXPECT_FALSE(guard.check(1000.1).ok());
  EXPECT_TRUE(guard.check(1000.2).ok());
  guard.accepted(1000.2);
  EXPECT_EQ(guard.held(), 2);
  EXPECT_EQ(guard.jumps(), 1);
  EXPECT_TRUE(guard.check(1000.3).ok());  // the new clock is the clock now
  // Samples on the held clock must follow each other within the limit: a second jump starts again.
  guard.accepted(1000.3);
  EXPECT_FALSE(guard.check(5000.0).ok());
  EXPECT_FALSE(guard.check(9000.0).ok());
  EXPECT_FALSE(guard.check(9000.1).ok());
  EXPECT_TRUE(guard.check(9000.2).ok());
  EXPECT_EQ(guard.held(), 5);
  EXPECT_EQ(guard.jumps(), 2);
}

TEST(OdometryClockGuard, WithinTheLimitOffOrNotFiniteIsNotItsBusiness) {
  OdometryClockGuard guard(10.0);
  EXPECT_TRUE(guard.check(1.7e9).ok());  // the first sample: nothing to jump from
  guard.accepted(1.7e9);
  EXPECT_TRUE(guard.check(1.7e9 + 10.0).ok());  // exactly the limit on an epoch clock: not beyond it
  EXPECT_TRUE(guard.check(NAN).ok());            // the sample check refuses it as not finite
  EXPECT_TRUE(guard.check(1.0).ok());            // backwards: the order check refuses it
  OdometryClockGuard off(0.0);
  feedSecond(off);
  EXPECT_TRUE(off.check(1e9).ok());
  EXPECT_EQ(guard.held() + off.held(), 0);
}

}  // namespace clock_guard_test
}  // namespace dualgraph
