// SPDX-License-Identifier: MIT
// TrackingMonitor's rules (loss of lock, recovery, what is no evidence) and the Localizer's tracking state:
// initialising until relocalize, the states its poses carry, relocalize's bookkeeping.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "dualgraph/dual_graph/tracking_monitor.h"
#include "test/dual_graph/localizer_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

std::vector<Eigen::Vector3d> at(double x) { return {Eigen::Vector3d(x, 0.0, 1.0)}; }

TEST(TrackingMonitor, APersistentUnmatchedGateWithoutSuccessTurnsLostAfterTheTime) {
  TrackingMonitor monitor(TrackingState::kTracking, 1.0, 5);
  monitor.locked(0.0);
  // The same gate, seen 30 times a second, 3 m from where the map has it: persistent failures.
  double t = 0.1;
  for (; t < 0.95; t += 1.0 / 30.0) monitor.addUnmatched(t, at(5.0 + 0.01 * t));
  EXPECT_EQ(monitor.state(), TrackingState::kTracking) << "before lost_after_s";
  EXPECT_GE(monitor.failuresSinceSuccess(), 5);
  for (; t < 1.1; t += 1.0 / 30.0) monitor.addUnmatched(t, at(5.0));
  EXPECT_EQ(monitor.state(), TrackingState::kLost);
  EXPECT_EQ(monitor.losses(), 1);
  // A gate edge accepted among the failures is no clean evidence (it may be a gate matched to its neighbour by
  // the wrong estimate): still lost.
  monitor.addUpdate(1.2, 1, 0);
  EXPECT_EQ(monitor.state(), TrackingState::kLost);
  EXPECT_EQ(monitor.recoveries(), 0);
  // Accepted once the last failure is lost_after_s old: tracking again.
  monitor.addUpdate(2.2, 1, 0);
  EXPECT_EQ(monitor.state(), TrackingState::kTracking);
  EXPECT_EQ(monitor.recoveries(), 1);
  EXPECT_EQ(monitor.failuresSinceSuccess(), 0);
}

TEST(TrackingMonitor, FailuresBesideSuccessesMakeTheFrameSuspiciousButNotLost) {
  TrackingMonitor monitor(TrackingState::kTracking, 1.0, 5);
  monitor.locked(0.0);
  // Half the gates keep fitting (an edge a keyframe), the other half are seen again where the map has none.
  double t = 0.1;
  for (; t < 3.0; t += 1.0 / 30.0) {
    monitor.addUnmatched(t, at(5.0));
    if (static_cast<int>(t * 30.0) % 10 == 0) monitor.addUpdate(t, 1, 0);
  }
  EXPECT_EQ(monitor.state(), TrackingState::kTracking);  // successes keep it alive
  EXPECT_GE(monitor.recentFailures(), 5);
  EXPECT_TRUE(monitor.suspicious());
  // The failures stop: after lost_after_s nothing is suspicious any more.
  monitor.addUpdate(t + 1.1, 1, 0);
  EXPECT_EQ(monitor.recentFailures(), 0);
  EXPECT_FALSE(monitor.suspicious());
  // A check found a better frame: lost (counted), and the relocalisation's lock makes it tracking.
  monitor.declareLost(t + 1.2);
  EXPECT_EQ(monitor.state(), TrackingState::kLost);
  EXPECT_EQ(monitor.losses(), 1);
  EXPECT_FALSE(monitor.suspicious());
  monitor.locked(t + 1.3);
  EXPECT_EQ(monitor.state(), TrackingState::kTracking);
}

TEST(TrackingMonitor, OneOffFalseDetectionsAndSilenceAreNoEvidence) {
  TrackingMonitor monitor(TrackingState::kTracking, 1.0, 5);
  monitor.locked(0.0);
  // A false detection every frame, each somewhere else (metres apart): never the same gate twice.
  for (int k = 0; k < 300; ++k) monitor.addUnmatched(0.1 + k / 30.0, at(3.0 * k));
  EXPECT_EQ(monitor.state(), TrackingState::kTracking);
  EXPECT_EQ(monitor.failuresSinceSuccess(), 0);
  // Updates without edges (no gate in view) neither.
  for (int k = 0; k < 50; ++k) monitor.addUpdate(11.0 + k, 0, 0);
  EXPECT_EQ(monitor.state(), TrackingState::kTracking);
}

TEST(TrackingMonitor, RejectedEdgesCountAndASuccessResetsTheCount) {
  TrackingMonitor monitor(TrackingState::kTracking, 1.0, 5);
  monitor.locked(0.0);
  monitor.addUpdate(0.5, 0, 4);
  monitor.addUpdate(0.9, 1, 0);  // accepted: the count starts again
  monitor.addUpdate(1.5, 0, 4);
  EXPECT_EQ(monitor.state(), TrackingState::kTracking);  // 4 < 5
  monitor.addUpdate(2.0, 0, 3);                          // 7 failures, 1.1 s since the success
  EXPECT_EQ(monitor.state(), TrackingState::kLost);
}

TEST(TrackingMonitor, InitialisingStaysSoUntilLocked) {
  TrackingMonitor monitor(TrackingState::kInitialising, 1.0, 5);
  for (int k = 0; k < 100; ++k) monitor.addUnmatched(k / 30.0, at(1.0));
  monitor.addUpdate(4.0, 0, 10);
  EXPECT_EQ(monitor.state(), TrackingState::kInitialising);
  EXPECT_EQ(monitor.losses(), 0);
  monitor.locked(4.0);
  EXPECT_EQ(monitor.state(), TrackingState::kTracking);
}

TEST(LocalizerTracking, InitialisingUsesNoObservationUntilRelocalizedThenTracks) {
  const SyntheticRace race = makeSyntheticRace({});
  auto created = Localizer::create(LocalizerParams{}, race.map, TrackingState::kInitialising);
  ASSERT_TRUE(created.ok()) << created.status().message();
  Localizer& localizer = **created;
  EXPECT_EQ(localizer.trackingState(), TrackingState::kInitialising);
  EXPECT_EQ(localizer.relocalize(Eigen::Isometry3d::Identity()).status().code(), StatusCode::kFailedPrecondition);
  size_t k = 0;
  for (; k < race.odometry.size() / 4; ++k) {
    auto pose = localizer.addOdometry(race.odometry[k]);
    ASSERT_TRUE(pose.ok());
    EXPECT_EQ(pose->state, TrackingState::kInitialising);
  }
  const Status refused = localizer.addObservation(race.observations.front());
  EXPECT_EQ(refused.code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(refused.message().find("initialising"), std::string::npos) << refused.message();
  EXPECT_TRUE(localizer.keyframeTrajectory().empty());  // no graph yet
  // Anchored at the last sample at or before `since`, not the newest: the odometry since is still there.
  const double since = race.odometry[k / 2].t + 1e-9;
  auto anchor = localizer.relocalize(Eigen::Isometry3d::Identity(), since, 0.2, 0.04);
  ASSERT_TRUE(anchor.ok()) << anchor.status().message();
  EXPECT_EQ(*anchor, race.odometry[k / 2].t);
  EXPECT_EQ(localizer.trackingState(), TrackingState::kTracking);
  EXPECT_EQ(localizer.counters().relocalizations, 0);  // a first lock, not a relocalisation
  for (const GateObservation& observation : race.observations) {
    if (observation.t >= *anchor && observation.t <= race.odometry[k - 1].t) {
      EXPECT_TRUE(localizer.addObservation(observation).ok());
    }
  }
  for (; k < race.odometry.size(); ++k) {
    auto pose = localizer.addOdometry(race.odometry[k]);
    ASSERT_TRUE(pose.ok());
    EXPECT_EQ(pose->state, TrackingState::kTracking);
  }
  ASSERT_TRUE(localizer.finish().ok());
  EXPECT_EQ(localizer.keyframeTrajectory().front().t, *anchor);
  EXPECT_EQ(localizer.counters().losses, 0);
}

TEST(LocalizerTracking, RelocalizeKeepsTheKeyframesSoFarAndCountsWhatItDrops) {
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> localizer = makeLocalizer(LocalizerParams{}, race.map);
  EXPECT_FALSE(localizer->frameConfirmed());  // given, no gate edge yet
  const RunOutput half = runRace(*localizer, race);  // the whole race, tracking from the given frame
  EXPECT_TRUE(localizer->frameConfirmed());
  const size_t before = localizer->keyframeTrajectory().size();
  ASSERT_GT(before, 2u);
  ASSERT_TRUE(localizer->relocalize(Eigen::Isometry3d::Identity()).ok());
  EXPECT_FALSE(localizer->frameConfirmed());  // a new frame: no gate edge in it yet
  EXPECT_EQ(localizer->keyframeTrajectory().size(), before + 1);  // the old ones, then the new first keyframe
  EXPECT_EQ(localizer->trackingState(), TrackingState::kTracking);
  Eigen::Isometry3d sheared = Eigen::Isometry3d::Identity();
  sheared.linear()(0, 1) = 0.5;
  EXPECT_EQ(localizer->relocalize(sheared).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(Localizer::create(LocalizerParams{}, race.map, TrackingState::kLost).status().code(),
            StatusCode::kInvalidArgument);
  (void)half;
}

}  // namespace
}  // namespace dualgraph

namespace dualgraph {
namespace {

// A drone may hand relocalize or resumeWithNewGraph a σ computed onboard: NaN, infinity or one whose square
// overflows is refused, and the run goes on in the graph it had — before, the new graph replaced the old one
// before its first keyframe's prior was refused, and the next keyframe read a graph without keyframes.
TEST(LocalizerTracking, AnUnusablePriorSigmaIsRefusedAndChangesNothing) {
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> localizer = makeLocalizer(LocalizerParams{}, race.map);
  const size_t half = race.odometry.size() / 2;
  size_t next_observation = 0;
  auto feed = [&](size_t from, size_t to) {
    for (size_t k = from; k < to; ++k) {
      while (next_observation < race.observations.size() && race.observations[next_observation].t <= race.odometry[k].t) {
        ASSERT_TRUE(localizer->addObservation(race.observations[next_observation++]).ok());
      }
      ASSERT_TRUE(localizer->addOdometry(race.odometry[k]).ok());
    }
  };
  feed(0, half);
  const size_t keyframes = localizer->keyframeTrajectory().size();
  ASSERT_GT(keyframes, 2u);
  const double inf = std::numeric_limits<double>::infinity();
  const std::pair<double, double> unusable[] = {{NAN, 0.1}, {0.2, NAN}, {inf, 0.1}, {0.2, inf}, {1e200, 0.1}, {0.2, 1e160}};
  for (const auto& [sigma_t, sigma_r] : unusable) {
    SCOPED_TRACE(std::to_string(sigma_t) + " " + std::to_string(sigma_r));
    const auto refused = localizer->relocalize(Eigen::Isometry3d::Identity(), race.odometry[half - 1].t, sigma_t, sigma_r);
    EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(refused.status().message().find("sigma"), std::string::npos) << refused.status().message();
    EXPECT_EQ(localizer->keyframeTrajectory().size(), keyframes);
    EXPECT_TRUE(localizer->frameConfirmed());
    EXPECT_EQ(localizer->trackingState(), TrackingState::kTracking);
  }
  localizer->distrustFrame();
  ASSERT_EQ(localizer->trackingState(), TrackingState::kLost);
  EXPECT_EQ(localizer->resumeWithNewGraph(1e200, 0.1).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(localizer->trackingState(), TrackingState::kLost);
  EXPECT_EQ(localizer->counters().recoveries, 0);
  localizer->resumeTracking();
  feed(half, race.odometry.size());
  ASSERT_TRUE(localizer->finish().ok());
  EXPECT_GT(localizer->keyframeTrajectory().size(), keyframes);
  EXPECT_EQ(localizer->counters().relocalizations, 0);
}

}  // namespace
}  // namespace dualgraph
