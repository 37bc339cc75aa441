// SPDX-License-Identifier: MIT
// OdometryClockGuard: one odometry stamp far from the clock (a glitch) cannot lose the flight; a real new clock can.
#pragma once

#include <optional>
#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// What OdometryClockGuard::check says of one sample.
enum class ClockCheck {
  kOn,       ///< on the accepted clock, or not the guard's business (within the limit, not finite, off): go on
  kHeld,     ///< more than the limit from the newest accepted sample, not (yet) confirmed: refuse it (heldStatus())
  kJump,     ///< the third sample in a row on a clock ahead: take it (the pipeline sees a gap)
  kRestart,  ///< a clock behind confirmed (3 samples in a row over kRestartSpanS): take it in a new pipeline
};

/// Watches the odometry's time stamps [s] for jumps longer than `max_jump_s`, either way. Without it one sample
/// stamped far ahead (a bit flip, another clock's stamp) is taken, and every later sample of the real clock is
/// refused as not after it; and a clock that really restarts (a looped bag, a VIO restarted on a clock from 0, a
/// glitched first sample) is refused for ever. With it such a sample is held: refused, and taken as the start of a
/// new clock only when kConfirmations samples in a row continue from it (each after the one before, by at most
/// `max_jump_s`); the third is then taken ahead of the newest (a jump, kJump: the pipeline sees a gap). Behind it, a
/// restart (kRestart) throws the flight's state away, so the clock behind must also have run kRestartSpanS: a burst
/// of a few stale samples (a driver's buffer replayed) is held and dropped, not a reset. What is held stays
/// refused. A sample on the accepted clock in between drops what was held. A sample behind
/// the newest by at most `max_jump_s` is not judged here (the order check refuses it), nor validity: give it valid
/// samples only (StreamingLocalizer checks them first), so garbage cannot confirm a new clock. `max_jump_s` 0: off.
/// Plain value; one thread at a time.
class OdometryClockGuard {
 public:
  static constexpr int kConfirmations = 3;
  /// The stamps a clock behind must span, first held sample to the one taken, before it restarts the pipeline [s].
  static constexpr double kRestartSpanS = 1.0;

  explicit OdometryClockGuard(double max_jump_s) : max_jump_s_(max_jump_s) {}

  /// What to do with a valid sample at `t`; call `accepted` once it was taken.
  ClockCheck check(double t);
  /// Why the sample last checked was held (kInvalidArgument naming the jump and the confirmations so far).
  Status heldStatus() const;
  /// The pipeline took the sample at `t`.
  void accepted(double t) { newest_ = t; }

  int held() const { return held_; }          ///< samples held, either way
  int jumps() const { return jumps_; }        ///< new clocks ahead confirmed
  int restarts() const { return restarts_; }  ///< new clocks behind confirmed

 private:
  struct Candidate {
    double first_t = 0.0;  ///< the first sample held on that clock [s]
    double last_t = 0.0;   ///< the newest [s]
    int samples = 0;       ///< samples in a row on it
  };
  double max_jump_s_;
  std::optional<double> newest_;
  std::optional<Candidate> candidate_;
  int held_ = 0;
  int jumps_ = 0;
  int restarts_ = 0;
};

}  // namespace dualgraph
