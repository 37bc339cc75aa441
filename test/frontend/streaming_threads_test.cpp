// SPDX-License-Identifier: MIT
// StreamingLocalizer fed as a drone feeds it: odometry from one thread, detections from another, a publisher
// reading snapshots from a third; the graph equals the replay's and the streamed poses hold its accuracy.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "test/frontend/simulated_flight.h"
#include "test/frontend/streaming_flight.h"

namespace dualgraph {
namespace {

struct Streamed {
  std::vector<CorrectedPose> estimate;
  PipelineResults results;
  long snapshots_read = 0;
  bool snapshots_consistent = true;
};

// Feeds `sequence` from two producer threads into a pipeline in `threading` mode while a publisher reads
// snapshots. The detector delivers an instant once the odometry is within 0.2 s of it (never far ahead), and between
// them says it is done up to each odometry time (an empty instant: a real detector's image without gates); the
// odometry thread waits for the instants up to its sample's time (so every detection arrives on time) and, in worker
// mode, for the worker to be within 10 samples.
Streamed streamFlight(const Sequence& sequence, const SequenceRunParams& params, PipelineThreading threading) {
  Streamed out;
  auto created = StreamingLocalizer::create(params, sequence.map, sequence.camera, threading);
  EXPECT_TRUE(created.ok()) << created.status().message();
  if (!created.ok()) return out;
  StreamingLocalizer& pipeline = **created;
  const double offset = sequence.camera ? sequence.camera->time_offset : 0.0;
  // The detector 50 ms ahead of the odometry thread, on the camera's clock as given (a self-calibrated offset moves
  // it by a few ms): before each sample it has said it is done up to 50 ms past it.
  constexpr double kDetectorAhead = 0.05;
  const std::vector<DetectionInstant> instants = flighttest::withDoneMarks(sequence, kDetectorAhead + offset);
  std::atomic<double> odometry_t{sequence.odometry.samples.front().t};  // the clock starts at the first sample
  std::atomic<size_t> delivered{0};
  std::atomic<bool> done{false};

  std::thread detector([&] {
    for (size_t i = 0; i < instants.size(); ++i) {
      while (odometry_t.load() < instants[i].t - offset - 0.2 && !done.load()) std::this_thread::yield();
      EXPECT_TRUE(pipeline.addDetections(instants[i]).ok());
      delivered.store(i + 1);
    }
  });
  std::thread publisher([&] {
    double last_t = -std::numeric_limits<double>::infinity();
    while (!done.load()) {
      const PipelineSnapshot snapshot = pipeline.snapshot();
      ++out.snapshots_read;
      if (snapshot.t < last_t || !snapshot.map_T_odom.matrix().allFinite() ||
          !snapshot.world_T_body.matrix().allFinite()) {
        out.snapshots_consistent = false;
      }
      last_t = snapshot.t;
    }
  });
  size_t next_instant = 0;
  for (size_t k = 0; k < sequence.odometry.samples.size(); ++k) {
    const double t = sequence.odometry.samples[k].t;
    while (next_instant < instants.size() && instants[next_instant].t - offset <= t + kDetectorAhead + 1e-9) {
      ++next_instant;
    }
    while (delivered.load() < next_instant) std::this_thread::yield();
    Result<PoseUpdate> update = pipeline.addOdometry(flighttest::odometryInput(sequence, k));
    EXPECT_TRUE(update.ok()) << update.status().message();
    if (update.ok()) out.estimate.push_back(update->pose);
    odometry_t.store(t);
    // The VIO's pace: the worker keeps up with 100 Hz odometry in real time (bench/README: per-sample figures);
    // here the samples come as fast as the loop goes, so the producer lets it stay at most 10 samples behind.
    while (threading == PipelineThreading::kWorker && static_cast<long>(k) + 1 - pipeline.snapshot().samples > 10) {
      std::this_thread::yield();
    }
  }
  detector.join();
  Result<PipelineResults> results = pipeline.finish();
  done.store(true);
  publisher.join();
  EXPECT_TRUE(results.ok()) << results.status().message();
  if (results.ok()) out.results = std::move(results).value();
  return out;
}

double ateOf(const Sequence& sequence, const std::vector<CorrectedPose>& estimate, const PipelineResults& results) {
  SequenceRunResult run;
  run.estimate = estimate;
  run.keyframes = results.keyframes;
  run.stats = results.stats;
  run.localizer_counters = results.localizer_counters;
  run.frontend_counters = results.frontend_counters;
  auto metrics = computeRunMetrics(sequence, run);
  EXPECT_TRUE(metrics.ok()) << metrics.status().message();
  return metrics.ok() ? metrics->estimate.ate_m : INFINITY;
}

TEST(StreamingThreads, TwoProducersAndAPublisherGiveTheReplaysGraphAndItsAccuracy) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 1, 12);  // the demo's race
  const SequenceRunParams params;  // the frame found from the detections, no start pose
  auto replayed = runSequence(sequence, params);
  ASSERT_TRUE(replayed.ok()) << replayed.status().message();
  auto replay_metrics = computeRunMetrics(sequence, *replayed);
  ASSERT_TRUE(replay_metrics.ok());
  ASSERT_GT(replay_metrics->ate_reduction_pct, 80.0);

  for (PipelineThreading threading : {PipelineThreading::kCallerThread, PipelineThreading::kWorker}) {
    const std::string what = threading == PipelineThreading::kWorker ? "worker" : "caller thread";
    const Streamed streamed = streamFlight(sequence, params, threading);
    EXPECT_TRUE(streamed.snapshots_consistent) << what;
    EXPECT_GT(streamed.snapshots_read, 0) << what;
    // Every detection arrived before the odometry passed it: the graph saw what the replay's saw.
    ASSERT_EQ(streamed.results.keyframes.size(), replayed->keyframes.size()) << what;
    for (size_t k = 0; k < replayed->keyframes.size(); ++k) {
      ASSERT_EQ(streamed.results.keyframes[k].t, replayed->keyframes[k].t) << what;
      ASSERT_TRUE(streamed.results.keyframes[k].world_T_body.isApprox(replayed->keyframes[k].world_T_body, 1e-9)) << what;
    }
    EXPECT_EQ(streamed.results.frontend_counters.used, replayed->frontend_counters.used) << what;
    ASSERT_EQ(streamed.estimate.size(), replayed->estimate.size()) << what;
    // The poses given at each sample: the replay's exactly in caller-thread mode; through the last finished result
    // in worker mode (a few samples behind at most), within 10 % of the replay's ATE.
    const double ate = ateOf(sequence, streamed.estimate, streamed.results);
    if (threading == PipelineThreading::kCallerThread) {
      EXPECT_EQ(ate, replay_metrics->estimate.ate_m);
    } else {
      EXPECT_LT(ate, 1.1 * replay_metrics->estimate.ate_m + 0.005) << ate << " against " << replay_metrics->estimate.ate_m;
    }
  }
}

TEST(StreamingThreads, DestroyedWithoutFinishTheWorkerStops) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "clean", 2, 1);
  auto pipeline = StreamingLocalizer::create(SequenceRunParams{}, sequence.map, sequence.camera, PipelineThreading::kWorker);
  ASSERT_TRUE(pipeline.ok());
  for (size_t k = 0; k < 200 && k < sequence.odometry.samples.size(); ++k) {
    ASSERT_TRUE((*pipeline)->addOdometry(flighttest::odometryInput(sequence, k)).ok());
  }
  pipeline->reset();  // joins the worker; nothing leaks (ASan, TSan)
}

TEST(StreamingThreads, WorkerModeRefusesBadOdometryAtOnceAndCountsIt) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "clean", 2, 1);
  auto pipeline = StreamingLocalizer::create(SequenceRunParams{}, sequence.map, sequence.camera, PipelineThreading::kWorker);
  ASSERT_TRUE(pipeline.ok());
  ASSERT_TRUE((*pipeline)->addOdometry(flighttest::odometryInput(sequence, 0)).ok());
  OdometryInput bad = flighttest::odometryInput(sequence, 1);
  bad.odom_T_body.translation().x() = NAN;
  EXPECT_EQ((*pipeline)->addOdometry(bad).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ((*pipeline)->addOdometry(flighttest::odometryInput(sequence, 0)).status().code(), StatusCode::kInvalidArgument);
  OdometryInput not_a_covariance = flighttest::odometryInput(sequence, 1);
  not_a_covariance.absolute_covariance = -Matrix6d::Identity();
  EXPECT_FALSE((*pipeline)->addOdometry(not_a_covariance).ok());  // at submission, not later in the worker
  ASSERT_TRUE((*pipeline)->addOdometry(flighttest::odometryInput(sequence, 1)).ok());
  auto results = (*pipeline)->finish();
  ASSERT_TRUE(results.ok()) << results.status().message();
  EXPECT_EQ(results->pipeline_counters.odometry_invalid, 2);
  EXPECT_EQ(results->pipeline_counters.odometry_not_after_previous, 1);
  EXPECT_EQ(results->localizer_counters.odometry_accepted, 2);
  EXPECT_EQ((*pipeline)->snapshot().samples, 5);  // refused ones count as taken: a feeder waiting on it never stalls
  EXPECT_EQ((*pipeline)->finish().status().code(), StatusCode::kFailedPrecondition);
}

// Worker mode checks an instant at submission; what it refuses is counted as the core counts it in caller-thread
// mode, and so is what an adapter could not turn into an input at all.
TEST(StreamingThreads, RefusedDetectionsAreCountedInBothModes) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "clean", 2, 1);
  for (PipelineThreading threading : {PipelineThreading::kCallerThread, PipelineThreading::kWorker}) {
    auto pipeline = StreamingLocalizer::create(SequenceRunParams{}, sequence.map, sequence.camera, threading);
    ASSERT_TRUE(pipeline.ok());
    ASSERT_TRUE((*pipeline)->addOdometry(flighttest::odometryInput(sequence, 0)).ok());
    DetectionInstant infinite;
    infinite.t = sequence.odometry.samples[0].t;
    CornerDetection corners;
    corners.t = infinite.t;
    corners.corners.fill(Eigen::Vector2d(INFINITY, 1.0));
    infinite.corners = {corners, corners};
    EXPECT_EQ((*pipeline)->addDetections(infinite).code(), StatusCode::kInvalidArgument);
    (*pipeline)->countMalformedDetections(3);
    (*pipeline)->countMalformedOdometry();
    auto results = (*pipeline)->finish();
    ASSERT_TRUE(results.ok()) << results.status().message();
    EXPECT_EQ(results->pipeline_counters.detections_invalid, 5);
    EXPECT_EQ(results->pipeline_counters.odometry_invalid, 1);
    EXPECT_EQ(results->localizer_counters.odometry_rejected, 1);
    EXPECT_EQ((*pipeline)->snapshot().samples, 2);
  }
}

// Invalid samples never count towards a new clock: three far-ahead stamps with a NaN in the pose are refused as
// invalid, not held, and the clock stays the one in use, in both modes.
TEST(StreamingThreads, InvalidSamplesFarAheadCannotConfirmANewClock) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "clean", 2, 1);
  for (PipelineThreading threading : {PipelineThreading::kCallerThread, PipelineThreading::kWorker}) {
    auto pipeline = StreamingLocalizer::create(SequenceRunParams{}, sequence.map, sequence.camera, threading);
    ASSERT_TRUE(pipeline.ok());
    for (size_t k = 0; k < 60; ++k) {
      if (k == 30) {
        for (int j = 0; j < 3; ++j) {
          OdometryInput garbage = flighttest::odometryInput(sequence, k);
          garbage.t = 1e6 + j;
          garbage.odom_T_body.translation().y() = NAN;
          EXPECT_EQ((*pipeline)->addOdometry(garbage).status().code(), StatusCode::kInvalidArgument);
        }
      }
      ASSERT_TRUE((*pipeline)->addOdometry(flighttest::odometryInput(sequence, k)).ok()) << k;
    }
    auto results = (*pipeline)->finish();
    ASSERT_TRUE(results.ok()) << results.status().message();
    EXPECT_EQ(results->pipeline_counters.odometry_invalid, 3);
    EXPECT_EQ(results->pipeline_counters.odometry_held_at_clock_jump, 0);
    EXPECT_EQ(results->pipeline_counters.odometry_clock_jumps, 0);
    EXPECT_EQ(results->localizer_counters.odometry_rejected, 3);
  }
}

// A glitched stamp far ahead is held at submission too: the samples after it are not refused as older than it.
TEST(StreamingThreads, WorkerModeHoldsAGlitchedStampAndTakesWhatFollows) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "clean", 2, 1);
  auto pipeline = StreamingLocalizer::create(SequenceRunParams{}, sequence.map, sequence.camera, PipelineThreading::kWorker);
  ASSERT_TRUE(pipeline.ok());
  const size_t samples = std::min<size_t>(300, sequence.odometry.samples.size());
  for (size_t k = 0; k < samples; ++k) {
    if (k == 100) {
      OdometryInput ahead = flighttest::odometryInput(sequence, k);
      ahead.t = 1.7e9;  // an epoch stamp among boot-time ones
      EXPECT_EQ((*pipeline)->addOdometry(ahead).status().code(), StatusCode::kInvalidArgument);
    }
    ASSERT_TRUE((*pipeline)->addOdometry(flighttest::odometryInput(sequence, k)).ok()) << k;
  }
  auto results = (*pipeline)->finish();
  ASSERT_TRUE(results.ok()) << results.status().message();
  EXPECT_EQ(results->pipeline_counters.odometry_held_at_clock_jump, 1);
  EXPECT_EQ(results->pipeline_counters.odometry_not_after_previous, 0);
  EXPECT_EQ(results->localizer_counters.odometry_accepted, static_cast<int>(samples));
}

// The snapshot says how long the pose has gone on the odometry alone: the detector stops halfway through the flight
// and the last gate update stays there while the pose goes on, in both modes.
TEST(StreamingThreads, TheSnapshotSaysWhenTheLastGateUpdateWas) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 2, 2);
  const double offset = sequence.camera ? sequence.camera->time_offset : 0.0;
  const std::vector<DetectionInstant> instants = flighttest::detectionInstants(sequence);
  const double end = sequence.odometry.samples.back().t;
  const double stop = 0.5 * (sequence.odometry.samples.front().t + end);
  for (PipelineThreading threading : {PipelineThreading::kCallerThread, PipelineThreading::kWorker}) {
    SCOPED_TRACE(threading == PipelineThreading::kWorker ? "worker" : "caller thread");
    auto pipeline = StreamingLocalizer::create(SequenceRunParams{}, sequence.map, sequence.camera, threading);
    ASSERT_TRUE(pipeline.ok());
    EXPECT_EQ((*pipeline)->snapshot().last_gate_update_t, -std::numeric_limits<double>::infinity());
    double at_stop = -std::numeric_limits<double>::infinity();
    size_t next = 0;
    for (size_t k = 0; k < sequence.odometry.samples.size(); ++k) {
      const double t = sequence.odometry.samples[k].t;
      while (next < instants.size() && instants[next].t - offset <= t) {
        if (instants[next].t - offset <= stop) {
          ASSERT_TRUE((*pipeline)->addDetections(instants[next]).ok());
        }
        ++next;
      }
      ASSERT_TRUE((*pipeline)->addOdometry(flighttest::odometryInput(sequence, k)).ok());
      while (static_cast<long>(k) + 1 - (*pipeline)->snapshot().samples > 10) std::this_thread::yield();  // worker
      const PipelineSnapshot now = (*pipeline)->snapshot();
      EXPECT_LE(now.last_gate_update_t, now.t);
      if (now.t <= stop + 2.0) at_stop = std::max(at_stop, now.last_gate_update_t);
    }
    auto results = (*pipeline)->finish();
    ASSERT_TRUE(results.ok());
    double newest_with_gates = -std::numeric_limits<double>::infinity();
    for (const KeyframeStats& row : results->stats) {
      if (row.gate_edges_added > 0) newest_with_gates = row.t;
    }
    const PipelineSnapshot last = (*pipeline)->snapshot();
    EXPECT_EQ(last.last_gate_update_t, newest_with_gates);
    EXPECT_GT(last.last_gate_update_t, sequence.odometry.samples.front().t);  // gates were used
    EXPECT_EQ(last.last_gate_update_t, at_stop);  // none after the detector stopped
    EXPECT_GT(last.t - last.last_gate_update_t, end - stop - 2.0);
  }
}

// A worker that falls behind its queue's bound: each input refused there is counted, none lost without a trace.
// Before, a refused odometry sample was in no counter (nor in the snapshot's count) and a refused instant's
// detections likewise. A queue of one input makes refusals certain without stalling the worker by hand.
TEST(StreamingThreads, InputsRefusedAtAFullWorkerQueueAreCounted) {
  const Sequence sequence = flighttest::simulatedFlight("ratm_ellipse.yaml", "clean", 2, 1);
  EXPECT_EQ(StreamingLocalizer::create(SequenceRunParams{}, sequence.map, sequence.camera, PipelineThreading::kWorker, 0)
                .status()
                .code(),
            StatusCode::kInvalidArgument);
  auto pipeline =
      StreamingLocalizer::create(SequenceRunParams{}, sequence.map, sequence.camera, PipelineThreading::kWorker, 1);
  ASSERT_TRUE(pipeline.ok()) << pipeline.status().message();
  const double offset = sequence.camera ? sequence.camera->time_offset : 0.0;
  const std::vector<DetectionInstant> instants = flighttest::detectionInstants(sequence);
  int odometry_full = 0, detections_full = 0;
  size_t next = 0;
  const size_t samples = sequence.odometry.samples.size();
  for (size_t k = 0; k < samples; ++k) {
    while (next < instants.size() && instants[next].t - offset <= sequence.odometry.samples[k].t) {
      const Status answer = (*pipeline)->addDetections(instants[next]);
      if (!answer.ok()) {
        EXPECT_NE(answer.message().find("inputs behind"), std::string::npos) << answer.message();
        detections_full += static_cast<int>(instants[next].size());
      }
      ++next;
    }
    const Status answer = (*pipeline)->addOdometry(flighttest::odometryInput(sequence, k)).status();
    if (!answer.ok()) {
      EXPECT_NE(answer.message().find("inputs behind"), std::string::npos) << answer.message();
      ++odometry_full;
    }
  }
  auto results = (*pipeline)->finish();
  ASSERT_TRUE(results.ok()) << results.status().message();
  RecordProperty("odometry_refused", odometry_full);
  RecordProperty("detections_refused", detections_full);
  EXPECT_GT(odometry_full + detections_full, 0);
  EXPECT_EQ(results->pipeline_counters.odometry_queue_full, odometry_full);
  EXPECT_EQ(results->pipeline_counters.detections_queue_full, detections_full);
  EXPECT_EQ((*pipeline)->snapshot().samples, static_cast<long>(samples));
  EXPECT_EQ(results->localizer_counters.odometry_accepted + results->localizer_counters.odometry_rejected,
            static_cast<int>(samples));
}

}  // namespace
}  // namespace dualgraph
