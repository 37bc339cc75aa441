// SPDX-License-Identifier: MIT
// OdometryMotionGuard: one odometry pose far from the motion (a glitch) is never taken; a real jump of the VIO is.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// What OdometryMotionGuard::check says of one sample.
enum class MotionCheck {
  kOn,    ///< within the speed and turn-rate limits of the newest accepted sample (or not the guard's business)
  kHeld,  ///< faster than a drone flies from the newest accepted sample, not (yet) confirmed: refuse it (heldStatus())
  kJump,  ///< the third sample in a row continuing from such a pose: take it (the VIO really jumped)
};

/// Watches the odometry's poses odom_T_body [m] against their stamps [s]: a sample that moved further from the newest
/// accepted one than `max_speed` [m/s] · Δt + kSlackM, or turned more than `max_turn_rate` [rad/s] · Δt + kSlackRad,
/// is faster than a drone flies. Without the guard such a pose (a driver's glitch: a bit flip, an uninitialised
/// message, another frame's pose) was taken as motion: its own corrected pose went out as `tracking` 10⁶ m away,
/// and the keyframes it closed moved the flight's estimate. With it the sample is held: refused, and taken as the
/// VIO's new place only when kConfirmations samples in a row continue from it (each within the limits of the one
/// before) — a VIO that really jumps (a reset, a loop closure) is then taken as before, two samples later. A sample
/// within the limits of the newest accepted one drops what was held. Not judged: a sample not after the newest (the
/// order check's business) and the first sample. Give it valid samples only. Limits 0: that check is off.
/// Plain value; one thread at a time.
class OdometryMotionGuard {
 public:
  static constexpr int kConfirmations = 3;
  static constexpr double kSlackM = 0.1;    ///< displacement allowed on top of max_speed · Δt (noise, jitter) [m]
  static constexpr double kSlackRad = 0.1;  ///< rotation allowed on top of max_turn_rate · Δt [rad]

  OdometryMotionGuard(double max_speed, double max_turn_rate) : max_speed_(max_speed), max_turn_rate_(max_turn_rate) {}

  /// What to do with a valid sample at `t` posed `odom_T_body`; call `accepted` once it was taken.
  MotionCheck check(double t, const Eigen::Isometry3d& odom_T_body);
  /// Why the sample last checked was held (kInvalidArgument naming the step, the limits and the confirmations).
  Status heldStatus() const;
  /// The pipeline took this sample.
  void accepted(double t, const Eigen::Isometry3d& odom_T_body);
  /// Forgets the newest accepted sample and anything held (a new clock, a new pipeline): the next sample is a first.
  void reset();

  int held() const { return held_; }    ///< samples held
  int jumps() const { return jumps_; }  ///< jumps confirmed and taken

 private:
  struct Stamped {
    double t = 0.0;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  };
  /// Whether going from `from` to (t, pose) is within the limits.
  bool withinLimits(const Stamped& from, double t, const Eigen::Isometry3d& pose) const;

  double max_speed_;
  double max_turn_rate_;
  std::optional<Stamped> newest_;
  std::optional<Stamped> candidate_;  ///< the newest held sample
  int candidate_samples_ = 0;         ///< held samples in a row continuing from each other
  Stamped last_checked_;              ///< for heldStatus
  int held_ = 0;
  int jumps_ = 0;
};

}  // namespace dualgraph
