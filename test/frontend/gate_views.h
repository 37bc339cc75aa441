// SPDX-License-Identifier: MIT
// Test helper: RATM's radial-tangential camera and a gate placed in its view by range, direction and turn.
#pragma once

#include <cmath>
#include <random>

#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph::testing {

/// RATM's calibration (calib_ap-ellipse-lemniscate.json), radial-tangential, 640×480.
inline CameraModel ratmRadtanCamera() {
  CameraModel camera = CameraModel::pinhole(289.88, 387.06, 316.58, 241.87, 640, 480, CameraModel::Distortion::kRadTan);
  camera.distortion << -0.2814528, 0.1091225, 0.0001824, 0.0000679, -0.0232501;
  return camera;
}

/// camera_T_gate: the gate centred at `range` [m] along (azimuth, elevation) [rad] off the optical axis, its normal
/// turned by `yaw` and `pitch` away from the line of sight and `roll` about it (front side, upright in the image at
/// zero).
inline Eigen::Isometry3d gateView(double range, double azimuth, double elevation, double yaw, double pitch,
                                  double roll) {
  const Eigen::Vector3d direction(std::sin(azimuth) * std::cos(elevation), -std::sin(elevation),
                                  std::cos(azimuth) * std::cos(elevation));
  const Eigen::Vector3d up(0, -1, 0);  // the image's up
  Eigen::Matrix3d facing;              // gate x along the line of sight, z towards the image's up
  facing.col(0) = direction;
  facing.col(2) = (up - up.dot(direction) * direction).normalized();
  facing.col(1) = facing.col(2).cross(facing.col(0));
  Eigen::Isometry3d camera_T_gate = Eigen::Isometry3d::Identity();
  camera_T_gate.linear() = facing * so3Exp(Eigen::Vector3d(0, 0, yaw)) * so3Exp(Eigen::Vector3d(0, pitch, 0)) *
                           so3Exp(Eigen::Vector3d(roll, 0, 0));
  camera_T_gate.translation() = range * direction;
  return camera_T_gate;
}

/// Random gate views and corner noise for the PnP statistics tests, deterministic for a seed: the gate at a range the
/// caller draws, up to 20° sideways and 15° vertically off the optical axis, its normal up to 60° off the line of
/// sight and tilted up to 10° either way.
class RandomGateViews {
 public:
  explicit RandomGateViews(unsigned seed) : rng_(seed) {}
  /// Uniform in [0, 1).
  double uniform() { return unit_(rng_); }
  /// camera_T_gate at `range` [m] (gateView above), the angles drawn in a fixed order.
  Eigen::Isometry3d at(double range) {
    constexpr double kDeg = M_PI / 180.0;
    const double azimuth = (uniform() - 0.5) * 40 * kDeg;
    const double elevation = (uniform() - 0.5) * 30 * kDeg;
    const double yaw = (uniform() - 0.5) * 120 * kDeg;
    const double pitch = (uniform() - 0.5) * 20 * kDeg;
    const double roll = (uniform() - 0.5) * 20 * kDeg;
    return gateView(range, azimuth, elevation, yaw, pitch, roll);
  }
  /// Gaussian noise of σ [px] on every coordinate of `pixels` (a 2×4 matrix).
  template <typename Pixels>
  void addNoise(double sigma, Pixels& pixels) {
    for (int i = 0; i < 8; ++i) pixels(i % 2, i / 2) += sigma * normal_(rng_);
  }

 private:
  std::mt19937 rng_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace dualgraph::testing
