// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/tracking_monitor.h"

#include <algorithm>
#include <cmath>

#include "dualgraph/core/stamp_tolerance.h"

namespace dualgraph {

const char* trackingStateName(TrackingState state) {
  switch (state) {
    case TrackingState::kInitialising: return "initialising";
    case TrackingState::kTracking: return "tracking";
    case TrackingState::kLost: return "lost";
  }
  return "unknown";
}

namespace {
constexpr double kPersistenceSeconds = 0.5;  ///< an unmatched gate seen again within this [s]
constexpr double kPersistenceMetres = 1.0;   ///< and this far from where it was seen [m]
}  // namespace

void TrackingMonitor::addUnmatched(double t, const std::vector<Eigen::Vector3d>& p_world) {
  while (!recent_unmatched_.empty() && elapsedMoreThan(t, recent_unmatched_.front().t, kPersistenceSeconds)) {
    recent_unmatched_.pop_front();
  }
  int persistent = 0;
  for (const Eigen::Vector3d& p : p_world) {
    for (const Unmatched& earlier : recent_unmatched_) {
      if (earlier.t < t && (earlier.p_world - p).norm() <= kPersistenceMetres) {
        ++persistent;
        break;
      }
    }
  }
  for (const Eigen::Vector3d& p : p_world) recent_unmatched_.push_back(Unmatched{t, p});
  addFailures(t, persistent);
}

void TrackingMonitor::addUpdate(double t, int added, int rejected_observations) {
  newest_t_ = std::max(newest_t_, t);
  if (added > 0) {
    if (state_ == TrackingState::kLost) {
      if (recentFailures() > 0 || rejected_observations > 0) {  // not clean evidence: stay lost
        addFailures(t, rejected_observations);
        return;
      }
      state_ = TrackingState::kTracking;
      ++recoveries_;
    }
    last_success_t_ = t;
    failures_ = 0;
    return;
  }
  addFailures(t, rejected_observations);
}

int TrackingMonitor::recentFailures() const {
  int count = 0;
  for (const Failures& failures : recent_failures_) {
    if (!elapsedMoreThan(newest_t_, failures.t, lost_after_s_)) count += failures.count;
  }
  return count;
}

void TrackingMonitor::declareLost(double t) {
  if (state_ != TrackingState::kTracking) return;
  state_ = TrackingState::kLost;
  ++losses_;
  newest_t_ = std::max(newest_t_, t);
}

void TrackingMonitor::locked(double t) {
  state_ = TrackingState::kTracking;
  recent_failures_.clear();
  last_success_t_ = t;
  failures_ = 0;
}

void TrackingMonitor::resume(double t) {
  if (state_ != TrackingState::kLost) return;
  locked(t);
  ++recoveries_;
}

void TrackingMonitor::addFailures(double t, int count) {
  newest_t_ = std::max(newest_t_, t);
  while (!recent_failures_.empty() && elapsedMoreThan(newest_t_, recent_failures_.front().t, lost_after_s_)) {
    recent_failures_.pop_front();
  }
  if (count > 0 && state_ != TrackingState::kInitialising) recent_failures_.push_back(Failures{t, count});
  if (count <= 0 || state_ != TrackingState::kTracking) return;
  // Given a frame at the start (no lock, no success yet), the clock starts at the first evidence.
  if (std::isinf(last_success_t_) && std::isnan(first_evidence_t_)) first_evidence_t_ = t;
  failures_ += count;
  const double since = std::isinf(last_success_t_) ? first_evidence_t_ : last_success_t_;
  if (failures_ >= min_failures_ && elapsedAtLeast(t, since, lost_after_s_)) {
    state_ = TrackingState::kLost;
    ++losses_;
  }
}

}  // namespace dualgraph
