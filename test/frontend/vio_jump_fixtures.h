// SPDX-License-Identifier: MIT
// A simulated flight whose VIO jumps mid-flight (a VIO reset or a bad feature track), run as `dualgraph run` runs
// it, and what the run made of the jump: when it was a map pose again, how long it tracked while wrong.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "dualgraph/frontend/replay/self_calibration.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "test/frontend/simulated_flight.h"
#include "test/testing/shared_data.h"

namespace dualgraph::jumptest {

/// What a run made of a jump of the VIO at t_jump (times relative to it) [s, m].
struct JumpOutcome {
  /// The last tracking pose after the jump that was more than 1 m from the truth, relative to the jump: the
  /// time the run claimed `tracking` while wrong (−1: never). Poses lost or initialising are not claims.
  double wrong_tracking_until = -1.0;
  int losses = 0;           ///< counted by the Localizer (a frame replaced by a check counts as one)
  int relocalizations = 0;
  TrackingState final_state = TrackingState::kInitialising;
  double last_quarter_mean_m = 0.0;  ///< mean distance from the truth over the flight's last quarter
  double ate_m = 0.0;
  double vio_ate_m = 0.0;
  /// The graph size reported at the end counts the keyframes of the graphs given up at a relocalisation too.
  bool size_counts_every_keyframe = false;
  /// The jump as the pose guard saw it: confirmed once, its first two samples held (OdometryMotionGuard).
  int pose_jumps = 0;
  int held_at_pose_jump = 0;
  bool self_calibrated_before_jump = false;  ///< the configuration's self-calibration (first 15 s) came first
};

/// `laps` laps of `track_name` on `profile` with `seed`; the VIO (not its covariance: a VIO that jumps does not
/// know it did) jumps by `jump` [m, odometry frame] halfway through; run with the bundled configuration.
inline JumpOutcome runWithVioJump(const std::string& track_name, const std::string& profile, std::uint64_t seed,
                                  const Eigen::Vector3d& jump, int laps = 4) {
  JumpOutcome outcome;
  auto config = loadRunConfig(testing::sourcePath("data/config/default.yaml"));
  EXPECT_TRUE(config.ok());
  if (!config.ok()) return outcome;
  Sequence sequence = flighttest::simulatedFlight(track_name, profile, seed, laps);
  if (sequence.odometry.samples.empty()) return outcome;
  std::vector<OdometrySample>& samples = sequence.odometry.samples;
  const double t_jump = samples.front().t + 0.5 * (samples.back().t - samples.front().t);
  const Eigen::Isometry3d jumped(Eigen::Translation3d{jump});
  for (OdometrySample& sample : samples) {
    if (sample.t >= t_jump) sample.odom_T_body = jumped * sample.odom_T_body;
  }
  SelfCalibrationReport self_calibration;
  auto run = runSequenceSelfCalibrating(sequence, *config, {}, &self_calibration);
  EXPECT_TRUE(run.ok()) << run.status().message();
  if (!run.ok()) return outcome;
  outcome.self_calibrated_before_jump = self_calibration.applied && self_calibration.at_s < t_jump;
  const StampedPoses truth = stampedPosesFromSamples(sequence.ground_truth->samples);
  auto errorOf = [&truth](const CorrectedPose& pose) {
    const auto at = std::lower_bound(truth.begin(), truth.end(), pose.t,
                                     [](const auto& stamped, double t) { return stamped.first < t; });
    return at == truth.end() ? INFINITY : (pose.world_T_body.translation() - at->second.translation()).norm();
  };
  const double last_quarter = samples.front().t + 0.75 * (samples.back().t - samples.front().t);
  double sum = 0.0;
  int n = 0;
  for (const CorrectedPose& pose : run->estimate) {
    const double error = errorOf(pose);
    if (pose.t >= t_jump && pose.state == TrackingState::kTracking && error > 1.0) {
      outcome.wrong_tracking_until = pose.t - t_jump;
    }
    if (pose.t >= last_quarter && std::isfinite(error)) {
      sum += error;
      ++n;
    }
  }
  outcome.last_quarter_mean_m = n > 0 ? sum / n : INFINITY;
  outcome.size_counts_every_keyframe =
      !run->stats.empty() && run->stats.back().main_vertices >= static_cast<int>(run->keyframes.size());
  outcome.losses = run->localizer_counters.losses;
  outcome.pose_jumps = run->pipeline_counters.odometry_pose_jumps;
  outcome.held_at_pose_jump = run->pipeline_counters.odometry_held_at_pose_jump;
  outcome.relocalizations = run->localizer_counters.relocalizations;
  outcome.final_state = run->estimate.empty() ? TrackingState::kInitialising : run->estimate.back().state;
  auto metrics = computeRunMetrics(sequence, *run);
  EXPECT_TRUE(metrics.ok());
  if (metrics.ok()) {
    outcome.ate_m = metrics->estimate.ate_m;
    outcome.vio_ate_m = metrics->vio.ate_m;
  }
  std::printf("%s %s seed %d jump (%.1f, %.1f, %.1f): tracking while > 1 m off until %.2f s after the jump, %d losses, "
              "%d relocalisations, final %s, last-quarter mean error %.3f m, ATE %.3f m (VIO %.3f m)\n",
              profile.c_str(), track_name.c_str(), static_cast<int>(seed), jump.x(), jump.y(), jump.z(),
              outcome.wrong_tracking_until, outcome.losses, outcome.relocalizations,
              trackingStateName(outcome.final_state), outcome.last_quarter_mean_m, outcome.ate_m, outcome.vio_ate_m);
  return outcome;
}

/// Issue 24's target for a jump: found and a map pose again within 2 s, tracking to the end, as good as
/// tracking makes it over the last quarter (0.1-0.3 m on these profiles, not the jump's 3 m), better than VIO.
inline void expectRecovered(const JumpOutcome& outcome, const std::string& what) {
  EXPECT_EQ(outcome.pose_jumps, 1) << what;
  EXPECT_EQ(outcome.held_at_pose_jump, 2) << what;
  EXPECT_GE(outcome.losses, 1) << what;
  EXPECT_GE(outcome.relocalizations, 1) << what;
  EXPECT_TRUE(outcome.size_counts_every_keyframe) << what;
  EXPECT_LT(outcome.wrong_tracking_until, 2.0) << what;
  EXPECT_EQ(outcome.final_state, TrackingState::kTracking) << what;
  EXPECT_LT(outcome.last_quarter_mean_m, 0.5) << what;
  EXPECT_LT(outcome.ate_m, outcome.vio_ate_m) << what;
}

}  // namespace dualgraph::jumptest
