// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/pipeline/odometry_clock_guard.h"

#include <cmath>

#include "dualgraph/core/stamp_tolerance.h"

namespace dualgraph {

ClockCheck OdometryClockGuard::check(double t) {
  if (!std::isfinite(t)) return ClockCheck::kOn;  // the sample check's business: refused as not finite
  const bool far = max_jump_s_ > 0.0 && newest_ &&
                   (elapsedMoreThan(t, *newest_, max_jump_s_) || elapsedMoreThan(*newest_, t, max_jump_s_));
  if (!far) {
    candidate_.reset();  // on the accepted clock (or just behind it: the order check's business)
    return ClockCheck::kOn;
  }
  if (candidate_ && t > candidate_->last_t && !elapsedMoreThan(t, candidate_->last_t, max_jump_s_)) {
    candidate_->last_t = t;
    ++candidate_->samples;
  } else {
    candidate_ = Candidate{t, t, 1};
  }
  const bool ahead = t > *newest_;
  if (candidate_->samples < kConfirmations ||
      (!ahead && !elapsedAtLeast(candidate_->last_t, candidate_->first_t, kRestartSpanS))) {
    ++held_;
    return ClockCheck::kHeld;
  }
  candidate_.reset();
  if (ahead) {
    ++jumps_;
    return ClockCheck::kJump;
  }
  ++restarts_;
  return ClockCheck::kRestart;
}

Status OdometryClockGuard::heldStatus() const {
  if (!candidate_ || !newest_) return Status();
  const double t = candidate_->last_t;
  const bool ahead = t > *newest_;
  return Status(StatusCode::kInvalidArgument,
                "odometry sample at t=" + formatTimestamp(t) + " is " + formatNumber(std::abs(t - *newest_)) + " s " +
                    (ahead ? "after" : "before") + " the newest accepted one at t=" + formatTimestamp(*newest_) +
                    " (more than frontend.max_odometry_jump_s = " + formatNumber(max_jump_s_) + " s): a clock " +
                    (ahead ? "jump" : "restart") + ", held until " + std::to_string(kConfirmations) +
                    " samples in a row continue from it" + (ahead ? "" : " over " + formatNumber(kRestartSpanS) + " s") +
                    " (" + std::to_string(candidate_->samples) + " so far)");
}

}  // namespace dualgraph
