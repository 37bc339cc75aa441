// SPDX-License-Identifier: MIT
// OdometryScale: the VIO kept bit for bit until a scale is applied, the scale found from keyframes whose graph
// motion is the truth, at most max_change per keyframe, past poses never bent, a good VIO left alone.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dualgraph/dual_graph/odometry_scale.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

using Pairs = std::vector<OdometryScale::KeyframePair, Eigen::aligned_allocator<OdometryScale::KeyframePair>>;

/// The true body pose at sample k (10 Hz): a circle of radius 5 m at 1 m/s, yawing with the path, a little climb.
Eigen::Isometry3d truthAt(int k) {
  const double t = 0.1 * k;
  const double angle = t / 5.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(angle + M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(5.0 * std::cos(angle), 5.0 * std::sin(angle), 1.0 + 0.02 * t);
  return pose;
}

/// A VIO whose translation is (1 + error) times the truth's from the start, in its own frame (`odom_T_world`).
class ScaledVio {
 public:
  ScaledVio(double error, const Eigen::Isometry3d& odom_T_world) : error_(error), odom_T_world_(odom_T_world) {}
  Eigen::Isometry3d at(int k) const {
    const Eigen::Isometry3d truth = odom_T_world_ * truthAt(k);
    const Eigen::Vector3d start = (odom_T_world_ * truthAt(0)).translation();
    Eigen::Isometry3d pose = truth;
    pose.translation() = start + (1.0 + error_) * (truth.translation() - start);
    return pose;
  }

 private:
  double error_;
  Eigen::Isometry3d odom_T_world_;
};

Eigen::Isometry3d someFrame() {
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  frame.translation() = Eigen::Vector3d(3.0, -2.0, 0.5);
  return frame;
}

/// Feeds `samples` samples (keyframes every 20, i.e. 2 m), the graph's keyframes being the truth itself (perfect
/// gates); returns the scale applied after each update.
std::vector<double> fly(OdometryScale& scale, const ScaledVio& vio, int samples, Pairs* keyframes_out = nullptr,
                        std::vector<Eigen::Isometry3d>* rescaled_out = nullptr) {
  Pairs keyframes;
  std::vector<double> applied;
  for (int k = 0; k < samples; ++k) {
    const Eigen::Isometry3d raw = vio.at(k);
    const Eigen::Isometry3d rescaled = scale.rescaled(raw);
    scale.accept(0.1 * k, raw);
    if (rescaled_out) rescaled_out->push_back(rescaled);
    if (k % 20 == 0) {
      keyframes.push_back({0.1 * k, truthAt(k), rescaled});
      scale.update(keyframes, 0.1 * k);
      applied.push_back(scale.scale());
    }
  }
  if (keyframes_out) *keyframes_out = keyframes;
  return applied;
}

TEST(OdometryScale, TheVioIsKeptBitForBitUntilAScaleIsApplied) {
  OdometryScale scale{OdometryScaleParams{}};
  const ScaledVio vio(0.0, someFrame());
  for (int k = 0; k < 50; ++k) {
    const Eigen::Isometry3d raw = vio.at(k);
    const Eigen::Isometry3d rescaled = scale.rescaled(raw);
    EXPECT_EQ(rescaled.matrix(), raw.matrix());
    scale.accept(0.1 * k, raw);
  }
  Matrix6d covariance = Matrix6d::Identity();
  EXPECT_EQ(scale.rescaled(covariance), covariance);
}

TEST(OdometryScale, AMonocularScaleErrorIsFoundAndTakenOut) {
  for (double error : {0.08, -0.07}) {
    SCOPED_TRACE(::testing::Message() << "VIO scale error " << error);
    OdometryScale scale{OdometryScaleParams{}};
    const ScaledVio vio(error, someFrame());
    std::vector<Eigen::Isometry3d> rescaled;
    const std::vector<double> applied = fly(scale, vio, 1200, nullptr, &rescaled);
    ASSERT_TRUE(scale.applied());
    // Needs min_pairs (10) steps of 2 m first; then at most 2 % per keyframe.
    EXPECT_GE(*scale.appliedAt(), 0.1 * 20 * 10 - 1e-9);
    for (size_t i = 1; i < applied.size(); ++i) {
      EXPECT_LE(std::abs(applied[i] - applied[i - 1]), 0.02 * applied[i - 1] + 1e-12) << "update " << i;
    }
    // With the truth as the graph, the estimate is the truth's ratio at once: 1 / (1 + error).
    EXPECT_NEAR(scale.scale(), 1.0 / (1.0 + error), 1e-9);
    const OdometryScaleReport report = scale.report();
    EXPECT_TRUE(report.applied);
    EXPECT_NEAR(report.estimate, 1.0 / (1.0 + error), 1e-9);
    EXPECT_LT(report.sigma, 1e-9);
    // The rescaled VIO now moves as the truth does: the last 2 m step, in the body frame.
    const size_t last = rescaled.size() - 1;
    const Eigen::Vector3d moved = (rescaled[last - 20].inverse() * rescaled[last]).translation();
    const Eigen::Vector3d truth = (truthAt(static_cast<int>(last) - 20).inverse() * truthAt(static_cast<int>(last))).translation();
    EXPECT_LT((moved - truth).norm(), 1e-9);
    // Covariances follow the translation: S Σ S with S = diag(s I, I).
    const Matrix6d covariance = scale.rescaled(Matrix6d::Identity());
    EXPECT_NEAR(covariance(0, 0), scale.scale() * scale.scale(), 1e-12);
    EXPECT_NEAR(covariance(5, 5), 1.0, 1e-12);
  }
}

TEST(OdometryScale, AChangeOfScaleBendsNoPastPoseAndLeavesNoJump) {
  OdometryScale scale{OdometryScaleParams{}};
  const ScaledVio vio(0.08, someFrame());
  std::vector<Eigen::Isometry3d> rescaled;
  fly(scale, vio, 600, nullptr, &rescaled);
  ASSERT_TRUE(scale.applied());
  // Each change of scale starts from where the rescaled path was (a knot at the last sample): consecutive samples
  // are never further apart than the raw step times the scales in force (here between 1 and 1 / 1.08), so a change
  // makes no jump; and the rotation is the VIO's own.
  for (size_t k = 1; k < rescaled.size(); ++k) {
    const double step = (rescaled[k].translation() - rescaled[k - 1].translation()).norm();
    const double raw_step = (vio.at(static_cast<int>(k)).translation() - vio.at(static_cast<int>(k) - 1).translation()).norm();
    EXPECT_LE(step, raw_step * 1.0 + 1e-9) << "sample " << k;  // the scale here only shrinks (error > 0)
    EXPECT_GE(step, raw_step / 1.08 - 1e-9) << "sample " << k;
    EXPECT_EQ(rescaled[k].linear(), vio.at(static_cast<int>(k)).linear());
  }
}

TEST(OdometryScale, AGoodVioIsLeftAsItIs) {
  for (double error : {0.01, -0.015}) {
    SCOPED_TRACE(::testing::Message() << "VIO scale error " << error);
    OdometryScale scale{OdometryScaleParams{}};
    const ScaledVio vio(error, someFrame());
    fly(scale, vio, 1200);
    EXPECT_FALSE(scale.applied());
    EXPECT_EQ(scale.scale(), 1.0);
    EXPECT_GT(scale.updates(), 0);
    EXPECT_NEAR(scale.lastEstimate(), 1.0 / (1.0 + error), 1e-9);  // estimated, not applied
  }
}

TEST(OdometryScale, AHoveringDroneGivesNoEstimate) {
  OdometryScale scale{OdometryScaleParams{}};
  Pairs keyframes;
  for (int k = 0; k < 40; ++k) {
    Eigen::Isometry3d raw = truthAt(0);
    raw.translation().x() += 0.01 * k;  // 1 cm per keyframe: below min_step
    scale.accept(0.1 * k, raw);
    Eigen::Isometry3d graph = raw;
    graph.translation().x() *= 1.5;
    keyframes.push_back({0.1 * k, graph, raw});
    EXPECT_FALSE(scale.update(keyframes, 0.1 * k));
  }
  EXPECT_EQ(scale.updates(), 0);
  EXPECT_FALSE(scale.applied());
}

TEST(OdometryScale, OffMeansTheVioAsItIs) {
  OdometryScaleParams params;
  params.enabled = false;
  OdometryScale scale{params};
  const ScaledVio vio(0.08, someFrame());
  std::vector<Eigen::Isometry3d> rescaled;
  fly(scale, vio, 600, nullptr, &rescaled);
  EXPECT_FALSE(scale.applied());
  EXPECT_EQ(scale.updates(), 0);
  for (size_t k = 0; k < rescaled.size(); ++k) EXPECT_EQ(rescaled[k].matrix(), vio.at(static_cast<int>(k)).matrix());
  EXPECT_FALSE(scale.report().enabled);
}

}  // namespace
}  // namespace dualgraph
