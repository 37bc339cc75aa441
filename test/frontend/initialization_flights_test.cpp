// SPDX-License-Identifier: MIT
// The automatic initialisation on simulated flights of every bundled track, realistic and harsh, seeds 1-3 (the
// VIO in its own frame at a random yaw and up to 10 m away; the first lock fitted again on its window's corners,
// against the search's own frame as the control): locked within 2 s of the first detection, on a
// the right frame: where the drone is at the lock within 1.5 m and 15 degrees of the truth, well inside the
// 2.6 m (the nearest gates' spacing) or half turn that a wrong hypothesis is off (measured 0.2-1.4 m and 0.1-10.4
// degrees: 4 px corners, an uncalibrated 1.5-2 degree mount; the main graph removes the rest). The bound was 10
// degrees over 0.3-7.4 measured until the searches' 0.2 s spacing stopped depending on the clock's rounding
// (core/stamp_tolerance.h): a search now runs at exactly 0.2 s, and the harsh lemniscate seed 3 locks on other
// detections, 10.4 degrees off. Before the pixel noise was learnt during the search (the prior
// 1 px refused most 4 px gates until 30 fits were seen by tracking) the harsh lemniscate took 2.4-4.0 s, and
// before the lock's yaw fused the inliers' positions and normals the realistic lemniscate seed 1 locked 10
// degrees off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dualgraph/frontend/replay/sequence_run.h"
#include "dualgraph/types/se3_math.h"
#include "test/frontend/simulated_flight.h"

namespace dualgraph {
namespace {

TEST(InitializationFlights, EveryTrackAndProfileLocksWithinTwoSecondsOnTheRightFrame) {
  double apart_sum = 0.0, apart_sum_unfitted = 0.0;
  int refined = 0;
  for (const char* profile : {"realistic", "harsh"}) {
    for (const char* track_name : {"ratm_ellipse.yaml", "ratm_lemniscate.yaml"}) {
      for (std::uint64_t seed : {1, 2, 3}) {
        SCOPED_TRACE(std::string(profile) + " " + track_name + " seed " + std::to_string(seed));
        const Sequence sequence = flighttest::simulatedFlight(track_name, profile, seed, 1);
        ASSERT_FALSE(sequence.corners.empty());
        auto run = runSequence(sequence, SequenceRunParams{});
        ASSERT_TRUE(run.ok()) << run.status().message();
        ASSERT_TRUE(run->initialization.has_value());
        ASSERT_TRUE(run->initialization->locked) << run->initialization->why_not;
        const double after_first = run->initialization->locked_at - sequence.corners.front().t;
        // The drone at the lock: odometry sample and ground truth at the first stamps at or after it.
        const auto [found, truth] = flighttest::droneAtTheLock(sequence, *run->initialization);
        const double apart = (found.translation() - truth.translation()).norm();
        const double turn = so3Log(found.linear().transpose() * truth.linear()).norm() * 180.0 / M_PI;
        std::printf("%s %s seed %d: locked %.2f s after the first detection, the drone %.3f m and %.2f deg from the "
                    "truth\n", profile, track_name, static_cast<int>(seed), after_first, apart, turn);
        EXPECT_LT(after_first, 2.0);
        EXPECT_LT(apart, 1.5);
        EXPECT_LT(turn, 15.0);
        // The control: the search's own frame (its PnP gate centres), not fitted again on the corners.
        SequenceRunParams unfitted;
        unfitted.initialization.refine_on_corners = false;
        auto control = runSequence(sequence, unfitted);
        ASSERT_TRUE(control.ok()) << control.status().message();
        ASSERT_TRUE(control->initialization && control->initialization->locked);
        EXPECT_FALSE(control->initialization->refined_on_corners);
        const auto [found_unfitted, truth_unfitted] = flighttest::droneAtTheLock(sequence, *control->initialization);
        apart_sum += apart;
        apart_sum_unfitted += (found_unfitted.translation() - truth_unfitted.translation()).norm();
        refined += run->initialization->refined_on_corners ? 1 : 0;
      }
    }
  }
  // Fitted on the corners, the drone at the lock is nearer the truth over the 12 flights (measured: 0.33 m against
  // 0.62 m on average; the lemniscate 0.19-0.91 m, its two far gates leave the yaw 1-7 degrees off).
  std::printf("the drone at the lock on average %.3f m from the truth, %.3f m unfitted; %d of 12 fitted\n",
              apart_sum / 12.0, apart_sum_unfitted / 12.0, refined);
  EXPECT_EQ(refined, 12);
  EXPECT_LT(apart_sum, 0.8 * apart_sum_unfitted);
}

// `initialization: given` with a frame the detections contradict (the VIO's frame is elsewhere, 30 m or the
// track's own offset away): lost within seconds, and as no gate ever confirmed the given frame the search goes
// over the whole map at once (here 1.4 s after the first detection; a search near the wrong estimate, widened only
// after relocalization_global_after_s, took 5.5 s, and in `dualgraph run` over the 12 laps of the realistic ellipse
// seed 1 locked onto neighbouring gates: 2.8 and 9.5 m ATE, exit 0), said in the counters; from the relocalisation on the drone is where it
// is. The poses before the loss stay as wrong as the frame given (the run cannot know better causally).
TEST(InitializationFlights, AGivenFrameTheDetectionsContradictIsSearchedForInTheWholeMap) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 1, 2);
  for (double offset : {0.0, 30.0}) {
    SCOPED_TRACE(::testing::Message() << "given frame at x = " << offset << " m");
    SequenceRunParams params;
    params.auto_initialize = false;
    params.localizer.initial_world_T_odom = Eigen::Isometry3d::Identity();
    params.localizer.initial_world_T_odom.translation().x() = offset;
    auto run = runSequence(sequence, params);
    ASSERT_TRUE(run.ok()) << run.status().message();
    EXPECT_EQ(run->pipeline_counters.unconfirmed_frame_searches, 1);
    EXPECT_EQ(run->localizer_counters.relocalizations, 1);
    ASSERT_FALSE(run->estimate.empty());
    double relocalised_at = -1.0;
    for (size_t k = 1; k < run->estimate.size() && relocalised_at < 0.0; ++k) {
      if (run->estimate[k - 1].state == TrackingState::kLost && run->estimate[k].state == TrackingState::kTracking) {
        relocalised_at = run->estimate[k].t;
      }
    }
    ASSERT_GT(relocalised_at, 0.0);
    EXPECT_LT(relocalised_at - sequence.corners.front().t, 4.0);
    double worst = 0.0;
    for (const CorrectedPose& pose : run->estimate) {
      if (pose.t < relocalised_at + 1.0) continue;
      const Eigen::Isometry3d truth = flighttest::poseAtOrAfter(sequence.ground_truth->samples, pose.t);
      worst = std::max(worst, (pose.world_T_body.translation() - truth.translation()).norm());
    }
    std::printf("given frame at x = %.0f m: relocalised %.2f s after the first detection, then at most %.3f m from "
                "the truth\n", offset, relocalised_at - sequence.corners.front().t, worst);
    EXPECT_LT(worst, 1.0);
  }
}

}  // namespace
}  // namespace dualgraph
