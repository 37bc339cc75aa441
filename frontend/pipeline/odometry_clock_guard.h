// SPDX-License-Identifier: MIT
// OdometryClockGuard: one odometry sample stamped far ahead (a clock glitch) cannot make every later sample "old".
#pragma once

#include <optional>
#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// Watches the odometry's time stamps [s] for forward jumps longer than `max_jump_s`. Without it one sample stamped
/// far ahead (a bit flip, another clock's stamp) is taken, and every later sample of the real clock is refused as not
/// after it: the rest of the flight is lost. With it such a sample is held: refused, and taken as the start of a new
/// clock only when kConfirmations samples in a row continue from it (each after the one before, by at most
/// `max_jump_s`); the third is then accepted (the pipeline sees a gap, frontend/pipeline/README.md), the two before it
/// stay refused. A sample on the accepted clock in between drops what was held. `max_jump_s` 0: off. Order (a sample
/// not after the newest) is not judged here, nor validity: give it valid samples only (StreamingLocalizer checks them
/// first), so garbage cannot confirm a new clock. Plain value; one thread at a time.
class OdometryClockGuard {
 public:
  static constexpr int kConfirmations = 3;

  explicit OdometryClockGuard(double max_jump_s) : max_jump_s_(max_jump_s) {}

  /// OK when a sample at `t` may go on (then `accepted` once it was taken); kInvalidArgument, naming the jump, when it
  /// is held. A held sample counts in `held()`; the one that confirms a new clock in `jumps()`.
  Status check(double t);
  /// The pipeline took the sample at `t`.
  void accepted(double t) { newest_ = t; }

  int held() const { return held_; }
  int jumps() const { return jumps_; }

 private:
  struct Candidate {
    double last_t = 0.0;  ///< the newest sample on the held clock [s]
    int samples = 0;      ///< samples in a row on it
  };
  double max_jump_s_;
  std::optional<double> newest_;
  std::optional<Candidate> candidate_;
  int held_ = 0;
  int jumps_ = 0;
};

}  // namespace dualgraph
