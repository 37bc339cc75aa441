// SPDX-License-Identifier: MIT
// Detections that reach the Localizer late (a detector's latency): without waiting, those of a keyframe's last
// instants arrive after it closed and are lost; a keyframe that waits LocalizerParams::detection_latency gets
// every one of them, and the same keyframes as when they arrive at once.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "test/dual_graph/localizer_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

/// Feeds `race` as onboard with a detector `delay` [s] late: an observation stamped t is given once the
/// odometry has reached t + delay (before that sample), the rest after the last sample, then finish().
void runLate(Localizer& localizer, const SyntheticRace& race, double delay) {
  size_t next = 0;
  for (const OdometrySample& sample : race.odometry) {
    while (next < race.observations.size() && race.observations[next].t <= sample.t - delay) {
      (void)localizer.addObservation(race.observations[next++]);  // refusals are counted
    }
    ASSERT_TRUE(localizer.addOdometry(sample).ok());
  }
  while (next < race.observations.size()) (void)localizer.addObservation(race.observations[next++]);
  ASSERT_TRUE(localizer.finish().ok());
}

std::vector<CorrectedPose> keyframesOf(const LocalizerParams& params, const SyntheticRace& race, double delay,
                                       LocalizerCounters* counters) {
  std::unique_ptr<Localizer> localizer = makeLocalizer(params, race.map);
  if (!localizer) return {};
  runLate(*localizer, race, delay);
  *counters = localizer->counters();
  return localizer->keyframeTrajectory();
}


/// A keyframe closed at once (detection_latency 0; the default waits 0.1 s).
LocalizerParams closedAtOnce() {
  LocalizerParams params;
  params.detection_latency = 0.0;
  return params;
}

// A detector that says it is done up to each sample (observationsCompleteUntil) costs no wait: the keyframes close
// as they do at detection_latency 0, and every pose the Localizer answers is that run's.
TEST(DetectionLatency, ADetectorDoneUpToTheSampleClosesKeyframesWithoutWaiting) {
  const SyntheticRace race = makeSyntheticRace({});
  std::unique_ptr<Localizer> waiting = makeLocalizer(LocalizerParams{}, race.map);
  std::unique_ptr<Localizer> at_once = makeLocalizer(closedAtOnce(), race.map);
  ASSERT_TRUE(waiting && at_once);
  ASSERT_GT(LocalizerParams{}.detection_latency, 0.0);
  size_t next = 0;
  for (const OdometrySample& sample : race.odometry) {
    while (next < race.observations.size() && race.observations[next].t <= sample.t) {
      (void)waiting->addObservation(race.observations[next]);
      (void)at_once->addObservation(race.observations[next++]);
    }
    waiting->observationsCompleteUntil(sample.t);
    Result<CorrectedPose> a = waiting->addOdometry(sample), b = at_once->addOdometry(sample);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_TRUE(a->world_T_body.matrix() == b->world_T_body.matrix()) << sample.t;
  }
  EXPECT_EQ(waiting->keyframeTrajectory().size(), at_once->keyframeTrajectory().size());
  EXPECT_GT(waiting->keyframeTrajectory().size(), 20u);
}

TEST(DetectionLatency, TheDefaultWaitCoversADetectorAHundredMillisecondsLate) {
  const SyntheticRace race = makeSyntheticRace({});
  LocalizerCounters on_time, late;
  const std::vector<CorrectedPose> expected = keyframesOf(LocalizerParams{}, race, 0.0, &on_time);
  const std::vector<CorrectedPose> got = keyframesOf(LocalizerParams{}, race, 0.1, &late);
  EXPECT_EQ(late.observations_rejected, 0) << late.last_error;
  ASSERT_EQ(got.size(), expected.size());
  for (size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].t, expected[k].t) << k;
    EXPECT_LT((got[k].world_T_body.matrix() - expected[k].world_T_body.matrix()).norm(), 1e-9) << k;
  }
}

TEST(DetectionLatency, WithoutWaitingTheDetectionsOfAKeyframesLastInstantsAreLostAndCounted) {
  const SyntheticRace race = makeSyntheticRace({});
  LocalizerCounters at_once, late;
  (void)keyframesOf(closedAtOnce(), race, 0.0, &at_once);
  (void)keyframesOf(closedAtOnce(), race, 0.05, &late);
  EXPECT_EQ(at_once.observations_too_late, 0);
  // 30 Hz detections and keyframes every 2 m at 8 m/s: about one or two detections per keyframe arrive too late.
  EXPECT_GT(late.observations_too_late, 10) << late.last_error;
  EXPECT_EQ(late.observations_rejected, late.observations_too_late);
  EXPECT_EQ(late.observations_accepted + late.observations_rejected, static_cast<int>(race.observations.size()));
}

TEST(DetectionLatency, AKeyframeThatWaitsGetsEveryDetectionAndTheSameKeyframesAsWithoutLatency) {
  const SyntheticRace race = makeSyntheticRace({});
  LocalizerCounters at_once_counters;
  const std::vector<CorrectedPose> at_once = keyframesOf(closedAtOnce(), race, 0.0, &at_once_counters);
  ASSERT_GT(at_once.size(), 20u);
  LocalizerParams waiting;
  waiting.detection_latency = 0.05;
  for (double delay : {0.05, 0.03, 0.0}) {  // as late as the wait, less late, on time
    LocalizerCounters counters;
    const std::vector<CorrectedPose> keyframes = keyframesOf(waiting, race, delay, &counters);
    EXPECT_EQ(counters.observations_too_late, 0) << delay << ": " << counters.last_error;
    EXPECT_EQ(counters.observations_rejected, 0) << delay;
    EXPECT_EQ(counters.observations_never_processed, 0) << delay;
    ASSERT_EQ(keyframes.size(), at_once.size()) << delay;
    for (size_t k = 0; k < keyframes.size(); ++k) {
      EXPECT_EQ(keyframes[k].t, at_once[k].t) << delay << " keyframe " << k;
      EXPECT_LT((keyframes[k].world_T_body.matrix() - at_once[k].world_T_body.matrix()).norm(), 1e-9)
          << delay << " keyframe " << k;
    }
  }
}

TEST(DetectionLatency, TheCorrectionLagsByTheWaitAndNegativeOrNonFiniteWaitsAreRefused) {
  const SyntheticRace race = makeSyntheticRace({});
  LocalizerParams waiting;
  waiting.detection_latency = 0.2;
  std::unique_ptr<Localizer> localizer = makeLocalizer(waiting, race.map);
  ASSERT_NE(localizer, nullptr);
  size_t next = 0;
  double first_keyframe_decided = -1.0;
  for (const OdometrySample& sample : race.odometry) {
    while (next < race.observations.size() && race.observations[next].t <= sample.t) {
      ASSERT_TRUE(localizer->addObservation(race.observations[next++]).ok());
    }
    const size_t before = localizer->mainGraph().keyframes().size();
    ASSERT_TRUE(localizer->addOdometry(sample).ok());
    if (localizer->mainGraph().keyframes().size() > before && before == 1) {
      first_keyframe_decided = localizer->mainGraph().keyframes().back().t;
      // The second keyframe enters the graph once the odometry is 0.2 s past it.
      EXPECT_GE(sample.t, first_keyframe_decided + 0.2 - 1e-12);
      EXPECT_LT(sample.t, first_keyframe_decided + 0.2 + 0.011);  // 100 Hz odometry
      break;
    }
  }
  EXPECT_GT(first_keyframe_decided, 0.0);
  for (double bad : {-0.01, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    LocalizerParams params;
    params.detection_latency = bad;
    const auto refused = Localizer::create(params, race.map);
    ASSERT_FALSE(refused.ok()) << bad;
    EXPECT_NE(refused.status().message().find("detection_latency"), std::string::npos) << refused.status().message();
  }
}

}  // namespace
}  // namespace dualgraph
