// SPDX-License-Identifier: MIT
// The first lock's corner fit (frontend/gates/frame_corner_fit.h) on a synthetic window: a drone flying 4 m towards
// two gates 2.6 m apart, each gate seen at every instant, corners with 1 px of Gaussian noise (focal 400 px, fixed
// seed), the fit started 0.5 m and 4° off. Argument: instants in the window (each gives 8 corners). A run fits once
// per flight, on the sample that locks: its cost is that sample's latency on the caller's thread.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "dualgraph/frontend/gates/frame_corner_fit.h"

namespace dualgraph {
namespace {

Eigen::Isometry3d yawPose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

using Window = std::vector<FrameFitDetection, Eigen::aligned_allocator<FrameFitDetection>>;

Window simulateWindow(const GateMap& map, const Eigen::Isometry3d& world_T_odom, int instants) {
  constexpr double kFocal = 400.0;  // [px]
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 1.0 / kFocal);
  Eigen::Isometry3d body_T_camera = Eigen::Isometry3d::Identity();
  body_T_camera.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // the camera looks along the body's x
  Window window;
  for (int k = 0; k < instants; ++k) {
    const double along = static_cast<double>(k) / std::max(1, instants - 1);
    const Eigen::Isometry3d world_T_body = yawPose(-9.0 + 4.0 * along, 0.2 * std::sin(7.0 * along), 1.0, 0.05 * std::cos(7.0 * along));
    for (const auto& [id, world_T_gate] : map.world_T_gate) {
      GateCornerRays rays;
      rays.count = 4;
      rays.body_T_camera = body_T_camera;
      const double h = 0.75;
      rays.p_gate << 0, 0, 0, 0, -h, h, h, -h, h, h, -h, -h;
      for (int j = 0; j < 4; ++j) {
        const Eigen::Vector3d p_camera = (world_T_body * body_T_camera).inverse() * (world_T_gate * rays.p_gate.col(j));
        rays.normalized.col(j) = p_camera.head<2>() / p_camera.z() + Eigen::Vector2d(noise(random), noise(random));
        rays.covariance[j] = Eigen::Matrix2d::Identity() / (kFocal * kFocal);
      }
      GateObservation observation = GateObservation::pose(0.05 * k, id, world_T_body.inverse() * world_T_gate,
                                                          Matrix6d::Identity() * 1e-4);
      observation.corner_rays = rays;
      window.push_back(FrameFitDetection{world_T_odom.inverse() * world_T_body, observation});
    }
  }
  return window;
}

void BM_FrameCornerFit(benchmark::State& state) {
  GateMap map;
  map.world_T_gate[3] = yawPose(0.0, -1.3, 1.2, 0.0);
  map.world_T_gate[4] = yawPose(0.0, 1.3, 1.2, 0.02);
  const Eigen::Isometry3d world_T_odom = yawPose(3.0, -2.0, 0.1, 0.7);
  const Window window = simulateWindow(map, world_T_odom, static_cast<int>(state.range(0)));
  const Eigen::Isometry3d start = world_T_odom * yawPose(0.4, -0.3, 0.1, 4.0 * M_PI / 180.0);
  FrameCornerFit fit;
  for (auto _ : state) {
    fit = fitFrameOnCorners(window, map, start, 1.0);
    benchmark::DoNotOptimize(&fit);
  }
  if (!fit.refined) return state.SkipWithError("the fit did not refine the frame");
  state.counters["corners"] = fit.corners;
  state.counters["error_m"] = (fit.world_T_odom.translation() - world_T_odom.translation()).norm();
}
BENCHMARK(BM_FrameCornerFit)->ArgName("instants")->Arg(10)->Arg(40)->Arg(120)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dualgraph
