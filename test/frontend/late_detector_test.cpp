// SPDX-License-Identifier: MIT
// A real detector delivers 20-100 ms after its image: with the default configuration its detections are used as the
// replay uses them; one later than localizer.detection_latency is refused with a Status, counted and shown in the
// snapshot, in both threading modes.
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>
#include <vector>

#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "test/frontend/simulated_flight.h"
#include "test/frontend/streaming_flight.h"

namespace dualgraph {
namespace {

struct LateFeed {
  std::vector<CorrectedPose> estimate;  ///< the pose at each sample, as addOdometry answered it
  std::vector<CorrectedPose> keyframes;
  int refused_too_late = 0;      ///< addDetections answered kFailedPrecondition "arrived after..."
  int other_refusals = 0;
  long snapshot_too_late = 0;    ///< PipelineSnapshot::detections_too_late after finish
  int counted_unplaced = 0;      ///< PipelineCounters::detections_unplaced
  PipelineCounters counters;
};

// One thread, as a drone's callbacks would interleave: before each odometry sample, every detection instant whose
// image (on the odometry clock) is at least `late_s` older than the sample and an empty instant there (the images up
// to it held no more gates), then the sample.
LateFeed feedLate(const Sequence& sequence, const SequenceRunParams& params, PipelineThreading threading, double late_s) {
  LateFeed out;
  auto created = StreamingLocalizer::create(params, sequence.map, sequence.camera, threading);
  EXPECT_TRUE(created.ok()) << created.status().message();
  if (!created.ok()) return out;
  StreamingLocalizer& pipeline = **created;
  const std::vector<DetectionInstant> instants = flighttest::detectionInstants(sequence);
  const double offset = sequence.camera ? sequence.camera->time_offset : 0.0;
  size_t next = 0;
  const auto deliver = [&](double until) {
    for (; next < instants.size() && instants[next].t - offset <= until; ++next) {
      const Status added = pipeline.addDetections(instants[next]);
      if (added.ok()) continue;
      const bool too_late = added.code() == StatusCode::kFailedPrecondition &&
                            added.message().find("detection_latency") != std::string::npos;
      (too_late ? out.refused_too_late : out.other_refusals) += static_cast<int>(instants[next].size());
    }
  };
  for (size_t k = 0; k < sequence.odometry.samples.size(); ++k) {
    deliver(sequence.odometry.samples[k].t - late_s);
    DetectionInstant done;  // the images up to then held nothing more: the detector is done up to there
    done.t = sequence.odometry.samples[k].t - late_s + offset;
    if (next == instants.size() || done.t < instants[next].t) {
      EXPECT_TRUE(pipeline.addDetections(done).ok());
    }
    Result<PoseUpdate> update = pipeline.addOdometry(flighttest::odometryInput(sequence, k));
    EXPECT_TRUE(update.ok()) << update.status().message();
    if (update.ok()) out.estimate.push_back(update->pose);
    // Worker mode: the VIO's pace (the loop is faster than 100 Hz); the worker stays within 10 samples.
    while (threading == PipelineThreading::kWorker && static_cast<long>(k) + 1 - pipeline.snapshot().samples > 10) {
      std::this_thread::yield();
    }
  }
  deliver(sequence.odometry.samples.back().t);
  auto results = pipeline.finish();
  EXPECT_TRUE(results.ok()) << results.status().message();
  if (!results.ok()) return out;
  out.keyframes = results->keyframes;
  out.counters = results->pipeline_counters;
  out.counted_unplaced = results->pipeline_counters.detections_unplaced;
  out.snapshot_too_late = pipeline.snapshot().detections_too_late;
  return out;
}

// The default configuration covers a detector 50 ms late that says which images it has processed (an empty instant
// for one without gates): every detection is used and the run is as good as the replay's on-time detector within
// 10 % (its information comes 50 ms later: the lock and the keyframes after it 50 ms later). Before
// (detection_latency 0), about one detection in five was lost without a Status.
TEST(LateDetector, FiftyMillisecondsLateTheDefaultConfigurationUsesEveryDetection) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 1, 3);
  const SequenceRunParams params;
  ASSERT_GE(params.localizer.detection_latency, 0.05 + 0.01);  // 50 ms plus one 100 Hz sample
  auto replayed = runSequence(sequence, params);
  ASSERT_TRUE(replayed.ok()) << replayed.status().message();
  ASSERT_GT(replayed->keyframes.size(), 20u);
  const LateFeed late = feedLate(sequence, params, PipelineThreading::kCallerThread, 0.05);
  EXPECT_EQ(late.refused_too_late + late.other_refusals, 0);
  EXPECT_EQ(late.counted_unplaced, 0);
  EXPECT_EQ(late.counters.detections_unplaced + late.counters.detections_in_gap + late.counters.detections_invalid, 0);
  EXPECT_NEAR(static_cast<double>(late.keyframes.size()), static_cast<double>(replayed->keyframes.size()), 2.0);
  // Its poses (each sample's, as the drone had it) as good as the on-time run's within 10 %.
  SequenceRunResult run;
  run.estimate = late.estimate;
  run.keyframes = late.keyframes;
  auto metrics = computeRunMetrics(sequence, run), replay_metrics = computeRunMetrics(sequence, *replayed);
  ASSERT_TRUE(metrics.ok() && replay_metrics.ok());
  EXPECT_LT(metrics->estimate.ate_m, 1.1 * replay_metrics->estimate.ate_m)
      << metrics->estimate.ate_m << " against " << replay_metrics->estimate.ate_m;
}

// An on-time detector (the replay's) costs no lag for the default wait: a keyframe closes as soon as the detector
// said it is done up to its time, so the run is the one that closes every keyframe at once, pose for pose.
TEST(LateDetector, AnOnTimeDetectorGetsNoLagFromTheDefaultWait) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 2, 2);
  SequenceRunParams at_once;
  at_once.localizer.detection_latency = 0.0;
  auto waiting = runSequence(sequence, SequenceRunParams{});
  auto immediate = runSequence(sequence, at_once);
  ASSERT_TRUE(waiting.ok() && immediate.ok());
  ASSERT_EQ(waiting->estimate.size(), immediate->estimate.size());
  for (size_t k = 0; k < waiting->estimate.size(); ++k) {
    ASSERT_TRUE(waiting->estimate[k].world_T_body.matrix() == immediate->estimate[k].world_T_body.matrix()) << k;
  }
  EXPECT_EQ(waiting->keyframes.size(), immediate->keyframes.size());
}

// A detector later than the configured latency: each detection that can no longer be placed is refused at once with
// a Status naming detection_latency, counted (detections_unplaced) and shown in the snapshot, in both modes; the
// pipeline goes on tracking.
TEST(LateDetector, LaterThanTheLatencyEachDetectionIsRefusedCountedAndShownInTheSnapshot) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 1, 2);
  SequenceRunParams params;
  params.localizer.detection_latency = 0.02;
  for (PipelineThreading threading : {PipelineThreading::kCallerThread, PipelineThreading::kWorker}) {
    const char* mode = threading == PipelineThreading::kWorker ? "worker" : "caller thread";
    const LateFeed late = feedLate(sequence, params, threading, 0.3);
    EXPECT_GT(late.refused_too_late, 0) << mode;
    EXPECT_EQ(late.other_refusals, 0) << mode;
    // Worker mode refuses at submission what the last published view already rules out; the rest the worker counts.
    EXPECT_GE(late.counted_unplaced, late.refused_too_late) << mode;
    EXPECT_EQ(late.snapshot_too_late, late.counted_unplaced) << mode;
    if (threading == PipelineThreading::kCallerThread) {
      EXPECT_EQ(late.counted_unplaced, late.refused_too_late);
    }
    EXPECT_GT(late.keyframes.size(), 0u) << mode;
  }
}

// "Done up to t" stamped on another clock (1000 s ahead) is refused as such a detection is, in both modes: taken, it
// would make every later detection "older than the one before it". An older one says nothing new and is ignored.
TEST(LateDetector, ADoneMarkFarAheadIsRefusedAndHoldsNothingBack) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 1, 1);
  const std::vector<DetectionInstant> instants = flighttest::detectionInstants(sequence);
  ASSERT_FALSE(instants.empty());
  const double offset = sequence.camera ? sequence.camera->time_offset : 0.0;
  for (PipelineThreading threading : {PipelineThreading::kCallerThread, PipelineThreading::kWorker}) {
    auto created = StreamingLocalizer::create(SequenceRunParams{}, sequence.map, sequence.camera, threading);
    ASSERT_TRUE(created.ok());
    StreamingLocalizer& pipeline = **created;
    size_t k = 0;
    while (sequence.odometry.samples[k].t < instants[0].t - offset) {
      ASSERT_TRUE(pipeline.addOdometry(flighttest::odometryInput(sequence, k++)).ok());
    }
    while (threading == PipelineThreading::kWorker && pipeline.snapshot().samples < static_cast<long>(k)) {
      std::this_thread::yield();
    }
    DetectionInstant far;
    far.t = instants[0].t + 1000.0;
    const Status refused = pipeline.addDetections(far);
    if (threading == PipelineThreading::kCallerThread) {
      EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument) << refused.message();
    }
    DetectionInstant older;
    older.t = instants[0].t - 5.0;
    EXPECT_TRUE(pipeline.addDetections(older).ok());
    EXPECT_TRUE(pipeline.addDetections(instants[0]).ok());  // not "older than the one before it"
    auto results = pipeline.finish();
    ASSERT_TRUE(results.ok()) << results.status().message();
    EXPECT_EQ(results->pipeline_counters.detections_backwards, 0);
  }
}

}  // namespace
}  // namespace dualgraph
