// SPDX-License-Identifier: MIT
// StreamingLocalizer when the odometry clock goes back and stays there (a looped bag, a VIO restarted on a clock
// from 0, a glitched first sample): the pipeline restarts as new once the clock behind ran 1 s
// (OdometryClockGuard::kRestartSpanS), in both threading modes, and the flight after it is the flight a new pipeline
// would give; a borrowed pipeline cannot restart and says so.
#include <gtest/gtest.h>

#include "dualgraph/core/stamp_tolerance.h"
#include "dualgraph/frontend/pipeline/streaming_localizer.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/replay/sequence_run.h"
#include "test/frontend/simulated_flight.h"
#include "test/frontend/streaming_flight.h"
#include "test/testing/shared_data.h"

namespace dualgraph {
namespace clock_restart_test {

struct Fed {
  std::vector<Result<PoseUpdate>> answers;  ///< one per odometry sample of `flight`, in order
  PipelineResults results;
  long samples = 0;  ///< the snapshot's count at the end
};

// `before` (its own odometry and detections, in time order) then `flight`, each detection instant just before the
// first odometry sample that covers it, from one thread.
void feed(StreamingLocalizer& pipeline, const Sequence& sequence, std::vector<Result<PoseUpdate>>* answers) {
  const std::vector<DetectionInstant> instants = flighttest::detectionInstants(sequence);
  const double offset = sequence.camera ? sequence.camera->time_offset : 0.0;
  size_t next = 0;
  for (size_t k = 0; k < sequence.odometry.samples.size(); ++k) {
    const double t = sequence.odometry.samples[k].t;
    while (next < instants.size() && instants[next].t - offset <= t) (void)pipeline.addDetections(instants[next++]);
    Result<PoseUpdate> answer = pipeline.addOdometry(flighttest::odometryInput(sequence, k));
    if (answers) answers->push_back(std::move(answer));
  }
}

Fed run(const std::vector<const Sequence*>& parts, PipelineThreading threading) {
  Fed out;
  auto pipeline = StreamingLocalizer::create(SequenceRunParams{}, parts.back()->map, parts.back()->camera, threading);
  EXPECT_TRUE(pipeline.ok()) << pipeline.status().message();
  if (!pipeline.ok()) return out;
  for (const Sequence* part : parts) feed(**pipeline, *part, part == parts.back() ? &out.answers : nullptr);
  Result<PipelineResults> results = (*pipeline)->finish();
  EXPECT_TRUE(results.ok()) << results.status().message();
  if (results.ok()) out.results = std::move(results).value();
  out.samples = (*pipeline)->snapshot().samples;
  return out;
}

// `detections` up to `end` [s], `shift` seconds later.
template <typename Detection>
std::vector<Detection> shiftedUpTo(const std::vector<Detection>& detections, double end, double shift) {
  std::vector<Detection> out;
  for (Detection detection : detections) {
    if (detection.t > end) continue;
    detection.t += shift;
    out.push_back(detection);
  }
  return out;
}

// The first `samples` odometry samples of `flight` and the detections up to the last of them, `shift` seconds later.
Sequence shiftedPrefix(const Sequence& flight, size_t samples, double shift) {
  Sequence out = flight;
  out.odometry.samples.resize(samples);
  if (!out.odometry.absolute_covariances.empty()) out.odometry.absolute_covariances.resize(samples);
  for (OdometrySample& sample : out.odometry.samples) sample.t += shift;
  const double end = flight.odometry.samples[samples - 1].t;
  out.corners = shiftedUpTo(flight.corners, end, shift);
  out.pose_detections = shiftedUpTo(flight.pose_detections, end, shift);
  return out;
}

// `flight` without its first `samples` odometry samples: what a new pipeline started at the restart sees.
Sequence withoutFirst(const Sequence& flight, size_t samples) {
  Sequence out = flight;
  out.odometry.samples.erase(out.odometry.samples.begin(), out.odometry.samples.begin() + samples);
  if (!out.odometry.absolute_covariances.empty()) {
    out.odometry.absolute_covariances.erase(out.odometry.absolute_covariances.begin(),
                                            out.odometry.absolute_covariances.begin() + samples);
  }
  return out;
}

void expectSameKeyframes(const PipelineResults& a, const PipelineResults& b) {
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  ASSERT_FALSE(a.keyframes.empty());
  for (size_t k = 0; k < a.keyframes.size(); ++k) {
    EXPECT_EQ(a.keyframes[k].t, b.keyframes[k].t) << k;
    EXPECT_TRUE(a.keyframes[k].world_T_body.isApprox(b.keyframes[k].world_T_body, 1e-12)) << k;
  }
}

// The index of the first sample of `flight` at least kRestartSpanS after its first: where a restart onto it happens.
size_t restartIndex(const Sequence& flight) {
  const std::vector<OdometrySample>& samples = flight.odometry.samples;
  size_t k = 0;
  while (k < samples.size() && !elapsedAtLeast(samples[k].t, samples[0].t, OdometryClockGuard::kRestartSpanS)) ++k;
  return k;
}

class StreamingClockRestart : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    flight_ = new Sequence(flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 3, 2));
    restart_at_ = restartIndex(*flight_);
    rest_ = new Sequence(withoutFirst(*flight_, restart_at_));
    fresh_ = new Fed(run({rest_}, PipelineThreading::kCallerThread));
  }
  static void TearDownTestSuite() {
    delete flight_;
    delete rest_;
    delete fresh_;
  }
  static Sequence* flight_;
  static size_t restart_at_;  ///< the sample fed after the flight's first where a restart happens
  static Sequence* rest_;     ///< the flight from that sample on
  static Fed* fresh_;         ///< a new pipeline fed rest_
};
size_t StreamingClockRestart::restart_at_ = 0;
Sequence* StreamingClockRestart::flight_ = nullptr;
Sequence* StreamingClockRestart::rest_ = nullptr;
Fed* StreamingClockRestart::fresh_ = nullptr;

// A looped bag: 600 samples of a flight 500 s later, one detection stamped beyond the odometry, then the flight from
// its start. Before: every sample of the second pass refused as not after the first pass's, the snapshot frozen at
// its last pose. Now its first second is held, the sample after it restarts the pipeline, and what follows is a new
// pipeline's flight to the last bit; what the first pass refused stays counted.
TEST_F(StreamingClockRestart, ALoopedBagRestartsThePipelineInBothModes) {
  const Sequence first_pass = shiftedPrefix(*flight_, 600, 500.0);
  ASSERT_GT(first_pass.odometry.samples.back().t, flight_->odometry.samples.back().t + 10.0);
  for (PipelineThreading threading : {PipelineThreading::kCallerThread, PipelineThreading::kWorker}) {
    SCOPED_TRACE(threading == PipelineThreading::kWorker ? "worker" : "caller thread");
    auto pipeline = StreamingLocalizer::create(SequenceRunParams{}, flight_->map, flight_->camera, threading);
    ASSERT_TRUE(pipeline.ok()) << pipeline.status().message();
    feed(**pipeline, first_pass, nullptr);
    DetectionInstant stray = flighttest::detectionInstants(first_pass).back();
    stray.t += 100.0;  // beyond the newest odometry: refused by the first pass's core, counted there
    for (CornerDetection& detection : stray.corners) detection.t = stray.t;
    const int stray_detections = static_cast<int>(stray.size());
    ASSERT_GT(stray_detections, 0);
    (void)(*pipeline)->addDetections(stray);
    std::vector<Result<PoseUpdate>> answers;
    feed(**pipeline, *flight_, &answers);
    Result<PipelineResults> results = (*pipeline)->finish();
    ASSERT_TRUE(results.ok()) << results.status().message();

    ASSERT_EQ(answers.size(), flight_->odometry.samples.size());
    ASSERT_GE(restart_at_, 3u);
    for (size_t k = 0; k < restart_at_; ++k) {
      EXPECT_EQ(answers[k].status().code(), StatusCode::kInvalidArgument) << k;
      EXPECT_NE(answers[k].status().message().find("clock restart"), std::string::npos) << answers[k].status().message();
    }
    for (size_t k = restart_at_; k < answers.size(); ++k) {
      ASSERT_TRUE(answers[k].ok()) << k << ": " << answers[k].status().message();
      EXPECT_EQ(answers[k]->report.clock_restarted, k == restart_at_) << k;  // both modes: told with that sample
    }
    const PipelineCounters& c = results->pipeline_counters;
    EXPECT_EQ(c.odometry_clock_restarts, 1);
    EXPECT_EQ(c.odometry_held_at_clock_jump, static_cast<int>(restart_at_));
    EXPECT_EQ(c.odometry_clock_jumps, 0);
    EXPECT_EQ(c.odometry_not_after_previous, 0);
    EXPECT_EQ(c.detections_too_far_ahead, stray_detections);  // the first pass's core's count, carried
    EXPECT_EQ(results->localizer_counters.odometry_rejected, static_cast<int>(restart_at_));
    expectSameKeyframes(*results, fresh_->results);
    EXPECT_EQ((*pipeline)->snapshot().samples, static_cast<long>(first_pass.odometry.samples.size() + answers.size()));
    EXPECT_EQ((*pipeline)->snapshot().t, flight_->odometry.samples.back().t);
  }
}

// A looped bag whose first pass ran long enough for the self-calibration (default.yaml's): the camera it calibrated
// (clock offset and mount) goes on after the restart. Before, the new pipeline went back to the camera file's and
// flew on it until its own self-calibration, as long again.
TEST(StreamingClockRestartCamera, TheSelfCalibratedCameraGoesOnAfterARestart) {
  const Sequence flight = flighttest::simulatedFlight("ratm_ellipse.yaml", "realistic", 1, 4);
  ASSERT_TRUE(flight.camera.has_value());
  const size_t restart_at = restartIndex(flight);
  const auto config = loadRunConfig(testing::sourcePath("data/config/default.yaml"));  // self-calibration on
  ASSERT_TRUE(config.ok()) << config.status().message();
  auto pipeline = StreamingLocalizer::create(*config, flight.map, flight.camera);
  ASSERT_TRUE(pipeline.ok()) << pipeline.status().message();
  feed(**pipeline, shiftedPrefix(flight, flight.odometry.samples.size(), 500.0), nullptr);
  const double calibrated = (*pipeline)->timeOffset();
  ASSERT_GT(std::abs(calibrated - flight.camera->time_offset), 1e-3) << "the first pass must have self-calibrated";
  std::vector<Result<PoseUpdate>> answers;
  feed(**pipeline, shiftedPrefix(flight, restart_at + 20, 0.0), &answers);
  ASSERT_TRUE(answers[restart_at].ok()) << answers[restart_at].status().message();
  EXPECT_TRUE(answers[restart_at]->report.clock_restarted);
  EXPECT_EQ((*pipeline)->timeOffset(), calibrated);
  Result<PipelineResults> results = (*pipeline)->finish();
  ASSERT_TRUE(results.ok()) << results.status().message();
  EXPECT_EQ(results->pipeline_counters.odometry_clock_restarts, 1);
}

// The very first sample stamped 10^6 s ahead: before, taken, and the whole real flight refused as not after it.
TEST_F(StreamingClockRestart, AGlitchedFirstSampleIsLeftBehind) {
  Sequence glitch = *flight_;
  glitch.odometry.samples.resize(1);
  if (!glitch.odometry.absolute_covariances.empty()) glitch.odometry.absolute_covariances.resize(1);
  glitch.odometry.samples[0].t += 1e6;
  glitch.corners.clear();
  glitch.pose_detections.clear();
  const Fed fed = run({&glitch, flight_}, PipelineThreading::kCallerThread);
  EXPECT_EQ(fed.results.pipeline_counters.odometry_clock_restarts, 1);
  EXPECT_EQ(fed.results.pipeline_counters.odometry_held_at_clock_jump, static_cast<int>(restart_at_));
  expectSameKeyframes(fed.results, fresh_->results);

  SequenceRunParams unguarded;  // the control: the guard off, the flight as it went before
  unguarded.max_odometry_jump_s = 0.0;
  auto pipeline = StreamingLocalizer::create(unguarded, flight_->map, flight_->camera);
  ASSERT_TRUE(pipeline.ok());
  feed(**pipeline, glitch, nullptr);
  feed(**pipeline, *flight_, nullptr);
  Result<PipelineResults> lost = (*pipeline)->finish();
  ASSERT_TRUE(lost.ok()) << lost.status().message();
  EXPECT_EQ(lost->pipeline_counters.odometry_not_after_previous, static_cast<int>(flight_->odometry.samples.size()));
}

// Around a Localizer its caller keeps there is nothing to restart: the sample that would restart is refused, loudly.
TEST_F(StreamingClockRestart, ABorrowedPipelineCannotRestartAndSaysSo) {
  SequenceRunParams params;
  auto map = flight_->map.gateMap();
  ASSERT_TRUE(map.ok());
  auto localizer = Localizer::create(params.localizer, *map, TrackingState::kTracking);
  ASSERT_TRUE(localizer.ok()) << localizer.status().message();
  auto frontend = GateFrontend::create(params.frontend, flight_->map, flight_->camera);
  ASSERT_TRUE(frontend.ok()) << frontend.status().message();
  auto pipeline = StreamingLocalizer::borrow(**localizer, *frontend, 0.0);
  ASSERT_TRUE(pipeline.ok());
  for (size_t k = 0; k < 10; ++k) {
    OdometryInput later = flighttest::odometryInput(*flight_, k);
    later.t += 500.0;
    ASSERT_TRUE((*pipeline)->addOdometry(later).ok()) << k;
  }
  for (size_t k = 0; k <= restart_at_ + 1; ++k) {
    const Status answer = (*pipeline)->addOdometry(flighttest::odometryInput(*flight_, k)).status();
    EXPECT_EQ(answer.code(), k == restart_at_ ? StatusCode::kFailedPrecondition : StatusCode::kInvalidArgument) << k;
    if (k == restart_at_) {
      EXPECT_NE(answer.message().find("cannot restart"), std::string::npos) << answer.message();
    }
  }
  Result<PipelineResults> results = (*pipeline)->finish();
  ASSERT_TRUE(results.ok()) << results.status().message();
  EXPECT_EQ(results->pipeline_counters.odometry_held_at_clock_jump, static_cast<int>(restart_at_) + 1);
  EXPECT_EQ(results->pipeline_counters.odometry_not_after_previous, 1);
  EXPECT_EQ(results->pipeline_counters.odometry_clock_restarts, 0);
  EXPECT_EQ(results->localizer_counters.odometry_rejected, static_cast<int>(restart_at_) + 2);
}

}  // namespace clock_restart_test
}  // namespace dualgraph
