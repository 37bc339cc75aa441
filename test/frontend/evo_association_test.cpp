// SPDX-License-Identifier: MIT
// associateAsEvo against evo's pairing written out by brute force (evo_reference.h) on seeded random stamps:
// ground truth sparser than the estimate and the other way round, stamps just outside max-diff, a dense pose
// serving two sparse stamps, the counters, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "dualgraph/frontend/evaluation/trajectory_metrics.h"
#include "test/frontend/evo_reference.h"

namespace dualgraph {
namespace {

/// The library's pairs, as (ground-truth index, estimate index).
evo_reference::IndexPairs pairsOf(const TrajectoryAssociation& association) {
  evo_reference::IndexPairs pairs;
  for (size_t k = 0; k < association.size(); ++k) {
    pairs.emplace_back(association.ground_truth_index[k], association.estimate_index[k]);
  }
  return pairs;
}

/// The library's association equals the brute force's: pairs, poses, stamps, counters, and time order.
void expectAsBruteForce(const StampedPoses& gt, const StampedPoses& est, double max_diff) {
  const evo_reference::Association expected = evo_reference::associate(gt, est, max_diff);
  const auto association = associateAsEvo(gt, est, max_diff);
  ASSERT_TRUE(association.ok()) << association.status().toString();
  EXPECT_EQ(association->paired_from_ground_truth, expected.from_ground_truth);
  EXPECT_EQ(association->paired_from_poses, static_cast<long>(expected.from_ground_truth ? gt.size() : est.size()));
  ASSERT_EQ(pairsOf(*association), expected.gt_est);
  EXPECT_EQ(association->before_span, expected.before);
  EXPECT_EQ(association->after_span, expected.after);
  EXPECT_EQ(association->beyond_gap, expected.beyond);
  EXPECT_EQ(static_cast<long>(association->size()) + association->unassociated(), association->paired_from_poses);
  for (size_t k = 0; k < association->size(); ++k) {
    const auto [g, e] = expected.gt_est[k];
    EXPECT_EQ(association->world_T_body_gt[k].first, gt[g].first);  // each keeps its own stamp
    EXPECT_EQ(association->estimate_T_body[k].first, est[e].first);
    EXPECT_TRUE(association->world_T_body_gt[k].second.isApprox(gt[g].second));
    EXPECT_TRUE(association->estimate_T_body[k].second.isApprox(est[e].second));
    EXPECT_LE(std::abs(gt[g].first - est[e].first), max_diff);
    if (k > 0) {  // in the sparse trajectory's time order
      EXPECT_GT(expected.from_ground_truth ? gt[g].first : est[e].first,
                expected.from_ground_truth ? association->world_T_body_gt[k - 1].first
                                           : association->estimate_T_body[k - 1].first);
    }
  }
}

/// `poses` without those whose stamp falls in [from, to) (a gap in the recording).
StampedPoses withGap(StampedPoses poses, double from, double to) {
  StampedPoses kept;
  for (const auto& sample : poses) {
    if (sample.first < from || sample.first >= to) kept.push_back(sample);
  }
  return kept;
}

// The case: ground truth at 30 Hz, the estimate at 100 Hz with a gap and starting earlier and ending later;
// evo pairs from the ground truth, so there are at most as many pairs as ground-truth poses.
TEST(EvoAssociation, GroundTruthSparserThanTheEstimateMatchesBruteForce) {
  for (const unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    SCOPED_TRACE(seed);
    std::mt19937 rng(seed);
    const StampedPoses gt = evo_reference::randomFlight(rng, 10.0, 1.0 / 30.0, 0.004, 600, 0.0, seed);
    const StampedPoses est =
        withGap(evo_reference::randomFlight(rng, 9.0, 0.01, 0.003, 2200, 0.02, seed), 14.0, 14.5);
    ASSERT_GT(est.size(), gt.size());
    for (const double max_diff : {0.01, 0.002, 0.02}) {
      SCOPED_TRACE(max_diff);
      expectAsBruteForce(gt, est, max_diff);
      const auto association = associateAsEvo(gt, est, max_diff);
      ASSERT_TRUE(association.ok());
      EXPECT_TRUE(association->paired_from_ground_truth);
      EXPECT_LE(association->size(), gt.size());
      EXPECT_GT(association->beyond_gap, 0);  // the gap in the estimate
    }
  }
}

TEST(EvoAssociation, EstimateSparserOrAsLongMatchesBruteForce) {
  for (const unsigned seed : {11u, 12u, 13u}) {
    SCOPED_TRACE(seed);
    std::mt19937 rng(seed);
    const StampedPoses gt = evo_reference::randomFlight(rng, 10.0, 0.005, 0.001, 3000, 0.0, seed);
    const StampedPoses est = evo_reference::randomFlight(rng, 8.0, 0.05, 0.02, 400, 0.05, seed);  // before the GT too
    expectAsBruteForce(gt, est, 0.01);
    EXPECT_FALSE(associateAsEvo(gt, est, 0.01)->paired_from_ground_truth);
    // As many poses: evo pairs from its second trajectory, the estimate.
    const StampedPoses same_count = evo_reference::randomFlight(rng, 10.0, 0.005, 0.002, 3000, 0.05, seed);
    expectAsBruteForce(gt, same_count, 0.01);
    EXPECT_FALSE(associateAsEvo(gt, same_count, 0.01)->paired_from_ground_truth);
  }
}

// Every other ground-truth stamp has its nearest estimate stamp a microsecond inside max-diff, the others a
// microsecond outside; a difference of exactly max-diff pairs (evo's ≤).
TEST(EvoAssociation, StampsJustOutsideMaxDiffAreNotPaired) {
  StampedPoses gt, est;
  for (int k = 0; k < 20; ++k) {
    const double t = 100.0 + k;
    gt.emplace_back(t, Eigen::Isometry3d::Identity());
    est.emplace_back(t + (k % 2 ? 0.01 - 1e-6 : -(0.01 + 1e-6)), Eigen::Isometry3d::Identity());
    est.emplace_back(t + 0.5, Eigen::Isometry3d::Identity());
  }
  expectAsBruteForce(gt, est, 0.01);
  const auto association = associateAsEvo(gt, est, 0.01);
  ASSERT_TRUE(association.ok()) << association.status().toString();
  EXPECT_EQ(association->size(), 10u);
  EXPECT_EQ(association->beyond_gap, 10);
  for (size_t k = 0; k < association->size(); ++k) EXPECT_EQ(association->ground_truth_index[k] % 2, 1u);

  const StampedPoses two = {{1.0, Eigen::Isometry3d::Identity()}, {2.0, Eigen::Isometry3d::Identity()}};
  const StampedPoses three = {{1.25, Eigen::Isometry3d::Identity()}, {1.5, Eigen::Isometry3d::Identity()},
                              {1.75, Eigen::Isometry3d::Identity()}};
  EXPECT_EQ(associateAsEvo(two, three, 0.25)->size(), 2u);  // |Δt| = 0.25 exactly, in binary too
  EXPECT_EQ(associateAsEvo(two, three, 0.2499).status().code(), StatusCode::kFailedPrecondition);
}

// evo does not keep a dense pose from serving twice: two ground-truth stamps 4 ms apart both pick the estimate pose
// between them. Ties go to the earlier stamp (numpy's argmin).
TEST(EvoAssociation, ADensePoseServesTwoSparseStampsAsInEvoAndTiesGoEarlier) {
  const auto at = [](std::initializer_list<double> stamps) {
    StampedPoses poses;
    for (const double t : stamps) poses.emplace_back(t, Eigen::Isometry3d::Identity());
    return poses;
  };
  const StampedPoses gt = at({0.0, 0.004, 5.0});
  const StampedPoses est = at({-1.0, 0.003, 2.0, 3.0, 4.0});
  expectAsBruteForce(gt, est, 0.01);
  const auto association = associateAsEvo(gt, est, 0.01);
  ASSERT_TRUE(association.ok());
  EXPECT_EQ(pairsOf(*association), (evo_reference::IndexPairs{{0, 1}, {1, 1}}));
  EXPECT_EQ(association->after_span, 1);  // 5 s is past the estimate's 4 s by more than 0.01 s

  const auto tie = associateAsEvo(at({0.5, 1.0, 1.5, 9.0}), at({1.25, 8.0}), 0.25);  // 1.0 and 1.5 equally near
  ASSERT_TRUE(tie.ok());
  EXPECT_EQ(pairsOf(*tie), (evo_reference::IndexPairs{{1, 0}}));
  EXPECT_EQ(tie->beyond_gap, 1);  // 8.0: nearest ground truth 9.0 is a second away
}

TEST(EvoAssociation, BadInputIsAnErrorNamingIt) {
  std::mt19937 rng(7);
  const StampedPoses gt = evo_reference::randomFlight(rng, 0.0, 0.02, 0.0, 100, 0.0, 7);
  for (const double bad : {-0.01, 0.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    const auto association = associateAsEvo(gt, gt, bad);
    EXPECT_EQ(association.status().code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(association.status().message().find("maximum time difference"), std::string::npos)
        << association.status().message();
  }
  StampedPoses with_nan = gt;
  with_nan[5].first = std::nan("");
  EXPECT_EQ(associateAsEvo(gt, with_nan, 0.01).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(associateAsEvo({}, gt, 0.01).status().code(), StatusCode::kInvalidArgument);
  StampedPoses later = gt;
  for (auto& sample : later) sample.first += 100.0;
  const auto apart = associateAsEvo(gt, later, 0.01);
  EXPECT_EQ(apart.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(apart.status().message().find("does not overlap"), std::string::npos) << apart.status().message();
}

}  // namespace
}  // namespace dualgraph
