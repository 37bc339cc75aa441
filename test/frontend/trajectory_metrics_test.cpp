// SPDX-License-Identifier: MIT
// Trajectory metrics: alignment recovers known transforms (SE(3); 4-DoF yaw but not roll), noise of
// known σ gives ATE ≈ σ√3, a scale error gives RPE = s·Δ, interpolation and the association
// counters, and every error path.
#include "dualgraph/frontend/evaluation/trajectory_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

constexpr double kDeg = 180.0 / EIGEN_PI;
constexpr double kInf = std::numeric_limits<double>::infinity();

Eigen::Isometry3d poseFrom(const Eigen::Vector3d& p, double roll, double pitch, double yaw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  pose.translation() = p;
  return pose;
}

/// A 3-D racing loop (an ellipse-like figure with height changes), body x along the velocity, banked.
StampedPoses racingLoop(int n, double dt) {
  StampedPoses world_T_body;
  for (int k = 0; k < n; ++k) {
    const double t = 100.0 + k * dt;
    const double a = 0.2 * t;
    const Eigen::Vector3d p(10.0 * std::cos(a), 5.0 * std::sin(2.0 * a), 1.5 + 0.5 * std::sin(0.3 * t));
    const double yaw = std::atan2(10.0 * std::cos(2.0 * a), -10.0 * std::sin(a));
    world_T_body.emplace_back(t, poseFrom(p, 0.3 * std::sin(a), 0.1 * std::cos(a), yaw));
  }
  return world_T_body;
}

/// The same poses seen from another frame: estimate_T_world · world_T_body.
StampedPoses inFrame(const Eigen::Isometry3d& estimate_T_world, const StampedPoses& world_T_body) {
  StampedPoses estimate_T_body;
  for (const auto& [t, pose] : world_T_body) estimate_T_body.emplace_back(t, estimate_T_world * pose);
  return estimate_T_body;
}

/// RMSE of |p_gt − estimate_T_world · p_gt| computed directly.
double offsetRmse(const Eigen::Isometry3d& estimate_T_world, const StampedPoses& world_T_body) {
  double sum = 0.0;
  for (const auto& [t, pose] : world_T_body) {
    sum += (estimate_T_world * pose.translation() - pose.translation()).squaredNorm();
  }
  return std::sqrt(sum / world_T_body.size());
}

bool nearlyEqual(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double tolerance) {
  return a.matrix().isApprox(b.matrix(), tolerance) || (a.matrix() - b.matrix()).norm() < tolerance;
}

TEST(TrajectoryMetrics, Se3AlignmentRecoversAKnownTransformAndUnalignedShowsIt) {
  const StampedPoses gt = racingLoop(800, 0.05);
  const Eigen::Isometry3d estimate_T_world = poseFrom({3.0, -2.0, 1.0}, 0.3, -0.2, 1.0);
  const StampedPoses est = inFrame(estimate_T_world, gt);
  const auto metrics = evaluateTrajectory(gt, est);
  ASSERT_TRUE(metrics.ok()) << metrics.status().toString();
  EXPECT_LT(metrics->ate_m, 1e-9);
  EXPECT_LT(metrics->ate_se3_m, 1e-9);
  EXPECT_LT(metrics->ate_rot_deg, 1e-6);
  EXPECT_TRUE(nearlyEqual(metrics->world_T_estimate, estimate_T_world.inverse(), 1e-9));
  EXPECT_NEAR(metrics->ate_unaligned_m, offsetRmse(estimate_T_world, gt), 1e-9);
  EXPECT_GT(metrics->ate_unaligned_m, 1.0);
  EXPECT_EQ(metrics->associated, 800);
  EXPECT_EQ(metrics->unassociated(), 0);
  ASSERT_EQ(metrics->rpe.size(), 2u);  // RPE does not see a fixed frame change
  for (const RelativePoseError& rpe : metrics->rpe) {
    EXPECT_GT(rpe.pairs, 100);
    EXPECT_LT(rpe.translation_rmse_m, 1e-9);
    EXPECT_LT(rpe.rotation_rmse_deg, 1e-6);
  }
}

TEST(TrajectoryMetrics, APureOffsetIsTheUnalignedAteAndNoRotationError) {
  const StampedPoses gt = racingLoop(400, 0.05);
  const StampedPoses est = inFrame(poseFrom({0.3, 0.4, 1.2}, 0.0, 0.0, 0.0), gt);
  TrajectoryMetricsParams params;
  params.alignment = TrajectoryAlignment::kNone;
  const auto metrics = evaluateTrajectory(gt, est, params);
  ASSERT_TRUE(metrics.ok()) << metrics.status().toString();
  EXPECT_NEAR(metrics->ate_m, 1.3, 1e-12);
  EXPECT_NEAR(metrics->ate_unaligned_m, 1.3, 1e-12);
  EXPECT_LT(metrics->ate_rot_deg, 1e-6);
  EXPECT_LT(metrics->ate_se3_m, 1e-9);
  EXPECT_LT(metrics->ate_4dof_m, 1e-9);
  EXPECT_TRUE(metrics->world_T_estimate.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(TrajectoryMetrics, FourDofRecoversYawAndTranslationButNotRoll) {
  const StampedPoses gt = racingLoop(800, 0.05);
  const Eigen::Isometry3d yawed = poseFrom({-4.0, 2.5, 0.7}, 0.0, 0.0, 2.5);
  TrajectoryMetricsParams params;
  params.alignment = TrajectoryAlignment::kFourDof;
  const auto metrics = evaluateTrajectory(gt, inFrame(yawed, gt), params);
  ASSERT_TRUE(metrics.ok()) << metrics.status().toString();
  EXPECT_LT(metrics->ate_m, 1e-9);
  EXPECT_LT(metrics->ate_4dof_m, 1e-9);
  EXPECT_LT(metrics->ate_rot_deg, 1e-6);
  EXPECT_TRUE(nearlyEqual(metrics->world_T_estimate, yawed.inverse(), 1e-9));

  const double roll = 0.1;
  const auto rolled = evaluateTrajectory(gt, inFrame(poseFrom({-4.0, 2.5, 0.7}, roll, 0.0, 2.5), gt), params);
  ASSERT_TRUE(rolled.ok()) << rolled.status().toString();
  EXPECT_GT(rolled->ate_4dof_m, 0.05);  // the loop spans ±10 m: a 0.1 rad roll leaves decimetres
  EXPECT_LT(rolled->ate_se3_m, 1e-9);
  EXPECT_NEAR(rolled->ate_rot_deg, roll * kDeg, 0.2 * roll * kDeg);  // the roll stays in every pose
  EXPECT_NEAR(rolled->world_T_estimate.linear().determinant(), 1.0, 1e-12);
}

TEST(TrajectoryMetrics, IsotropicNoiseOfKnownSigmaGivesAteOfSigmaRootThree) {
  const StampedPoses gt = racingLoop(3000, 0.02);
  const double sigma_m = 0.05;
  const double sigma_rad = 0.01;
  std::mt19937 rng(42);
  std::normal_distribution<double> normal(0.0, 1.0);
  StampedPoses est = gt;
  for (auto& [t, pose] : est) {
    pose.translation() += sigma_m * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    pose.linear() = pose.linear() * so3Exp(sigma_rad * Eigen::Vector3d(normal(rng), normal(rng), normal(rng)));
  }
  const auto metrics = evaluateTrajectory(gt, est);
  ASSERT_TRUE(metrics.ok()) << metrics.status().toString();
  // |n|²/σ² is χ²(3): the mean of 3000 has a relative std of √(6/3000)/3 = 1.5 %, the RMSE half that;
  // 5 % is more than six standard deviations.
  const double expected_m = sigma_m * std::sqrt(3.0);
  EXPECT_NEAR(metrics->ate_unaligned_m, expected_m, 0.05 * expected_m);
  EXPECT_NEAR(metrics->ate_se3_m, expected_m, 0.05 * expected_m);
  EXPECT_LE(metrics->ate_se3_m, metrics->ate_unaligned_m);  // the alignment minimises exactly this
  EXPECT_LE(metrics->ate_se3_m, metrics->ate_4dof_m + 1e-15);
  EXPECT_NEAR(metrics->ate_rot_deg, sigma_rad * std::sqrt(3.0) * kDeg, 0.05 * sigma_rad * std::sqrt(3.0) * kDeg);
}

TEST(TrajectoryMetrics, RpeOfAConstantScaleErrorIsScaleTimesDistance) {
  const double scale_error = 0.02;
  const Eigen::Vector3d step = 0.125 * Eigen::Vector3d(0.6, 0.8, 0.0);  // 0.125 m per sample
  StampedPoses gt;
  StampedPoses est;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d p = k * step;
    gt.emplace_back(k * 0.1, poseFrom(p, 0.0, 0.0, 0.93));
    est.emplace_back(k * 0.1, poseFrom((1.0 + scale_error) * p, 0.0, 0.0, 0.93));
  }
  const auto metrics = evaluateTrajectory(gt, est);
  ASSERT_TRUE(metrics.ok()) << metrics.status().toString();
  ASSERT_EQ(metrics->rpe.size(), 2u);
  EXPECT_EQ(metrics->rpe[0].distance_m, 1.0);
  EXPECT_NEAR(metrics->rpe[0].translation_rmse_m, scale_error * 1.0, 1e-12);
  EXPECT_EQ(metrics->rpe[0].pairs, 200 - 8);  // j = i + 8 for every i ≤ 191
  EXPECT_NEAR(metrics->rpe[1].translation_rmse_m, scale_error * 10.0, 1e-12);
  EXPECT_EQ(metrics->rpe[1].pairs, 200 - 80);
  EXPECT_LT(metrics->rpe[0].rotation_rmse_deg, 1e-9);

  TrajectoryAssociation short_path = *associateByTime(gt, est);  // longer than the whole path: no pairs
  const auto too_long = relativePoseError(short_path, 30.0);
  ASSERT_TRUE(too_long.ok());
  EXPECT_EQ(too_long->pairs, 0);
  EXPECT_TRUE(std::isnan(too_long->translation_rmse_m));
}

TEST(TrajectoryMetrics, GroundTruthIsInterpolatedLinearlyAndBySlerpOnTheShortArc) {
  const StampedPoses gt = {{0.0, poseFrom({0.0, 0.0, 0.0}, 0.0, 0.0, 3.0)},
                           {1.0, poseFrom({2.0, -4.0, 1.0}, 0.0, 0.0, -3.0)},
                           {2.0, poseFrom({2.0, -4.0, 3.0}, 0.0, 0.0, -3.0)}};
  const StampedPoses est = {{0.25, Eigen::Isometry3d::Identity()},
                            {0.5, Eigen::Isometry3d::Identity()},
                            {1.0, Eigen::Isometry3d::Identity()},
                            {2.0, Eigen::Isometry3d::Identity()}};
  const auto association = associateByTime(gt, est, 1.0);
  ASSERT_TRUE(association.ok()) << association.status().toString();
  ASSERT_EQ(association->size(), 4u);
  const Eigen::Isometry3d& quarter = association->world_T_body_gt[0].second;
  EXPECT_TRUE(quarter.translation().isApprox(Eigen::Vector3d(0.5, -1.0, 0.25)));
  // From yaw 3 to yaw −3 the short way goes through π: 3 + 0.25 · (2π − 6).
  const double quarter_yaw = 3.0 + 0.25 * (2.0 * EIGEN_PI - 6.0);
  EXPECT_TRUE(quarter.linear().isApprox(poseFrom({0, 0, 0}, 0, 0, quarter_yaw).linear(), 1e-12));
  EXPECT_TRUE(association->world_T_body_gt[1].second.linear().isApprox(poseFrom({0, 0, 0}, 0, 0, EIGEN_PI).linear(), 1e-12));
  EXPECT_TRUE(nearlyEqual(association->world_T_body_gt[2].second, gt[1].second, 1e-15));
  EXPECT_TRUE(nearlyEqual(association->world_T_body_gt[3].second, gt[2].second, 1e-15));  // the last sample
  EXPECT_EQ(association->estimate_index, (std::vector<size_t>{0, 1, 2, 3}));
  EXPECT_EQ(association->world_T_body_gt[0].first, 0.25);
}

TEST(TrajectoryMetrics, CountsEstimatePosesOutsideTheSpanAndBeyondTheGapWithoutDroppingAny) {
  StampedPoses gt;
  for (int k = 0; k <= 200; ++k) {
    if (k <= 80 || k >= 100) gt.emplace_back(k * 0.05, poseFrom({0.1 * k, 0.0, 0.0}, 0, 0, 0));  // hole 4 s–5 s
  }
  StampedPoses est;
  for (int k = -4; k <= 48; ++k) est.emplace_back(k * 0.25, poseFrom({0.5 * k, 0.0, 0.0}, 0, 0, 0));
  const auto association = associateByTime(gt, est);  // 0.1 s
  ASSERT_TRUE(association.ok()) << association.status().toString();
  EXPECT_EQ(association->before_span, 4);  // −1, −0.75, −0.5, −0.25
  EXPECT_EQ(association->after_span, 8);   // 10.25 … 12
  EXPECT_EQ(association->beyond_gap, 3);   // 4.25, 4.5, 4.75
  EXPECT_EQ(static_cast<long>(association->size()) + association->unassociated(), static_cast<long>(est.size()));
  const auto metrics = evaluateTrajectory(gt, est);
  ASSERT_TRUE(metrics.ok());
  EXPECT_EQ(metrics->associated, 53 - 15);  // 38
  EXPECT_EQ(metrics->unassociated(), 15);
  EXPECT_EQ(metrics->estimate_poses, 53);
}

TEST(TrajectoryMetrics, Se3AlignmentIsAProperRotationEvenForAMirroredEstimate) {
  const StampedPoses gt = racingLoop(300, 0.05);
  StampedPoses est = gt;
  for (auto& [t, pose] : est) pose.translation().z() = -pose.translation().z();  // a reflection of the positions
  const auto association = associateByTime(gt, est);
  ASSERT_TRUE(association.ok());
  const auto world_T_estimate = alignTrajectory(*association, TrajectoryAlignment::kSE3);
  ASSERT_TRUE(world_T_estimate.ok());
  const Eigen::Matrix3d rotation = world_T_estimate->world_T_estimate.linear();
  EXPECT_NEAR(rotation.determinant(), 1.0, 1e-12);
  EXPECT_TRUE((rotation.transpose() * rotation).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

TEST(TrajectoryMetrics, AlignmentNamesRoundTrip) {
  for (const auto alignment : {TrajectoryAlignment::kSE3, TrajectoryAlignment::kFourDof, TrajectoryAlignment::kNone,
                               TrajectoryAlignment::kSim3, TrajectoryAlignment::kOrigin}) {
    const auto parsed = parseTrajectoryAlignment(trajectoryAlignmentName(alignment));
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(*parsed, alignment);
  }
  const auto bad = parseTrajectoryAlignment("se(3)");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("'se(3)'"), std::string::npos);
}

/// Asserts an error with `code` whose message contains `fragment`.
::testing::AssertionResult failsWith(const Status& status, StatusCode code, const std::string& fragment) {
  if (status.ok()) return ::testing::AssertionFailure() << "expected an error, got OK";
  if (status.code() != code) return ::testing::AssertionFailure() << "wrong code: " << status.toString();
  if (status.message().find(fragment) == std::string::npos) {
    return ::testing::AssertionFailure() << "message lacks '" << fragment << "': " << status.message();
  }
  return ::testing::AssertionSuccess();
}

TEST(TrajectoryMetricsErrors, EmptyNoOverlapAndNothingWithinTheGap) {
  const StampedPoses gt = racingLoop(50, 0.1);  // t ∈ [100, 104.9]
  EXPECT_TRUE(failsWith(evaluateTrajectory({}, gt).status(), StatusCode::kInvalidArgument, "ground truth is empty"));
  EXPECT_TRUE(failsWith(evaluateTrajectory(gt, {}).status(), StatusCode::kInvalidArgument, "estimate is empty"));
  StampedPoses later = gt;
  for (auto& sample : later) sample.first += 10.0;
  EXPECT_TRUE(failsWith(evaluateTrajectory(gt, later).status(), StatusCode::kFailedPrecondition,
                        "does not overlap the ground truth [100, 104.9"));
  const StampedPoses sparse_gt = {gt.front(), gt.back()};
  const StampedPoses middle = {{102.0, Eigen::Isometry3d::Identity()}};
  EXPECT_TRUE(failsWith(evaluateTrajectory(sparse_gt, middle).status(), StatusCode::kFailedPrecondition,
                        "within the maximum gap of 0.1 s"));
}

TEST(TrajectoryMetricsErrors, AlignmentNeedsThreePosesExceptNone) {
  const StampedPoses gt = racingLoop(50, 0.1);
  const StampedPoses two = {gt[3], gt[7]};
  TrajectoryMetricsParams params;
  for (const auto alignment : {TrajectoryAlignment::kSE3, TrajectoryAlignment::kFourDof}) {
    params.alignment = alignment;
    EXPECT_TRUE(failsWith(evaluateTrajectory(gt, two, params).status(), StatusCode::kFailedPrecondition,
                          "at least 3 associated poses, got 2"));
  }
  params.alignment = TrajectoryAlignment::kNone;
  const auto metrics = evaluateTrajectory(gt, two, params);
  ASSERT_TRUE(metrics.ok()) << metrics.status().toString();
  EXPECT_LT(metrics->ate_m, 1e-12);
  EXPECT_TRUE(std::isnan(metrics->ate_se3_m));
  EXPECT_TRUE(std::isnan(metrics->ate_4dof_m));
}

TEST(TrajectoryMetricsErrors, NonFiniteOrUnorderedInputNamesTheTrajectoryAndPose) {
  const StampedPoses good = racingLoop(10, 0.1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    const char* name;
    void (*corrupt)(StampedPoses&, double);
    const char* fragment;
  };
  const Case cases[] = {
      {"nan stamp", [](StampedPoses& p, double bad) { p[3].first = bad; }, "pose 3: time stamp is not finite"},
      {"nan position", [](StampedPoses& p, double bad) { p[3].second.translation().y() = bad; }, "pose 3"},
      {"inf rotation", [](StampedPoses& p, double) { p[3].second.linear()(0, 0) = kInf; }, "pose 3"},
      {"not a rotation", [](StampedPoses& p, double) { p[3].second.linear() *= 2.0; }, "pose 3"},
      {"repeated stamp", [](StampedPoses& p, double) { p[3].first = p[2].first; }, "pose 3: time stamp"},
      {"stamp going back", [](StampedPoses& p, double) { p[3].first = 0.0; }, "pose 3: time stamp 0 s does not increase (previous 100.2 s)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    StampedPoses bad = good;
    c.corrupt(bad, nan);
    EXPECT_TRUE(failsWith(evaluateTrajectory(bad, good).status(), StatusCode::kInvalidArgument,
                          std::string("ground truth: ") + c.fragment));
    EXPECT_TRUE(failsWith(evaluateTrajectory(good, bad).status(), StatusCode::kInvalidArgument,
                          std::string("estimate: ") + c.fragment));
  }
}

TEST(TrajectoryMetricsErrors, BadGapOrRpeDistanceIsInvalid) {
  const StampedPoses gt = racingLoop(50, 0.1);
  for (const double gap : {0.0, -1.0, std::nan(""), kInf}) {
    EXPECT_TRUE(failsWith(associateByTime(gt, gt, gap).status(), StatusCode::kInvalidArgument, "maximum gap"));
  }
  TrajectoryMetricsParams params;
  for (const double distance : {0.0, -2.0, std::nan(""), kInf}) {
    params.rpe_distances_m = {1.0, distance};
    EXPECT_TRUE(failsWith(evaluateTrajectory(gt, gt, params).status(), StatusCode::kInvalidArgument, "RPE distance"));
  }
}

}  // namespace
}  // namespace dualgraph
