// SPDX-License-Identifier: MIT
// Flight: a simulated drone flying laps of a closed path under speed and acceleration limits.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "core/status.h"
#include "frontend/simulation/closed_curve.h"
#include "frontend/gates/track.h"

namespace dualgraph {

/// How a simulated racing drone flies its reference path.
struct FlightParams {
  int laps = 1;                                 ///< ≥ 1
  double max_speed = 8.0;                       ///< [m/s], > 0
  double max_lateral_acceleration = 8.0;        ///< [m/s²], > 0: caps the speed in turns, v ≤ √(a / κ)
  double max_longitudinal_acceleration = 3.5;   ///< [m/s²], > 0: braking and accelerating
  double speed_smoothing = 1.0;                 ///< [m]: width of the moving average on the speed profile (≥ 0)
  double gravity = 9.81;                        ///< [m/s²]
};

/// The true state of the drone at time t. Body frame FLU (x forward along the path, y left, z up
/// along the thrust): a quadrotor tilts its thrust axis along acceleration + gravity, so turns are
/// banked and braking pitches up. world_T_body maps body points to the world frame.
struct FlightState {
  double t = 0.0;         ///< [s] since take-off
  double distance = 0.0;  ///< [m] flown since take-off
  int lap = 0;            ///< 0-based lap being flown
  Eigen::Vector3d position = Eigen::Vector3d::Zero();      ///< world [m]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      ///< world [m/s]
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  ///< world [m/s²], without gravity
  Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// A flight of `laps` laps along a closed path, starting and ending at rest at the path's u = 0.
///
/// Speed profile: v(s) = min(max_speed, √(max_lateral_acceleration / κ(s))) along the distance s, then
/// limited by max_longitudinal_acceleration forwards (from rest) and backwards (to rest), then
/// smoothed by a moving average. Between profile samples the drone moves with constant acceleration,
/// so s(t) is C¹; position(t) = path(u(s)) with u(s) the inverse arc length (cubic Hermite on a table
/// of 20000 samples per lap). Velocity and acceleration are central differences of position over
/// ±1 ms, so they are those of the position actually reported.
class Flight {
 public:
  /// An empty flight (duration and length 0, at() gives the default state); use plan().
  Flight() = default;
  static Result<Flight> plan(const TrackPath& path, const FlightParams& params);

  double duration() const { return times_.empty() ? 0.0 : times_.back(); }  ///< [s]
  double length() const { return lap_length_ * params_.laps; }  ///< [m]
  double lapLength() const { return lap_length_; }  ///< [m]
  /// The state at t, clamped to [0, duration()].
  FlightState at(double t) const;
  /// Position at distance s ∈ [0, length()] [m] (the path itself, independent of time).
  Eigen::Vector3d positionAtDistance(double s) const;
  /// The highest speed of the profile [m/s].
  double topSpeed() const;

 private:
  double distanceAt(double t) const;

  FlightParams params_;
  std::shared_ptr<const ClosedCurve> curve_;
  double lap_length_ = 0.0;
  std::vector<double> lap_u_;          ///< per lap sample: curve parameter, 0 … 1
  std::vector<double> lap_s_;          ///< per lap sample: arc length from u = 0 [m]
  std::vector<double> lap_du_ds_;      ///< per lap sample: du/ds [1/m]
  std::vector<double> profile_speed_;  ///< over the whole flight, one per distance step [m/s]
  std::vector<double> times_;          ///< time at each profile sample [s]
};

}  // namespace dualgraph
