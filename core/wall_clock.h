// SPDX-License-Identifier: MIT
// nowMs, monotonic milliseconds, and PhaseTimer, which adds a scope's duration to a total.
#pragma once

#include <chrono>

namespace dualgraph {

/// Milliseconds on a monotonic clock (for durations only).
inline double nowMs() {
  using Clock = std::chrono::steady_clock;
  return std::chrono::duration<double, std::milli>(Clock::now().time_since_epoch()).count();
}

/// Adds the time since construction to `total` (milliseconds) when destroyed.
class PhaseTimer {
 public:
  explicit PhaseTimer(double& total) : total_(total), start_(nowMs()) {}
  ~PhaseTimer() { total_ += nowMs() - start_; }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  double& total_;
  double start_;
};

}  // namespace dualgraph
