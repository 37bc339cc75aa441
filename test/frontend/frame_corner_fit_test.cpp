// SPDX-License-Identifier: MIT
// fitFrameOnCorners: the frame a search locked on, fitted again on exact corners, comes back to the truth from a
// start 0.5 m and 4° off, whichever side each gate was seen from and however its corners were labelled; on noisy
// corners its covariance covers its error; too few corners, or detections without four corners, leave the start.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dualgraph/frontend/gates/frame_corner_fit.h"

namespace dualgraph {
namespace corner_fit_test {

constexpr double kFocal = 400.0;  // [px]: σ = 1 px in normalised coordinates is 1 / kFocal

Eigen::Isometry3d yawPose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

struct Scene {
  GateMap map;
  Eigen::Isometry3d world_T_odom = yawPose(3.0, -2.0, 0.1, 0.7);
  Eigen::Isometry3d body_T_camera = Eigen::Isometry3d::Identity();
  Scene() {
    map.world_T_gate[3] = yawPose(0.0, -1.3, 1.2, 0.0);
    map.world_T_gate[4] = yawPose(0.0, 1.3, 1.2, 0.02);
    // The camera looks along the body's x: its z is the body's x, its x the body's −y, its y the body's −z.
    body_T_camera.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  }
};

/// The window a drone flying from x = −9 to −5 m towards both gates sees: 10 instants, each gate once, corners
/// exact or with `pixel_noise` px of Gaussian noise; each gate's observation in its own frame turned by Rz(π)
/// when `from_behind`; with `quarter_off`, every other instant's corners labelled a quarter turn off (corner j is
/// the image of corner j + 1, as a detector that orders corners by the image labels them when the drone banks),
/// its PnP gate frame turned with them.
std::vector<FrameFitDetection, Eigen::aligned_allocator<FrameFitDetection>> window(const Scene& scene, double pixel_noise,
                                                                                  std::mt19937& random, bool from_behind,
                                                                                  bool quarter_off = false) {
  std::vector<FrameFitDetection, Eigen::aligned_allocator<FrameFitDetection>> out;
  std::normal_distribution<double> noise(0.0, pixel_noise / kFocal);
  const Eigen::Matrix3d turn = from_behind ? Eigen::Matrix3d(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()))
                                           : Eigen::Matrix3d::Identity();
  for (int k = 0; k < 10; ++k) {
    const Eigen::Isometry3d world_T_body = yawPose(-9.0 + 0.4 * k, 0.2 * std::sin(k), 1.0, 0.05 * std::cos(k));
    const Eigen::Isometry3d odom_T_body = scene.world_T_odom.inverse() * world_T_body;
    const bool relabelled = quarter_off && k % 2 == 1;
    for (const auto& [id, world_T_gate] : scene.map.world_T_gate) {
      GateCornerRays rays;
      rays.count = 4;
      rays.body_T_camera = scene.body_T_camera;
      const double h = 0.75;
      rays.p_gate << 0, 0, 0, 0, -h, h, h, -h, h, h, -h, -h;
      rays.p_gate = turn.transpose() * rays.p_gate;  // the same corners, in the turned gate frame
      for (int j = 0; j < 4; ++j) {
        const int imaged = relabelled ? (j + 1) % 4 : j;
        const Eigen::Vector3d p_camera =
            (world_T_body * scene.body_T_camera).inverse() * (world_T_gate * (turn * rays.p_gate.col(imaged)));
        rays.normalized.col(j) = p_camera.head<2>() / p_camera.z() + Eigen::Vector2d(noise(random), noise(random));
        rays.covariance[j] = Eigen::Matrix2d::Identity() * std::pow(std::max(pixel_noise, 1.0) / kFocal, 2);
      }
      Eigen::Isometry3d body_T_gate = world_T_body.inverse() * world_T_gate;
      const Eigen::Matrix3d relabel = relabelled ? Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix()
                                                 : Eigen::Matrix3d::Identity();
      body_T_gate.linear() = body_T_gate.linear() * relabel * turn;
      GateObservation observation = GateObservation::pose(0.1 * k, from_behind ? -1 : id, body_T_gate,
                                                          Matrix6d::Identity() * 1e-4);
      observation.corner_rays = rays;
      out.push_back(FrameFitDetection{odom_T_body, observation});
    }
  }
  return out;
}

double yawOf(const Eigen::Isometry3d& pose) { return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0)); }

TEST(FrameCornerFit, ExactCornersBringTheFrameBackFromHalfAMetreAndFourDegrees) {
  const Scene scene;
  const Eigen::Isometry3d start = scene.world_T_odom * yawPose(0.4, -0.3, 0.1, 4.0 * M_PI / 180.0);
  for (bool from_behind : {false, true}) {
    SCOPED_TRACE(from_behind ? "seen from behind, ids unknown" : "seen from the front");
    std::mt19937 random(1);
    const FrameCornerFit fit = fitFrameOnCorners(window(scene, 0.0, random, from_behind), scene.map, start, 1.0);
    ASSERT_TRUE(fit.refined);
    EXPECT_EQ(fit.detections, 20);
    EXPECT_EQ(fit.corners, 80);
    EXPECT_GT(fit.rms_before, 1.0);  // whitened (1 px) and Huber-bounded
    EXPECT_LT(fit.rms_after, 1e-4);
    EXPECT_LT((fit.world_T_odom.translation() - scene.world_T_odom.translation()).norm(), 1e-6);
    EXPECT_LT(std::abs(yawOf(fit.world_T_odom) - yawOf(scene.world_T_odom)), 1e-7);
    EXPECT_TRUE(fit.covariance.allFinite());
  }
}

TEST(FrameCornerFit, CornersLabelledAQuarterTurnOffFitAsWell) {
  const Scene scene;
  const Eigen::Isometry3d start = scene.world_T_odom * yawPose(0.4, -0.3, 0.1, 4.0 * M_PI / 180.0);
  for (bool from_behind : {false, true}) {
    SCOPED_TRACE(from_behind ? "seen from behind, ids unknown" : "seen from the front");
    std::mt19937 random(1);
    const FrameCornerFit fit =
        fitFrameOnCorners(window(scene, 0.0, random, from_behind, true), scene.map, start, 1.0);
    ASSERT_TRUE(fit.refined);
    EXPECT_EQ(fit.corners, 80);
    EXPECT_LT(fit.rms_after, 1e-4);  // every corner on its own map corner: none left to the Huber weight
    EXPECT_LT((fit.world_T_odom.translation() - scene.world_T_odom.translation()).norm(), 1e-6);
    EXPECT_LT(std::abs(yawOf(fit.world_T_odom) - yawOf(scene.world_T_odom)), 1e-7);
  }
}

TEST(FrameCornerFit, ItsCovarianceCoversItsErrorOnNoisyCorners) {
  const Scene scene;
  const Eigen::Isometry3d start = scene.world_T_odom * yawPose(0.2, 0.2, 0.0, -2.0 * M_PI / 180.0);
  double nees = 0.0;
  const int trials = 40;
  for (int trial = 0; trial < trials; ++trial) {
    std::mt19937 random(100 + trial);
    const FrameCornerFit fit = fitFrameOnCorners(window(scene, 1.0, random, false), scene.map, start, 1.0);
    ASSERT_TRUE(fit.refined) << trial;
    Eigen::Vector4d error;
    error.head<3>() = fit.world_T_odom.translation() - scene.world_T_odom.translation();
    error(3) = std::remainder(yawOf(fit.world_T_odom) - yawOf(scene.world_T_odom), 2.0 * M_PI);
    nees += error.dot(fit.covariance.ldlt().solve(error));
  }
  nees /= trials;
  EXPECT_GT(nees, 4.0 * 0.5);  // 4 dof: consistent is 4
  EXPECT_LT(nees, 4.0 * 1.5);
}

TEST(FrameCornerFit, TooFewCornersOrPartialGatesLeaveTheStart) {
  const Scene scene;
  const Eigen::Isometry3d start = scene.world_T_odom * yawPose(0.4, -0.3, 0.1, 0.05);
  std::mt19937 random(1);
  auto detections = window(scene, 0.0, random, false);
  detections.resize(2);  // 8 corners
  FrameCornerFit fit = fitFrameOnCorners(detections, scene.map, start, 1.0);
  EXPECT_FALSE(fit.refined);
  EXPECT_TRUE(fit.world_T_odom.isApprox(start));
  detections = window(scene, 0.0, random, false);
  for (FrameFitDetection& detection : detections) detection.observation.corner_rays.count = 3;
  fit = fitFrameOnCorners(detections, scene.map, start, 1.0);
  EXPECT_FALSE(fit.refined);
  EXPECT_EQ(fit.detections, 0);
  // A start so far off that no detection lies within max_distance of a map gate: nothing to fit.
  fit = fitFrameOnCorners(window(scene, 0.0, random, false), scene.map, scene.world_T_odom * yawPose(5.0, 0.0, 0.0, 0.0), 1.0);
  EXPECT_FALSE(fit.refined);
  EXPECT_EQ(fit.detections, 0);
}

}  // namespace corner_fit_test
}  // namespace dualgraph
