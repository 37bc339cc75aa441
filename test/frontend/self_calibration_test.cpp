// SPDX-License-Identifier: MIT
// Self-calibration (runSequenceSelfCalibrating): the camera's clock offset and mount calibrated on the flight so
// far, then used for the rest of the run; causal; and every case where it cannot be done says why.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "dualgraph/frontend/replay/self_calibration.h"
#include "dualgraph/frontend/evaluation/run_metrics.h"
#include "dualgraph/frontend/pipeline/self_calibrator.h"
#include "test/frontend/calibration_fixtures.h"

namespace dualgraph {
namespace {

double ateOf(const Sequence& sequence, const SequenceRunResult& run) {
  auto metrics = computeRunMetrics(sequence, run);
  EXPECT_TRUE(metrics.ok());
  return metrics.ok() ? metrics->estimate.ate_m : 0.0;
}

/// RMS distance [m] between the run's map poses from `from` [s] on and the truth (both in the map frame).
double rmsErrorFrom(const Sequence& sequence, const SequenceRunResult& run, double from) {
  const std::vector<OdometrySample>& truth = sequence.ground_truth->samples;
  double sum = 0.0;
  int n = 0;
  for (const CorrectedPose& pose : run.estimate) {
    if (pose.t < from || pose.state == TrackingState::kInitialising) continue;
    const auto at = std::lower_bound(truth.begin(), truth.end(), pose.t,
                                     [](const OdometrySample& sample, double t) { return sample.t < t; });
    if (at == truth.end()) continue;
    sum += (pose.world_T_body.translation() - at->odom_T_body.translation()).squaredNorm();
    ++n;
  }
  EXPECT_GT(n, 0);
  return n > 0 ? std::sqrt(sum / n) : 0.0;
}

// Realistic flights (1.5° mount error in camera.yaml, camera stamps 15 ms late, not told), 5 laps (≈ 30-40 s),
// calibrated on their first 12 s: the offset and the mount come back, and the rest of the flight is better for it
// (after the switch, over both tracks: one flight's run is too chaotic a figure to compare alone).
TEST(SelfCalibration, RecoversOffsetAndMountFromTheFlightSoFarAndImprovesTheRest) {
  double self_after = 0.0, plain_after = 0.0;
  for (const char* track : {"ratm_ellipse.yaml", "ratm_lemniscate.yaml"}) {
    const Sequence sequence = caltest::realisticFlight(track, 2, 5, 0.015);
    SequenceRunParams params;
    params.self_calibration_after_s = 12.0;
    SelfCalibrationReport report;
    auto run = runSequenceSelfCalibrating(sequence, params, {}, &report);
    ASSERT_TRUE(run.ok()) << run.status().toString();
    ASSERT_TRUE(report.applied) << track << ": " << report.why_not;
    EXPECT_TRUE(report.why_not.empty());
    EXPECT_EQ(report.at_s, sequence.odometry.samples.front().t + 12.0);
    ASSERT_TRUE(run->camera_switched_at.has_value());
    EXPECT_EQ(*run->camera_switched_at, report.applied_at_s);
    // The first 100 Hz sample at or after t_c + the budget (the calibration ran beside the pipeline meanwhile).
    EXPECT_GE(report.applied_at_s, report.at_s + params.self_calibration_budget_s);
    EXPECT_LT(report.applied_at_s, report.at_s + params.self_calibration_budget_s + 0.011);
    EXPECT_EQ(report.time_offset_before, 0.0);
    EXPECT_NEAR(report.time_offset_after, 0.015, 0.002) << track;
    EXPECT_NEAR(report.mount_change_deg, 1.5, 0.3) << track;
    auto plain = runSequence(sequence, caltest::uncalibrated());
    ASSERT_TRUE(plain.ok());
    const double self_ate = ateOf(sequence, *run), plain_ate = ateOf(sequence, *plain);
    const double self_rms = rmsErrorFrom(sequence, *run, report.at_s), plain_rms = rmsErrorFrom(sequence, *plain, report.at_s);
    self_after += self_rms;
    plain_after += plain_rms;
    std::printf("[ measured ] %s seed 2, 5 laps: offset %.2f ms (1 sigma %.2f), mount %.2f deg, ATE %.3f m (%.3f m "
                "uncalibrated), RMS error after the switch %.3f m (%.3f m)\n", track, 1e3 * report.time_offset_after,
                1e3 * report.time_offset_sigma, report.mount_change_deg, self_ate, plain_ate, self_rms, plain_rms);
  }
  EXPECT_LT(self_after, 0.9 * plain_after);
}

// A flight whose detector sees few gates (one image in six here: 156 corner detections while tracking) cannot carry the
// whole calibration (SelfCalibrator::kMinCorners) for a long time, or ever: its clock offset, which shows in every
// moving image, is calibrated alone first, the mount held as given, and the rest of the run uses it. Before, such a
// flight kept a 30 ms offset until 200 corner detections were in.
TEST(SelfCalibration, OnFewCornersTheClockOffsetAloneIsCalibratedFirst) {
  Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 3, 0.030);
  std::vector<CornerDetection> thinned;
  for (size_t k = 0; k < sequence.corners.size(); k += 6) thinned.push_back(sequence.corners[k]);
  sequence.corners = thinned;
  SequenceRunParams params;
  params.self_calibration_after_s = 6.0;
  SelfCalibrationReport report;
  auto run = runSequenceSelfCalibrating(sequence, params, {}, &report);
  ASSERT_TRUE(run.ok()) << run.status().toString();
  const double t_c = sequence.odometry.samples.front().t + 6.0;
  ASSERT_TRUE(report.clock_offset_first_applied) << report.why_not;
  EXPECT_GE(report.clock_offset_first_at_s, t_c);
  EXPECT_EQ(report.attempts, 0);  // the whole calibration never had its corners: before, nothing was calibrated
  EXPECT_NEAR(report.clock_offset_first_s, 0.030, 0.004);
  ASSERT_TRUE(run->camera_switched_at.has_value());
  EXPECT_EQ(report.applied_at_s, *run->camera_switched_at);
  EXPECT_TRUE(report.applied);
  EXPECT_TRUE(report.time_offset_applied);
  std::printf("[ measured ] one image in six, 3 laps: clock offset alone at t_c + %.2f s: %.2f ms; then %s (%d "
              "attempts): %s\n", report.clock_offset_first_at_s - t_c, 1e3 * report.clock_offset_first_s,
              report.parts.c_str(), report.attempts, report.why_not.c_str());
}

// A VIO whose attitude drifts (roll 0 → 6° over the flight) looks like a mount error to the whole calibration, a
// different one in each half: it refuses the mount and keeps its offset, which the mount protected — held at its
// value instead, the roll goes into the offset (its halves then 32 and 37 ms): no step-down when a part holds.
TEST(SelfCalibration, AMountTheHalvesDoNotShowIsRefusedAndTheWholesOffsetKept) {
  Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 2, 4, 0.030);
  sequence.camera = caltest::trueCamera();  // the mount as built: what looks like one is the VIO's attitude
  const double t0 = sequence.odometry.samples.front().t, span = sequence.odometry.samples.back().t - t0;
  for (OdometrySample& sample : sequence.odometry.samples) {
    const double roll = 6.0 * M_PI / 180.0 * (sample.t - t0) / span;
    sample.odom_T_body.linear() = sample.odom_T_body.linear() * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).matrix();
  }
  SequenceRunParams params;
  params.self_calibration_after_s = 16.0;
  SelfCalibrationReport report;
  auto run = runSequenceSelfCalibrating(sequence, params, {}, &report);
  ASSERT_TRUE(run.ok()) << run.status().toString();
  ASSERT_EQ(report.attempts, 1) << report.why_not;
  EXPECT_EQ(report.parts, "clock offset and mount");
  EXPECT_TRUE(report.time_offset_applied);
  EXPECT_FALSE(report.mount_applied);
  EXPECT_NEAR(report.time_offset_after, 0.030, 0.002);
  EXPECT_NE(report.why_not_mount.find("a VIO attitude error, not the mount"), std::string::npos) << report.why_not_mount;
}

// Nothing after t_c is used before it: up to the switch the run is the uncalibrated one, pose for pose.
TEST(SelfCalibration, IsCausalTheRunBeforeTheSwitchIsTheUncalibratedRun) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 4, 0.015);
  SequenceRunParams params;
  params.self_calibration_after_s = 10.0;
  SelfCalibrationReport report;
  auto run = runSequenceSelfCalibrating(sequence, params, {}, &report);
  auto plain = runSequence(sequence, caltest::uncalibrated());
  ASSERT_TRUE(run.ok() && plain.ok());
  ASSERT_TRUE(report.applied) << report.why_not;
  ASSERT_EQ(run->estimate.size(), plain->estimate.size());
  size_t before = 0, differ_after = 0;
  for (size_t k = 0; k < run->estimate.size(); ++k) {
    const CorrectedPose &a = run->estimate[k], &b = plain->estimate[k];
    ASSERT_EQ(a.t, b.t);
    if (a.t < *run->camera_switched_at) {
      ++before;
      ASSERT_TRUE(a.world_T_body.matrix() == b.world_T_body.matrix() && a.state == b.state) << "t = " << a.t;
    } else if (!(a.world_T_body.matrix() == b.world_T_body.matrix())) {
      ++differ_after;
    }
  }
  EXPECT_GT(before, 900u);
  EXPECT_GT(differ_after, 0u);  // and after it the camera really changed the run
}

// The calibration runs beside the pipeline (frontend.self_calibration_budget_s): it is the calibration the
// pipeline's thread makes (budget 0), its camera used one budget later; up to then the runs are one, pose for pose;
// and two runs give the same poses to the bit, however the threads were scheduled.
TEST(SelfCalibration, BesideThePipelineItIsTheSameCalibrationUsedOneBudgetLaterAndRepeatable) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 4, 0.015);
  SequenceRunParams at_once;
  at_once.self_calibration_after_s = 10.0;
  at_once.self_calibration_budget_s = 0.0;
  SequenceRunParams beside = at_once;
  beside.self_calibration_budget_s = 1.0;
  SelfCalibrationReport now, later, again;
  auto run_now = runSequenceSelfCalibrating(sequence, at_once, {}, &now);
  auto run_later = runSequenceSelfCalibrating(sequence, beside, {}, &later);
  auto run_again = runSequenceSelfCalibrating(sequence, beside, {}, &again);
  ASSERT_TRUE(run_now.ok() && run_later.ok() && run_again.ok());
  ASSERT_TRUE(now.applied && later.applied) << now.why_not << " / " << later.why_not;
  EXPECT_EQ(later.at_s, now.at_s);
  EXPECT_EQ(later.time_offset_after, now.time_offset_after);
  EXPECT_EQ(later.mount_change_deg, now.mount_change_deg);
  EXPECT_EQ(now.applied_at_s, *run_now->camera_switched_at);
  EXPECT_LT(now.applied_at_s, now.at_s + 0.011);
  EXPECT_EQ(later.applied_at_s, *run_later->camera_switched_at);
  EXPECT_GE(later.applied_at_s, later.at_s + 1.0);
  EXPECT_LT(later.applied_at_s, later.at_s + 1.011);
  ASSERT_EQ(run_later->estimate.size(), run_now->estimate.size());
  ASSERT_EQ(run_again->estimate.size(), run_later->estimate.size());
  size_t same_before = 0;
  for (size_t k = 0; k < run_later->estimate.size(); ++k) {
    const CorrectedPose &a = run_later->estimate[k], &b = run_again->estimate[k], &c = run_now->estimate[k];
    ASSERT_TRUE(a.world_T_body.matrix() == b.world_T_body.matrix() && a.state == b.state) << "t = " << a.t;
    if (a.t < now.applied_at_s) {
      ASSERT_TRUE(a.world_T_body.matrix() == c.world_T_body.matrix()) << "t = " << a.t;
      ++same_before;
    }
  }
  EXPECT_GT(same_before, 900u);
}

TEST(SelfCalibration, WhereItCannotBeDoneTheRunIsThePlainOneAndSaysWhy) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 1, 0.015);  // ≈ 8 s
  auto plain = runSequence(sequence, caltest::uncalibrated());
  ASSERT_TRUE(plain.ok());
  struct Case {
    std::string name;
    Sequence sequence;
    double after_s;
    std::string says;
    bool attempted;
  };
  Sequence no_camera = sequence;
  no_camera.camera.reset();
  Sequence no_detections_early = sequence;  // 3 corners: never enough to calibrate on (SelfCalibrator::kMinCorners)
  no_detections_early.corners.erase(no_detections_early.corners.begin(), no_detections_early.corners.end() - 3);
  const Case cases[] = {
      {"off", sequence, 0.0, "off", false},
      {"no camera", no_camera, 3.0, "camera", false},
      {"too short", sequence, 60.0, "ends before", false},
      {"nothing to calibrate with", no_detections_early, 5.0, "200 needed", false},
  };
  for (const Case& c : cases) {
    SequenceRunParams params;
    params.self_calibration_after_s = c.after_s;
    SelfCalibrationReport report;
    auto run = runSequenceSelfCalibrating(c.sequence, params, {}, &report);
    ASSERT_TRUE(run.ok()) << c.name << ": " << run.status().toString();
    EXPECT_FALSE(report.applied) << c.name;
    EXPECT_EQ(report.attempted, c.attempted) << c.name;
    EXPECT_NE(report.why_not.find(c.says), std::string::npos) << c.name << ": " << report.why_not;
    EXPECT_FALSE(run->camera_switched_at.has_value()) << c.name;
  }
  SequenceRunParams mapping;  // a mapping run has no map to calibrate against
  mapping.localizer.mapping = true;
  mapping.self_calibration_after_s = 3.0;
  SelfCalibrationReport mapping_report;
  auto mapped = runSequenceSelfCalibrating(sequence, mapping, {}, &mapping_report);
  ASSERT_TRUE(mapped.ok()) << mapped.status().toString();
  EXPECT_FALSE(mapping_report.attempted);
  EXPECT_NE(mapping_report.why_not.find("mapping"), std::string::npos) << mapping_report.why_not;
  // The off case is runSequence itself.
  SelfCalibrationReport report;
  auto off = runSequenceSelfCalibrating(sequence, caltest::uncalibrated(), {}, &report);
  ASSERT_TRUE(off.ok());
  ASSERT_EQ(off->estimate.size(), plain->estimate.size());
  EXPECT_TRUE(off->estimate.back().world_T_body.matrix() == plain->estimate.back().world_T_body.matrix());
}

TEST(SelfCalibration, AnInvalidCameraSwitchIsRefusedNamingTheField) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 1, 0.0);
  SequenceRunParams params;
  params.camera_switch = SequenceRunParams::CameraSwitch{2.0, *sequence.camera};
  params.camera_switch->camera.width = 0;
  auto run = runSequence(sequence, params);
  ASSERT_FALSE(run.ok());
  EXPECT_NE(run.status().message().find("width"), std::string::npos) << run.status().message();
  auto parsed = parseRunConfig("frontend:\n  self_calibration_after_s: -5\n", "run.yaml");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("run.yaml:2: field 'frontend.self_calibration_after_s'"), std::string::npos)
      << parsed.status().message();
  auto given = parseRunConfig("frontend:\n  self_calibration_after_s: 15\n", "run.yaml");
  ASSERT_TRUE(given.ok());
  EXPECT_EQ(given->self_calibration_after_s, 15.0);
}

}  // namespace
}  // namespace dualgraph

namespace dualgraph {
namespace {

/// A SelfCalibrator fed a flight's odometry, the localizer `tracking` from `lock` [s] on (after the sample at or
/// after it), and its corners: all of them before the odometry (arriving far ahead of it), or each just before the
/// first sample at or after its stamp (`interleaved`). Due at 5 s.
// A calibration started at t and its answer taken there (budget 0: on this thread).
std::optional<CameraModel> calibrateAt(SelfCalibrator& calibrator, double t, const CameraModel& camera,
                                       const Track& track, const std::vector<CorrectedPose>& keyframes) {
  calibrator.start(t, camera, track, keyframes);
  EXPECT_TRUE(calibrator.answerDue(t));
  return calibrator.takeAnswer(t);
}

SelfCalibrator fedCalibrator(const Sequence& sequence, bool tracking, double lock = -1e9, bool interleaved = false,
                             const CalibrationParams& calibration = {}, double budget_s = 0.0) {
  SelfCalibrator calibrator(5.0, budget_s, 0.0, "", calibration);
  size_t next = 0;
  if (!interleaved) calibrator.addCorners(sequence.corners, 0.0);
  for (const OdometrySample& sample : sequence.odometry.samples) {
    std::vector<CornerDetection> arrived;
    while (interleaved && next < sequence.corners.size() && sequence.corners[next].t <= sample.t) {
      arrived.push_back(sequence.corners[next++]);
    }
    calibrator.addCorners(arrived, 0.0);
    calibrator.addOdometry(sample);
    calibrator.noteState(sample.t, tracking && sample.t >= lock);
  }
  return calibrator;
}

// Corners stamped before the lock (or while lost) have no trajectory to be matched against: they are not kept,
// so they neither count towards kMinCorners nor enter the calibration (a flight that locked at 24.5 s calibrated on
// its first keyframe alone and found 6.3 degrees of mount error, the halves 12 degrees apart).
TEST(SelfCalibrator, KeepsOnlyTheCornersStampedWhileTracking) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 2, 0.015);
  ASSERT_GT(sequence.corners.size(), SelfCalibrator::kMinCorners);
  const double late = sequence.odometry.samples.front().t + 6.0;
  EXPECT_FALSE(fedCalibrator(sequence, false).due(late, true));
  EXPECT_EQ(fedCalibrator(sequence, false).cornersKept(), 0u);
  EXPECT_TRUE(fedCalibrator(sequence, true).due(late, true));
  EXPECT_EQ(fedCalibrator(sequence, true).cornersKept(), sequence.corners.size() -
                                                            static_cast<size_t>(std::count_if(
                                                                sequence.corners.begin(), sequence.corners.end(),
                                                                [&](const CornerDetection& c) {
                                                                  return c.t <= sequence.odometry.samples.front().t;
                                                                })));
}

// Which corners count is a matter of their stamps, not of when they arrive: a detector whose output reaches the
// pipeline a quarter of a second ahead of the VIO (`dualgraph live`) keeps the same corners as a replay that hands
// each one over at its time (`dualgraph run`), so both calibrate the same camera. Before, the state at arrival
// decided: corners stamped just after the lock but arriving before it were dropped.
TEST(SelfCalibrator, TheCornersKeptDoNotDependOnHowEarlyTheyArrive) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 2, 0.015);
  const double lock = sequence.odometry.samples.front().t + 2.0;
  const SelfCalibrator early = fedCalibrator(sequence, true, lock, false);
  const SelfCalibrator on_time = fedCalibrator(sequence, true, lock, true);
  const size_t stamped_after_lock = static_cast<size_t>(std::count_if(
      sequence.corners.begin(), sequence.corners.end(), [&](const CornerDetection& c) { return c.t > lock; }));
  EXPECT_GT(stamped_after_lock, SelfCalibrator::kMinCorners);
  EXPECT_EQ(early.cornersKept(), on_time.cornersKept());
  // Every corner stamped after the sample that locked (the sample at or after `lock`), none before it.
  const OdometrySample& locking = *std::find_if(sequence.odometry.samples.begin(), sequence.odometry.samples.end(),
                                                [&](const OdometrySample& s) { return s.t >= lock; });
  const size_t after_locking = static_cast<size_t>(std::count_if(
      sequence.corners.begin(), sequence.corners.end(), [&](const CornerDetection& c) { return c.t > locking.t; }));
  EXPECT_EQ(on_time.cornersKept(), after_locking);
}

// A calibration that finds too little to go on (here the map is 100 m off, so no corner matches a gate) is tried
// again after_s later on the longer flight so far, three times in all, each saying so; then the camera is kept.
TEST(SelfCalibrator, TriesAgainWhenTheFlightSoFarCouldNotCarryIt) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 2, 0.015);
  Track far = sequence.map;
  for (TrackGate& gate : far.gates) gate.position.x() += 100.0;
  SelfCalibrator calibrator = fedCalibrator(sequence, true);
  const double t0 = sequence.odometry.samples.front().t;
  for (int attempt = 1; attempt <= SelfCalibrator::kMaxAttempts; ++attempt) {
    SCOPED_TRACE(::testing::Message() << "attempt " << attempt);
    const double t = t0 + 5.0 * attempt;
    ASSERT_TRUE(calibrator.due(t, true));
    EXPECT_FALSE(calibrateAt(calibrator, t, caltest::trueCamera(), far, {}).has_value());
    const SelfCalibrationReport& report = calibrator.report();
    EXPECT_EQ(report.attempts, attempt);
    EXPECT_TRUE(report.evidence_missing);
    EXPECT_FALSE(report.applied);
    EXPECT_NE(report.why_not.find("the calibration failed"), std::string::npos) << report.why_not;
    if (attempt < SelfCalibrator::kMaxAttempts) {
      EXPECT_TRUE(calibrator.pending());
      EXPECT_EQ(report.at_s, t + 5.0);
      EXPECT_NE(report.why_not.find("attempt " + std::to_string(attempt) + " of 3"), std::string::npos) << report.why_not;
      EXPECT_FALSE(calibrator.due(t + 4.9, true));
    } else {
      EXPECT_FALSE(calibrator.pending());
      EXPECT_EQ(report.at_s, t);
    }
  }
  // A retry still due when the flight ends: the last attempt's reasons stand, and the report says it ended first.
  SelfCalibrator ended = fedCalibrator(sequence, true);
  ASSERT_FALSE(calibrateAt(ended, t0 + 5.0, caltest::trueCamera(), far, {}).has_value());
  ASSERT_TRUE(ended.pending());
  ended.finish(t0 + 7.0);
  EXPECT_FALSE(ended.pending());
  EXPECT_EQ(ended.report().at_s, t0 + 5.0);
  EXPECT_NE(ended.report().why_not.find("the flight ended before the next attempt"), std::string::npos);
}

/// The run's keyframes as a perfect one would have them: the truth every 100 samples.
std::vector<CorrectedPose> truthKeyframes(const Sequence& sequence) {
  std::vector<CorrectedPose> keyframes;
  for (size_t k = 0; k < sequence.ground_truth->samples.size(); k += 100) {
    keyframes.push_back(CorrectedPose{sequence.ground_truth->samples[k].t, sequence.ground_truth->samples[k].odom_T_body,
                                      TrackingState::kTracking, std::nullopt});
  }
  return keyframes;
}

// A whole calibration that cannot be carried (here it never converges: its mount is asked to stop moving entirely)
// steps down: the clock offset alone, the mount held as given, is calibrated and applied, and the report says which
// part and why the other was held. Before, nothing was applied. With the usual tolerance the whole converges.
TEST(SelfCalibrator, AWholeCalibrationThatCannotBeCarriedStepsDownToTheClockOffsetAlone) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 2, 0.030);
  const std::vector<CorrectedPose> keyframes = truthKeyframes(sequence);
  const double t = sequence.odometry.samples.back().t;
  CalibrationParams strict;
  strict.converged_rotation_deg = 0.0;  // a rotation step is never below 0
  strict.converged_sigma_fraction = 0.0;
  SelfCalibrator calibrator = fedCalibrator(sequence, true, -1e9, false, strict);
  ASSERT_TRUE(calibrator.due(t, true));
  const std::optional<CameraModel> camera = calibrateAt(calibrator, t, caltest::trueCamera(), sequence.map, keyframes);
  const SelfCalibrationReport& report = calibrator.report();
  ASSERT_TRUE(camera.has_value()) << report.why_not;
  EXPECT_EQ(report.parts, "clock offset alone");
  EXPECT_TRUE(report.time_offset_applied);
  EXPECT_FALSE(report.mount_applied);
  EXPECT_NEAR(camera->time_offset, 0.030, 0.002);
  EXPECT_TRUE(camera->body_T_camera.linear() == caltest::trueCamera().body_T_camera.linear());
  EXPECT_NE(report.why_not_mount.find("held: clock offset and mount: the calibration did not converge"), std::string::npos)
      << report.why_not_mount;
  SelfCalibrator usual = fedCalibrator(sequence, true);
  ASSERT_TRUE(calibrateAt(usual, t, caltest::trueCamera(), sequence.map, keyframes).has_value()) << usual.report().why_not;
  EXPECT_EQ(usual.report().parts, "clock offset and mount");
}

// With a budget, a calibration runs on its own thread from copies of its inputs: its answer is due one budget after
// it started and not before, no other starts meanwhile, and it is the answer the caller's thread gives at once.
TEST(SelfCalibrator, ABudgetedCalibrationGivesTheAnswerOfOneAtOnceABudgetLater) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 2, 0.030);
  const std::vector<CorrectedPose> keyframes = truthKeyframes(sequence);
  const double t = sequence.odometry.samples.back().t;
  SelfCalibrator at_once = fedCalibrator(sequence, true);
  const std::optional<CameraModel> expected = calibrateAt(at_once, t, caltest::trueCamera(), sequence.map, keyframes);
  ASSERT_TRUE(expected.has_value()) << at_once.report().why_not;
  EXPECT_EQ(at_once.report().applied_at_s, t);
  SelfCalibrator beside = fedCalibrator(sequence, true, -1e9, false, {}, 1.0);
  ASSERT_TRUE(beside.due(t, true));
  beside.start(t, caltest::trueCamera(), sequence.map, keyframes);
  EXPECT_FALSE(beside.due(t, true));  // one at a time
  EXPECT_FALSE(beside.answerDue(t));
  EXPECT_FALSE(beside.answerDue(t + 0.99));
  ASSERT_TRUE(beside.answerDue(t + 1.0));
  const std::optional<CameraModel> camera = beside.takeAnswer(t + 1.0);
  ASSERT_TRUE(camera.has_value()) << beside.report().why_not;
  EXPECT_EQ(camera->time_offset, expected->time_offset);
  EXPECT_TRUE(camera->body_T_camera.matrix() == expected->body_T_camera.matrix());
  const SelfCalibrationReport &a = at_once.report(), &b = beside.report();
  EXPECT_EQ(b.at_s, t);
  EXPECT_EQ(b.applied_at_s, t + 1.0);
  EXPECT_EQ(b.parts, a.parts);
  EXPECT_EQ(b.mount_change_deg, a.mount_change_deg);
  EXPECT_EQ(b.iterations, a.iterations);
  EXPECT_EQ(b.attempts, 1);
  EXPECT_TRUE(b.applied);
  EXPECT_FALSE(beside.pending());
}

// A flight that ends while its calibration runs: the figures are reported, and that its camera was never used.
TEST(SelfCalibrator, AFlightEndingBeforeTheAnswerIsDueSaysItsCameraWasNeverUsed) {
  const Sequence sequence = caltest::realisticFlight("ratm_ellipse.yaml", 1, 2, 0.030);
  const double t = sequence.odometry.samples.back().t;
  SelfCalibrator beside = fedCalibrator(sequence, true, -1e9, false, {}, 1.0);
  ASSERT_TRUE(beside.due(t, true));
  beside.start(t, caltest::trueCamera(), sequence.map, truthKeyframes(sequence));
  beside.finish(t + 0.5);
  const SelfCalibrationReport& report = beside.report();
  EXPECT_FALSE(beside.pending());
  EXPECT_TRUE(report.attempted);
  EXPECT_FALSE(report.applied);
  EXPECT_FALSE(report.time_offset_applied);
  EXPECT_FALSE(report.mount_applied);
  EXPECT_EQ(report.applied_at_s, 0.0);
  EXPECT_NEAR(report.time_offset_after, 0.030, 0.002);  // what it found stands
  EXPECT_NE(report.why_not.find("the flight ended before its answer was due"), std::string::npos) << report.why_not;
}

}  // namespace
}  // namespace dualgraph
