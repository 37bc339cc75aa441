// SPDX-License-Identifier: MIT
// evo's other modes: Sim(3) alignment recovers a known scale, origin alignment makes the first poses equal,
// nearest-stamp association pairs without interpolating (ties to the earlier sample, counters).
#include <gtest/gtest.h>

#include <cmath>

#include "dualgraph/frontend/evaluation/trajectory_metrics.h"

namespace dualgraph {
namespace {

/// A climbing spiral sampled every `dt` seconds from t = 50 s, body x along the path.
StampedPoses spiral(int n, double dt) {
  StampedPoses poses;
  for (int k = 0; k < n; ++k) {
    const double t = 50.0 + k * dt;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(0.4 * t + M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                    Eigen::AngleAxisd(0.2 * std::sin(t), Eigen::Vector3d::UnitX()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(8.0 * std::cos(0.4 * t), 6.0 * std::sin(0.4 * t), 0.05 * t);
    poses.emplace_back(t, pose);
  }
  return poses;
}

Eigen::Isometry3d someFrame() {
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()))
                       .toRotationMatrix();
  frame.translation() = Eigen::Vector3d(4.0, -3.0, 0.5);
  return frame;
}

TEST(TrajectoryAlignmentModes, Sim3RecoversAScaledFrameAndSe3CannotRemoveTheScale) {
  const StampedPoses gt = spiral(600, 0.05);
  const Eigen::Isometry3d estimate_T_world = someFrame();
  const double s = 0.8;  // a monocular estimate 20 % small
  StampedPoses est;
  for (const auto& [t, pose] : gt) {
    Eigen::Isometry3d p = estimate_T_world * pose;
    p.translation() = estimate_T_world.linear() * (s * pose.translation()) + estimate_T_world.translation();
    est.emplace_back(t, p);
  }
  TrajectoryMetricsParams params;
  params.alignment = TrajectoryAlignment::kSim3;
  const auto sim3 = evaluateTrajectory(gt, est, params);
  ASSERT_TRUE(sim3.ok()) << sim3.status().toString();
  EXPECT_NEAR(sim3->scale, 1.0 / s, 1e-9);
  EXPECT_LT(sim3->ate_m, 1e-9);
  EXPECT_LT(sim3->ate_rot_deg, 1e-6);
  EXPECT_LT(sim3->rpe[0].translation_rmse_m, 1e-9) << "the scale applies to the RPE too";
  EXPECT_NEAR(sim3->ate_stats.max, 0.0, 1e-9);

  params.alignment = TrajectoryAlignment::kSE3;
  const auto se3 = evaluateTrajectory(gt, est, params);
  ASSERT_TRUE(se3.ok());
  EXPECT_EQ(se3->scale, 1.0);
  EXPECT_GT(se3->ate_m, 0.5);
  EXPECT_GT(se3->rpe[0].translation_rmse_m, 0.1);  // 20 % of 1 m windows
}

TEST(TrajectoryAlignmentModes, Sim3NeedsSpreadPositions) {
  StampedPoses gt = spiral(10, 0.1), est = gt;
  for (auto& [t, pose] : est) pose.translation().setZero();
  const auto association = associateByTime(gt, est);
  ASSERT_TRUE(association.ok());
  const auto aligned = alignTrajectory(*association, TrajectoryAlignment::kSim3);
  ASSERT_FALSE(aligned.ok());
  EXPECT_NE(aligned.status().message().find("do not spread"), std::string::npos) << aligned.status().message();
}

TEST(TrajectoryAlignmentModes, OriginMakesTheFirstPosesEqualAndLeavesDriftVisible) {
  const StampedPoses gt = spiral(400, 0.05);
  const Eigen::Isometry3d estimate_T_world = someFrame();
  StampedPoses est;
  for (size_t k = 0; k < gt.size(); ++k) {
    Eigen::Isometry3d pose = estimate_T_world * gt[k].second;
    pose.translation() += Eigen::Vector3d(0.01 * static_cast<double>(k), 0.0, 0.0);  // drift growing from 0
    est.emplace_back(gt[k].first, pose);
  }
  TrajectoryMetricsParams params;
  params.alignment = TrajectoryAlignment::kOrigin;
  const auto metrics = evaluateTrajectory(gt, est, params);
  ASSERT_TRUE(metrics.ok()) << metrics.status().toString();
  EXPECT_TRUE(metrics->world_T_estimate.isApprox(estimate_T_world.inverse(), 1e-9));
  EXPECT_NEAR(metrics->ate_stats.min, 0.0, 1e-9);
  EXPECT_NEAR(metrics->ate_stats.max, 0.01 * 399, 1e-9);  // the drift, not spread out by a least-squares fit
  EXPECT_LT(metrics->ate_rot_deg, 1e-6);
}

TEST(TrajectoryAlignmentModes, NearestStampPairsWithoutInterpolating) {
  const StampedPoses gt = spiral(100, 0.1);  // [50, 59.9] s
  StampedPoses est;
  // 50.03 → gt 50.0; 50.05 (a tie) → the earlier 50.0; 50.07 → 50.1; 49.99 (before, within max_dt) → 50.0;
  // 49.9 → before the span; 60.5 → after it.
  for (const double t : {49.9, 49.99, 50.03, 50.05, 50.07, 60.5}) est.emplace_back(t, Eigen::Isometry3d::Identity());
  const auto association = associateByNearestStamp(gt, est, 0.035);
  ASSERT_TRUE(association.ok()) << association.status().toString();
  EXPECT_EQ(association->before_span, 1);
  EXPECT_EQ(association->after_span, 1);
  EXPECT_EQ(association->beyond_gap, 1);  // 50.05 is 0.05 s from both neighbours
  ASSERT_EQ(association->size(), 3u);
  EXPECT_TRUE(association->world_T_body_gt[0].second.isApprox(gt[0].second));  // 49.99
  EXPECT_TRUE(association->world_T_body_gt[1].second.isApprox(gt[0].second));  // 50.03
  EXPECT_TRUE(association->world_T_body_gt[2].second.isApprox(gt[1].second));  // 50.07
  EXPECT_EQ(association->world_T_body_gt[1].first, 50.03);  // stamped with the estimate's time

  const auto tie = associateByNearestStamp(gt, {{50.05, Eigen::Isometry3d::Identity()}}, 0.06);
  ASSERT_TRUE(tie.ok());
  EXPECT_TRUE(tie->world_T_body_gt[0].second.isApprox(gt[0].second)) << "a tie goes to the earlier sample";

  EXPECT_EQ(associateByNearestStamp(gt, est, 0.0).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(associateByNearestStamp(gt, {{70.0, Eigen::Isometry3d::Identity()}}, 0.01).status().code(),
            StatusCode::kFailedPrecondition);
}

TEST(TrajectoryAlignmentModes, NearestStampAndInterpolationAgreeOnCommonStamps) {
  const StampedPoses gt = spiral(300, 0.05);
  StampedPoses est;
  const Eigen::Isometry3d frame = someFrame();
  for (size_t k = 0; k < gt.size(); k += 3) est.emplace_back(gt[k].first, frame * gt[k].second);
  TrajectoryMetricsParams interpolated, nearest;
  nearest.max_dt_s = 0.01;
  const auto a = evaluateTrajectory(gt, est, interpolated);
  const auto b = evaluateTrajectory(gt, est, nearest);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->associated, b->associated);
  EXPECT_NEAR(a->ate_m, b->ate_m, 1e-12);
}

}  // namespace
}  // namespace dualgraph
