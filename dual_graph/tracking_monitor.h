// SPDX-License-Identifier: MIT
// TrackingState (initialising / tracking / lost) and TrackingMonitor, which decides loss of lock from the evidence.
#pragma once

#include <deque>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace dualgraph {

/// Whether the Localizer's estimate is a pose in the gate map.
///  - kInitialising: the VIO's frame in the map is not known yet (no gate used); the pose is the odometry
///    through the initial guess of world_T_odom, not a map pose.
///  - kTracking: gates are being used; the pose is the drift-corrected map pose.
///  - kLost: gates are seen but none has been used for a while (TrackingMonitor); the pose is the last
///    correction carried on by the odometry, and may be wrong by metres.
enum class TrackingState { kInitialising, kTracking, kLost };

/// "initialising", "tracking" or "lost".
const char* trackingStateName(TrackingState state);

/// Decides loss of lock from what happens to gate detections (times in seconds on the odometry's clock).
/// Success: a gate edge entered the main graph. Failure: a detection that matched no map gate and is
/// persistent — within 1 m (world frame, through the estimate) of another unmatched one from an earlier
/// instant of the last 0.5 s: a real gate seen again where the estimate has none, not a one-off false
/// detection (addUnmatched, reported by the frontend) — or one standing in an edge the χ² gate rejected
/// (addUpdate). Tracking turns lost when, since the last success (or the lock), at least `min_failures`
/// failures came and `lost_after_s` passed: gates are in view but none fits where the estimate says the drone
/// is. Silence (no gate in view) is no evidence either way. Lost turns tracking again at a success only when
/// no failure came in the last `lost_after_s` (a success among failures may be a gate matched to its
/// neighbour by a wrong estimate: the frame search decides then); initialising and lost turn tracking at
/// `locked` (a frame found, e.g. by relocalisation) or `resume` (the frame in use confirmed).
/// `suspicious()`: at least `min_failures` failures in the last `lost_after_s` even while successes keep
/// tracking alive — the cue for a frame search that checks the frame in use (a VIO jump onto a neighbouring
/// gate's place keeps some gates matched, wrongly, and leaves the others unmatched).
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class TrackingMonitor {
 public:
  TrackingMonitor(TrackingState initial, double lost_after_s, int min_failures)
      : state_(initial), lost_after_s_(lost_after_s), min_failures_(min_failures) {}

  TrackingState state() const { return state_; }
  /// The gate centres [m, world frame] of the detections at time t that matched no map gate.
  void addUnmatched(double t, const std::vector<Eigen::Vector3d>& p_world);
  /// A main-graph update at t: `added` gate edges entered it, `rejected_observations` detections stood in
  /// edges the χ² gate rejected.
  void addUpdate(double t, int added, int rejected_observations);
  /// The frame was found (or given) at t: tracking from now, evidence cleared.
  void locked(double t);
  /// Lost, but a search found the frame in use at t: tracking again, counted as a recovery. No-op unless lost.
  void resume(double t);
  /// A recovery made outside the monitor (the Localizer restarted its graph in the frame in use).
  void countRecovery() { ++recoveries_; }
  /// Times tracking turned lost, and lost turned tracking by a success (without a new frame).
  int losses() const { return losses_; }
  int recoveries() const { return recoveries_; }
  /// Failures since the last success (or the lock) [count].
  int failuresSinceSuccess() const { return failures_; }
  /// Failures in the `lost_after_s` before the newest evidence, successes or not [count].
  int recentFailures() const;
  /// Tracking, with at least `min_failures` recent failures.
  bool suspicious() const { return state_ == TrackingState::kTracking && recentFailures() >= min_failures_; }
  /// The frame in use was found wrong at t (a check found a better one): tracking turns lost (counted).
  void declareLost(double t);

 private:
  void addFailures(double t, int count);
  struct Unmatched {
    double t;
    Eigen::Vector3d p_world;
  };
  std::deque<Unmatched> recent_unmatched_;  ///< the last 0.5 s
  struct Failures {
    double t;
    int count;
  };
  std::deque<Failures> recent_failures_;  ///< the last lost_after_s, whatever the state
  double newest_t_ = -std::numeric_limits<double>::infinity();

  TrackingState state_;
  const double lost_after_s_;
  const int min_failures_;
  double last_success_t_ = -std::numeric_limits<double>::infinity();
  double first_evidence_t_ = std::numeric_limits<double>::quiet_NaN();  ///< when there was no success yet
  int failures_ = 0;
  int losses_ = 0;
  int recoveries_ = 0;
};

}  // namespace dualgraph
