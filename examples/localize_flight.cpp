// SPDX-License-Identifier: MIT
// The Localizer from an external project: three laps of a 10 m circle at 5 m/s through four gates, with an
// odometry whose yaw drifts by 0.02 rad/s, and gate pose detections (seeded noise) whenever a gate is
// 1–8 m ahead. Prints the corrected and the raw odometry error at the end and, given a path, writes the
// corrected trajectory as TUM (frontend/io/trajectory_io.h). Exit code 0 when the correction beats the drift.
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/frontend/io/trajectory_io.h"
#include "dualgraph/types/se3_math.h"

namespace {

using dualgraph::Matrix6d;

constexpr double kRadius = 10.0;  // [m]
constexpr double kSpeed = 5.0;    // [m/s]
constexpr double kHeight = 1.5;   // [m]

// A pose on the circle at angle phi, x axis along the direction of flight (counter-clockwise), z up.
Eigen::Isometry3d onCircle(double phi) {
  Eigen::Isometry3d world_T_x = Eigen::Isometry3d::Identity();
  world_T_x.translation() = Eigen::Vector3d(kRadius * std::cos(phi), kRadius * std::sin(phi), kHeight);
  world_T_x.linear() = Eigen::AngleAxisd(phi + M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return world_T_x;
}

int fail(const std::string& message) {
  std::cerr << "localize_flight: " << message << "\n";
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  dualgraph::GateMap map;
  for (int g = 0; g < 4; ++g) map.world_T_gate[g] = onCircle(M_PI / 4 + g * M_PI / 2);
  auto localizer = dualgraph::Localizer::create(dualgraph::LocalizerParams{}, map);
  if (!localizer.ok()) return fail(localizer.status().message());

  std::mt19937 rng(3);
  std::normal_distribution<double> unit(0.0, 1.0);
  Matrix6d detection_covariance = Matrix6d::Zero();
  detection_covariance.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02, 0.02 * 0.02, 0.02 * 0.02;
  const double omega = kSpeed / kRadius, duration = 3 * 2 * M_PI / omega, yaw_drift = 0.02;  // [rad/s], [s], [rad/s]
  std::vector<std::pair<double, Eigen::Isometry3d>> corrected;
  double vio_error = 0.0, corrected_error = 0.0;
  for (int k = 0; k * 0.02 <= duration; ++k) {
    const double t = k * 0.02;  // 50 Hz odometry; after every 5th sample, the detections at its time
    const Eigen::Isometry3d world_T_body = onCircle(omega * t);
    const Eigen::Isometry3d odom_T_body =
        Eigen::Isometry3d(Eigen::AngleAxisd(yaw_drift * t, Eigen::Vector3d::UnitZ())) * world_T_body;
    dualgraph::OdometrySample sample;
    sample.t = t;
    sample.odom_T_body = odom_T_body;
    auto pose = (*localizer)->addOdometry(sample);
    if (!pose.ok()) return fail(pose.status().message());
    if (k % 5 == 0) {
      for (const auto& [id, world_T_gate] : map.world_T_gate) {
        const Eigen::Isometry3d body_T_gate = world_T_body.inverse() * world_T_gate;
        const double ahead = body_T_gate.translation().x();
        if (ahead < 1.0 || ahead > 8.0) continue;
        dualgraph::Vector6d noise;
        for (int i = 0; i < 6; ++i) noise[i] = unit(rng) * std::sqrt(detection_covariance(i, i));
        const auto observation = dualgraph::GateObservation::pose(t, id, body_T_gate * dualgraph::se3Exp(noise),
                                                                  detection_covariance);
        if (dualgraph::Status s = (*localizer)->addObservation(observation); !s.ok()) return fail(s.message());
      }
    }
    corrected.emplace_back(t, pose->world_T_body);
    corrected_error = (pose->world_T_body.translation() - world_T_body.translation()).norm();
    vio_error = (odom_T_body.translation() - world_T_body.translation()).norm();
  }
  if (dualgraph::Status s = (*localizer)->finish(); !s.ok()) return fail(s.message());
  const auto& stats = (*localizer)->keyframeStats();
  std::cout << "localize_flight: " << corrected.size() << " poses, " << stats.size() << " optimisations, main graph "
            << stats.back().main_vertices << " nodes / " << stats.back().main_edges << " edges; final position error "
            << corrected_error << " m (odometry " << vio_error << " m)\n";
  if (argc > 1) {
    if (dualgraph::Status s = dualgraph::writeTum(argv[1], corrected); !s.ok()) return fail(s.message());
    std::cout << "  wrote " << argv[1] << "\n";
  }
  return corrected_error < 0.25 * vio_error ? 0 : fail("the correction does not beat the odometry's drift");
}
