// SPDX-License-Identifier: MIT
// Flight: a simulated drone flying laps of a closed path under speed and acceleration limits.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/simulation/closed_curve.h"
#include "dualgraph/frontend/gates/track.h"

namespace dualgraph {

/// How a simulated racing drone flies its reference path.
struct FlightParams {
  int laps = 1;                                 ///< ≥ 1
  double max_speed = 8.0;                       ///< [m/s], > 0
  double max_lateral_acceleration = 8.0;        ///< [m/s²], > 0: caps the speed in turns, v ≤ √(a / κ)
  double max_longitudinal_acceleration = 3.5;   ///< [m/s²], > 0: braking and accelerating
  double speed_smoothing = 1.0;                 ///< [m]: width of the moving average on the speed profile (≥ 0)
  double gravity = 9.81;                        ///< [m/s²]
  /// Laps that vary in speed: each lap's max_speed and max_lateral_acceleration are scaled by a factor drawn
  /// uniformly in [1 − v, 1 + v] for that lap (blended halfway to the neighbouring lap's where two laps meet, over
  /// lapWindow, so the caps do not jump); 0 ≤ v < 0.5 (0: every lap alike).
  double lap_speed_variation = 0.0;
  /// Laps that vary in line [m], ≥ 0: each lap flies the reference path displaced along its horizontal left normal
  /// by W(x) (a + b cos 2πx) / 2, a and b drawn uniformly in [−w, w] per lap (so within w), and vertically by
  /// W(x) (c + d cos 2πx) / 2, c and d in [−w/3, w/3]; x is the fraction of the lap and W (lapWindow) makes the
  /// offset and its first two derivatives vanish where a lap starts and ends; the horizontal offset fades out in
  /// tight turns (LapLines in closed_curve.h has the formula). 0: the path itself.
  double lap_line_variation = 0.0;
  /// Seed of the per-lap draws (5 per lap: speed factor, two horizontal and two vertical amplitudes); nothing is
  /// drawn when both variations are 0. simulateRace sets it from its own seed.
  std::uint64_t variation_seed = 0;
};

/// How one lap departs from the reference: its speed factor and the amplitudes of its line's offset.
struct LapVariation {
  double speed_factor = 1.0;                            ///< scales max_speed and max_lateral_acceleration
  Eigen::Vector2d lateral = Eigen::Vector2d::Zero();    ///< (a, b): the horizontal offset's amplitudes [m]
  Eigen::Vector2d vertical = Eigen::Vector2d::Zero();   ///< (c, d): the vertical offset's amplitudes [m]
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
/// Each lap flies a line: the reference path itself, or with lap_line_variation the path displaced by
/// that lap's offset (FlightParams). Speed profile: v(s) = min(f max_speed, √(f max_lateral_acceleration / κ(s)))
/// along the distance s flown (κ the curvature of the lap's line, f the lap's speed factor, 1 without
/// lap_speed_variation), then limited by max_longitudinal_acceleration forwards (from rest) and backwards (to
/// rest) over the whole flight, so across lap boundaries too, then smoothed by a moving average. Between profile
/// samples the drone moves with constant acceleration, so s(t) is C¹; position(t) = line(u(s)) with u(s) the
/// inverse arc length (cubic Hermite on a table of 20000 samples per lap). Velocity and acceleration are central
/// differences of position over ±1 ms, so they are those of the position actually reported (and the banked
/// attitude follows the displaced line).
class Flight {
 public:
  /// An empty flight (duration and length 0, at() gives the default state); use plan().
  Flight() = default;
  static Result<Flight> plan(const TrackPath& path, const FlightParams& params);

  double duration() const { return times_.empty() ? 0.0 : times_.back(); }  ///< [s]
  /// The distance flown over all laps [m] (laps × lapLength() without lap_line_variation).
  double length() const { return lap_start_.empty() ? 0.0 : lap_start_.back(); }
  /// The reference path's lap length [m]. With lap_line_variation each lap's line is a little longer or
  /// shorter: lapStartDistance gives where each lap starts along the distance flown.
  double lapLength() const { return lap_length_; }
  /// The distance flown when lap k (0 … laps; laps: the end of the flight) starts [m].
  double lapStartDistance(int k) const;
  /// The time at which lap k (0 … laps; laps: the end of the flight) starts [s].
  double lapStartTime(int k) const;
  /// Lap k's speed factor and line offset (neutral without variation); k in [0, laps).
  LapVariation lapVariation(int k) const;
  /// The state at t, clamped to [0, duration()].
  FlightState at(double t) const;
  /// Position at distance flown s ∈ [0, length()] [m] (on the line of the lap flown there, independent of time).
  Eigen::Vector3d positionAtDistance(double s) const;
  /// The highest speed of the profile [m/s].
  double topSpeed() const;

 private:
  /// The table of one lap's line, per lap sample.
  struct LapLine {
    std::vector<double> s;      ///< arc length from u = 0 [m]
    std::vector<double> du_ds;  ///< [1/m]
  };
  double distanceAt(double t) const;
  int lapAt(double s) const;
  const LapLine& lineOf(size_t lap) const { return lap_lines_ ? lines_[lap] : lines_.front(); }
  Eigen::Vector3d linePosition(size_t lap, double u) const;
  double speedFactor(size_t lap, double x) const;  ///< x: the fraction of the reference lap

  FlightParams params_;
  std::shared_ptr<const ClosedCurve> curve_;
  double lap_length_ = 0.0;            ///< of the reference path [m]
  std::vector<double> lap_u_;          ///< per lap sample: curve parameter, 0 … 1
  std::vector<LapLine> lines_;         ///< one (every lap on the reference path) or one per lap
  std::vector<LapVariation> variations_;  ///< one per lap, or empty (no variation)
  std::shared_ptr<const LapLines> lap_lines_;  ///< with lap_line_variation
  std::vector<double> lap_start_;      ///< distance flown at the start of each lap, laps + 1 values [m]
  std::vector<double> profile_speed_;  ///< over the whole flight, one per distance step [m/s]
  std::vector<double> times_;          ///< time at each profile sample [s]
};

}  // namespace dualgraph
