// SPDX-License-Identifier: MIT
#pragma once

// A small synthetic race for tests and benchmarks: laps of a circle through square gates, a drifting
// VIO (scale error, yaw-rate bias and random walk) and noisy SE(3) gate detections, all from a fixed seed.
// Header-only on purpose: test/ and bench/ both use it; the full simulator lives in tools/ (issue 4).

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "dualgraph/dual_graph/gate_map.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph::testing {

struct SyntheticRaceOptions {
  double radius = 10.0;            ///< [m]
  double speed = 8.0;              ///< [m/s]
  int laps = 3;
  int gates = 4;                   ///< evenly spaced on the circle
  double odometry_rate = 100.0;    ///< [Hz]
  double detection_rate = 30.0;    ///< [Hz]
  double scale_error = 0.03;       ///< VIO translation scale error (fraction)
  double yaw_bias = 0.02;          ///< VIO yaw-rate bias [rad/s]
  double odom_noise_t = 0.02;      ///< random walk [m/√s]
  double odom_noise_r = 0.005;     ///< random walk [rad/√s]
  double detection_sigma_t = 0.10; ///< detection noise [m] (at 5 m, grows linearly with range)
  double detection_sigma_r = 0.03; ///< [rad]
  double max_range = 12.0;         ///< gates farther than this are not seen [m]
  /// Give every odometry sample a relative covariance: the random walk's plus the biases treated as a
  /// random walk with a 1 s correlation time (an honest bound on the drift over a keyframe interval).
  bool with_covariance = false;
  double half_fov = 1.0;           ///< gates more than this off the heading are not seen [rad]
  unsigned seed = 42;
};

struct SyntheticRace {
  GateMap map;
  std::vector<OdometrySample> odometry;
  std::vector<GateObservation> observations;  ///< in time order
  std::vector<double> truth_t;
  std::vector<Eigen::Isometry3d> world_T_body_truth;  ///< at the odometry instants
};

/// The true pose on the circle at time t: tangent heading, a gentle height wave.
inline Eigen::Isometry3d syntheticTruth(const SyntheticRaceOptions& o, double t) {
  const double phi = o.speed / o.radius * t;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(o.radius * std::cos(phi), o.radius * std::sin(phi), 1.5 + 0.3 * std::sin(2 * phi));
  pose.linear() = so3Exp(Eigen::Vector3d(0, 0, phi + M_PI / 2));
  return pose;
}

inline SyntheticRace makeSyntheticRace(const SyntheticRaceOptions& o) {
  SyntheticRace race;
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto gaussian6 = [&](double st, double sr) {
    Vector6d v;
    for (int i = 0; i < 6; ++i) v[i] = normal(rng) * (i < 3 ? st : sr);
    return v;
  };
  for (int g = 0; g < o.gates; ++g) {
    const double phi = 2 * M_PI * (g + 0.5) / o.gates;
    Eigen::Isometry3d gate = syntheticTruth(o, phi * o.radius / o.speed);
    gate.translation().z() = 1.5;
    race.map.world_T_gate[g] = gate;
  }
  const double duration = o.laps * 2 * M_PI * o.radius / o.speed;
  const double dt = 1.0 / o.odometry_rate;
  Eigen::Isometry3d odom = syntheticTruth(o, 0.0);
  Eigen::Isometry3d previous_truth = odom;
  double next_detection = 0.5 / o.detection_rate;
  for (int k = 0; k * dt <= duration; ++k) {
    const double t = k * dt;
    const Eigen::Isometry3d truth = syntheticTruth(o, t);
    if (k > 0) {
      Eigen::Isometry3d increment = previous_truth.inverse() * truth;
      increment.translation() *= 1.0 + o.scale_error;
      Vector6d drift = gaussian6(o.odom_noise_t * std::sqrt(dt), o.odom_noise_r * std::sqrt(dt));
      drift[5] += o.yaw_bias * dt;
      odom = odom * increment * se3Exp(drift);
    }
    previous_truth = truth;
    race.truth_t.push_back(t);
    race.world_T_body_truth.push_back(truth);
    OdometrySample sample;
    sample.t = t;
    sample.odom_T_body = odom;
    if (o.with_covariance && k > 0) {
      Vector6d variance;
      const double scale_rate = o.scale_error * o.speed;
      variance << Eigen::Vector3d::Constant((o.odom_noise_t * o.odom_noise_t + scale_rate * scale_rate) * dt),
          Eigen::Vector3d::Constant((o.odom_noise_r * o.odom_noise_r + o.yaw_bias * o.yaw_bias) * dt);
      sample.relative_covariance = Matrix6d(variance.asDiagonal());
    }
    race.odometry.push_back(sample);
    // Detections at their own rate, between odometry samples.
    while (next_detection <= t + dt && next_detection <= duration) {
      const Eigen::Isometry3d body = syntheticTruth(o, next_detection);
      for (const auto& [id, world_T_gate] : race.map.world_T_gate) {
        const Eigen::Isometry3d body_T_gate = body.inverse() * world_T_gate;
        const Eigen::Vector3d p = body_T_gate.translation();
        if (p.norm() > o.max_range || p.x() <= 0 || std::atan2(std::hypot(p.y(), p.z()), p.x()) > o.half_fov) continue;
        const double scale = std::max(1.0, p.norm() / 5.0);
        Vector6d sigma;
        sigma << Eigen::Vector3d::Constant(o.detection_sigma_t * scale), Eigen::Vector3d::Constant(o.detection_sigma_r);
        const Eigen::Isometry3d measured = body_T_gate * se3Exp(gaussian6(sigma[0], sigma[3]));
        race.observations.push_back(
            GateObservation::pose(next_detection, id, measured, Matrix6d(sigma.cwiseAbs2().asDiagonal())));
      }
      next_detection += 1.0 / o.detection_rate;
    }
  }
  return race;
}

/// Root-mean-square position error [m] of `poses` against the truth at the same indices (no alignment:
/// the world frame is known).
inline double positionRmse(const std::vector<Eigen::Isometry3d>& poses, const std::vector<Eigen::Isometry3d>& truth) {
  double sum = 0.0;
  for (size_t k = 0; k < poses.size(); ++k) sum += (poses[k].translation() - truth[k].translation()).squaredNorm();
  return std::sqrt(sum / static_cast<double>(poses.size()));
}

}  // namespace dualgraph::testing
