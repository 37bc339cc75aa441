// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/odometry_motion_guard.h"

#include <cmath>

namespace dualgraph {
namespace {

double turnBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

}  // namespace

bool OdometryMotionGuard::withinLimits(const Stamped& from, double t, const Eigen::Isometry3d& pose) const {
  const double dt = t - from.t;
  if (max_speed_ > 0.0 && (pose.translation() - from.pose.translation()).norm() > max_speed_ * dt + kSlackM) return false;
  if (max_turn_rate_ > 0.0 && turnBetween(from.pose, pose) > max_turn_rate_ * dt + kSlackRad) return false;
  return true;
}

MotionCheck OdometryMotionGuard::check(double t, const Eigen::Isometry3d& odom_T_body) {
  if (!newest_ || !(t > newest_->t) || !std::isfinite(t)) return MotionCheck::kOn;  // first, or the order check's
  last_checked_ = Stamped{t, odom_T_body};
  if (withinLimits(*newest_, t, odom_T_body)) {
    candidate_.reset();  // on the accepted motion: what was held is dropped
    candidate_samples_ = 0;
    return MotionCheck::kOn;
  }
  if (candidate_ && t > candidate_->t && withinLimits(*candidate_, t, odom_T_body)) {
    ++candidate_samples_;
  } else {
    candidate_samples_ = 1;
  }
  candidate_ = Stamped{t, odom_T_body};
  if (candidate_samples_ < kConfirmations) {
    ++held_;
    return MotionCheck::kHeld;
  }
  candidate_.reset();
  candidate_samples_ = 0;
  ++jumps_;
  return MotionCheck::kJump;
}

void OdometryMotionGuard::accepted(double t, const Eigen::Isometry3d& odom_T_body) {
  newest_ = Stamped{t, odom_T_body};
}

void OdometryMotionGuard::reset() {
  newest_.reset();
  candidate_.reset();
  candidate_samples_ = 0;
}

Status OdometryMotionGuard::heldStatus() const {
  if (!newest_ || !candidate_) return Status();
  const double dt = last_checked_.t - newest_->t;
  const double moved = (last_checked_.pose.translation() - newest_->pose.translation()).norm();
  const double turned = turnBetween(newest_->pose, last_checked_.pose);
  return Status(StatusCode::kInvalidArgument,
                "odometry sample at t=" + formatTimestamp(last_checked_.t) + " is " + formatNumber(moved) + " m and " +
                    formatNumber(turned) + " rad from the newest accepted one at t=" + formatTimestamp(newest_->t) + ", " +
                    formatNumber(dt) + " s before (faster than frontend.max_odometry_speed_mps = " + formatNumber(max_speed_) +
                    " m/s or frontend.max_odometry_turn_rate_radps = " + formatNumber(max_turn_rate_) +
                    " rad/s): a pose jump, held until " + std::to_string(kConfirmations) +
                    " samples in a row continue from it (" + std::to_string(candidate_samples_) + " so far)");
}

}  // namespace dualgraph
