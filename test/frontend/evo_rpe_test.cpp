// SPDX-License-Identifier: MIT
// RPE windows in frames and metres, both pairings, and their statistics, against the pairs and errors written out
// by hand (evo_reference.h) on a seeded noisy estimate paired with sparser ground truth as evo pairs them.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dualgraph/frontend/evaluation/trajectory_metrics.h"
#include "test/frontend/evo_reference.h"

namespace dualgraph {
namespace {

/// Noisy estimate at 100 Hz against ground truth at 40 Hz, paired as evo pairs them.
struct Flight {
  StampedPoses gt, est;
  TrajectoryAssociation association;
  std::vector<Eigen::Isometry3d> q, p;  ///< the paired ground-truth and estimate poses
};

Flight noisyFlight(unsigned seed) {
  std::mt19937 rng(seed);
  Flight f;
  f.gt = evo_reference::randomFlight(rng, 20.0, 0.025, 0.003, 1600, 0.0, seed);  // 40 s
  f.est = evo_reference::randomFlight(rng, 20.0, 0.01, 0.002, 4000, 0.01, seed);
  f.association = *associateAsEvo(f.gt, f.est, 0.01);
  for (const auto& [g, e] : evo_reference::associate(f.gt, f.est, 0.01).gt_est) {
    f.q.push_back(f.gt[g].second);
    f.p.push_back(f.est[e].second);
  }
  return f;
}

void expectStatistics(const ErrorStatistics& actual, const std::vector<double>& errors) {
  const evo_reference::Statistics expected = evo_reference::statistics(errors);
  const double tolerance = 1e-9 * (1.0 + expected.max);
  EXPECT_NEAR(actual.rmse, expected.rmse, tolerance);
  EXPECT_NEAR(actual.mean, expected.mean, tolerance);
  EXPECT_NEAR(actual.median, expected.median, tolerance);
  EXPECT_NEAR(actual.std, expected.std, tolerance);
  EXPECT_NEAR(actual.min, expected.min, tolerance);
  EXPECT_NEAR(actual.max, expected.max, tolerance);
}

/// The library's window equals the hand computation over `pairs`.
void expectAsByHand(const RelativePoseError& rpe, const Flight& f, const evo_reference::IndexPairs& pairs, double scale) {
  ASSERT_EQ(rpe.pairs, static_cast<long>(pairs.size()));
  ASSERT_GT(rpe.pairs, 0);
  const auto [translation, rotation] = evo_reference::relativeErrors(f.q, f.p, pairs, scale);
  expectStatistics(rpe.translation_m, translation);
  expectStatistics(rpe.rotation_deg, rotation);
  EXPECT_EQ(rpe.translation_rmse_m, rpe.translation_m.rmse);
  EXPECT_EQ(rpe.rotation_rmse_deg, rpe.rotation_deg.rmse);
}

TEST(EvoRpe, FrameWindowsMatchTheHandComputationForBothPairings) {
  for (const unsigned seed : {21u, 22u, 23u}) {
    SCOPED_TRACE(seed);
    const Flight f = noisyFlight(seed);
    ASSERT_TRUE(f.association.paired_from_ground_truth);
    ASSERT_EQ(f.q.size(), f.association.size());
    for (const long frames : {1L, 3L, 10L}) {
      for (const RpePairing pairing : {RpePairing::kEvo, RpePairing::kEveryPose}) {
        SCOPED_TRACE(std::to_string(frames) + " frames, " + rpePairingName(pairing));
        const auto rpe = relativePoseErrorFrames(f.association, frames, 1.0, pairing);
        ASSERT_TRUE(rpe.ok()) << rpe.status().toString();
        EXPECT_EQ(rpe->frames, frames);
        EXPECT_EQ(rpe->distance_m, 0.0);
        expectAsByHand(*rpe, f, evo_reference::framePairs(f.q.size(), frames, pairing == RpePairing::kEvo), 1.0);
      }
    }
    // Δ = 1 frame: evo's default, the same pairs either way.
    EXPECT_EQ(relativePoseErrorFrames(f.association, 1, 1.0, RpePairing::kEvo)->translation_m.median,
              relativePoseErrorFrames(f.association, 1, 1.0, RpePairing::kEveryPose)->translation_m.median);
  }
}

TEST(EvoRpe, MetreWindowsMatchTheHandComputationForBothPairingsAndAScale) {
  const Flight f = noisyFlight(31);
  std::vector<Eigen::Vector3d> gt_path, est_path;
  for (size_t k = 0; k < f.q.size(); ++k) {
    gt_path.push_back(f.q[k].translation());
    est_path.push_back(f.p[k].translation());
  }
  for (const double scale : {1.0, 1.3}) {
    std::vector<Eigen::Vector3d> scaled_path;
    for (const Eigen::Vector3d& position : est_path) scaled_path.push_back(scale * position);
    for (const double distance_m : {1.0, 10.0}) {
      SCOPED_TRACE(std::to_string(distance_m) + " m, scale " + std::to_string(scale));
      const auto every = relativePoseError(f.association, distance_m, scale, RpePairing::kEveryPose);
      ASSERT_TRUE(every.ok()) << every.status().toString();
      expectAsByHand(*every, f, evo_reference::everyPosePathPairs(gt_path, distance_m), scale);
      const auto evo = relativePoseError(f.association, distance_m, scale, RpePairing::kEvo);
      ASSERT_TRUE(evo.ok()) << evo.status().toString();
      expectAsByHand(*evo, f, evo_reference::evoPathPairs(scaled_path, distance_m), scale);
      EXPECT_LT(evo->pairs, every->pairs);  // non-overlapping: about one per Δ of path, not one per pose
    }
  }
}

// evaluateTrajectory with evo's association and windows gives what the parts give; the distance windows and the
// frame windows come back separately, in the order asked for.
TEST(EvoRpe, EvaluateTrajectoryAssociatesAsEvoAndReportsFrameWindows) {
  const Flight f = noisyFlight(41);
  TrajectoryMetricsParams params;
  params.alignment = TrajectoryAlignment::kSE3;
  params.max_dt_s = 0.01;
  params.evo_association = true;
  params.rpe_distances_m = {5.0};
  params.rpe_frames = {1, 2};
  params.rpe_pairing = RpePairing::kEvo;
  const auto metrics = evaluateTrajectory(f.gt, f.est, params);
  ASSERT_TRUE(metrics.ok()) << metrics.status().toString();
  EXPECT_EQ(metrics->associated, static_cast<long>(f.q.size()));
  EXPECT_TRUE(metrics->paired_from_ground_truth);
  EXPECT_EQ(metrics->paired_from_poses, static_cast<long>(f.gt.size()));
  EXPECT_EQ(metrics->estimate_poses, static_cast<long>(f.est.size()));
  ASSERT_EQ(metrics->rpe.size(), 1u);
  ASSERT_EQ(metrics->rpe_frames.size(), 2u);
  EXPECT_EQ(metrics->rpe[0].distance_m, 5.0);
  EXPECT_EQ(metrics->rpe_frames[1].frames, 2);
  expectAsByHand(metrics->rpe_frames[0], f, evo_reference::framePairs(f.q.size(), 1, true), 1.0);
  expectAsByHand(metrics->rpe_frames[1], f, evo_reference::framePairs(f.q.size(), 2, true), 1.0);
  // Without the flag the same max_dt_s pairs from every estimate pose: one pair per estimate pose near a GT stamp.
  params.evo_association = false;
  const auto nearest = evaluateTrajectory(f.gt, f.est, params);
  ASSERT_TRUE(nearest.ok());
  EXPECT_FALSE(nearest->paired_from_ground_truth);
  EXPECT_GT(nearest->associated, metrics->associated);
}

TEST(EvoRpe, WindowsWithoutPairsAreNaNAndBadWindowsAreErrors) {
  const Flight f = noisyFlight(51);
  const auto too_long = relativePoseErrorFrames(f.association, static_cast<long>(f.association.size()), 1.0,
                                                RpePairing::kEvo);
  ASSERT_TRUE(too_long.ok());
  EXPECT_EQ(too_long->pairs, 0);
  EXPECT_TRUE(std::isnan(too_long->translation_rmse_m));
  EXPECT_TRUE(std::isnan(too_long->translation_m.median));
  EXPECT_TRUE(std::isnan(too_long->rotation_deg.max));
  for (const long frames : {0L, -1L}) {
    const auto bad = relativePoseErrorFrames(f.association, frames);
    EXPECT_EQ(bad.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(bad.status().message().find("must be at least 1"), std::string::npos) << bad.status().message();
  }
  for (const double distance_m : {0.0, -1.0, std::nan("")}) {
    EXPECT_EQ(relativePoseError(f.association, distance_m, 1.0, RpePairing::kEvo).status().code(),
              StatusCode::kInvalidArgument);
  }
  TrajectoryMetricsParams params;
  params.rpe_frames = {0};
  EXPECT_EQ(evaluateTrajectory(f.gt, f.est, params).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(parseRpePairing("all").status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(*parseRpePairing("evo"), RpePairing::kEvo);
}

}  // namespace
}  // namespace dualgraph
