// SPDX-License-Identifier: MIT
// A real detector delivers 20-100 ms after its image: with the default configuration its detections are used as the
// replay uses them; one later than localizer.detection_latency is refused with a Status, counted and shown in the
// snapshot, in both threading modes.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "dualgraph/frontend/sequence_run.h"
#include "test/frontend/simulated_flight.h"
#include "test/frontend/streaming_flight.h"

namespace dualgraph {
namespace {

struct LateFeed {
  std::vector<CorrectedPose> keyframes;
  int refused_too_late = 0;      ///< addDetections answered kFailedPrecondition "arrived after..."
  int other_refusals = 0;
  long snapshot_too_late = 0;    ///< PipelineSnapshot::detections_too_late after finish
  int counted_unplaced = 0;      ///< PipelineCounters::detections_unplaced
  PipelineCounters counters;
};

// One thread, as a drone's callbacks would interleave: before each odometry sample, every detection instant whose
// image (on the odometry clock) is at least `late_s` older than the sample, then the sample.
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
    EXPECT_TRUE(pipeline.addOdometry(flighttest::odometryInput(sequence, k)).ok());
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

// The default configuration covers a detector 50 ms late: the keyframes are the replay's, nothing refused. Before
// (detection_latency 0), about one detection in five was lost without a Status.
TEST(LateDetector, FiftyMillisecondsLateTheDefaultConfigurationGivesTheReplaysKeyframes) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 1, 3);
  const SequenceRunParams params;
  ASSERT_GE(params.localizer.detection_latency, 0.05 + 0.01);  // 50 ms plus one 100 Hz sample
  auto replayed = runSequence(sequence, params);
  ASSERT_TRUE(replayed.ok()) << replayed.status().message();
  ASSERT_GT(replayed->keyframes.size(), 20u);
  const LateFeed late = feedLate(sequence, params, PipelineThreading::kCallerThread, 0.05);
  EXPECT_EQ(late.refused_too_late + late.other_refusals, 0);
  EXPECT_EQ(late.counted_unplaced, 0);
  ASSERT_EQ(late.keyframes.size(), replayed->keyframes.size());
  for (size_t k = 0; k < late.keyframes.size(); ++k) {
    ASSERT_EQ(late.keyframes[k].t, replayed->keyframes[k].t) << k;
    ASSERT_TRUE(late.keyframes[k].world_T_body.isApprox(replayed->keyframes[k].world_T_body, 1e-9)) << k;
  }
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

}  // namespace
}  // namespace dualgraph
