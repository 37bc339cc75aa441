// SPDX-License-Identifier: MIT
// Comparisons of time-stamp differences with durations that give the same answer whatever the clock's origin.
#pragma once

namespace dualgraph {

/// Slack of every decision that compares a difference of two time stamps with a duration [s]. A stamp on an epoch
/// clock (Unix seconds, ≈ 1.7e9) is a double with a spacing of 2.4e-7 s, so the same flight stamped from 0 and
/// from an epoch gives differences that disagree by a few 1e-7 s: a tie (two detections exactly 0.2 s apart, a
/// failure exactly lost_after_s after the last success) must not fall one way on one clock and the other way on
/// the other. 1 µs is above that rounding and far below any sensor period.
constexpr double kStampTolerance = 1e-6;

/// `later − earlier ≥ duration`, ties (within kStampTolerance) counted as reached.
inline bool elapsedAtLeast(double later, double earlier, double duration) {
  return later - earlier >= duration - kStampTolerance;
}

/// `later − earlier > duration`, ties (within kStampTolerance) counted as not exceeded.
inline bool elapsedMoreThan(double later, double earlier, double duration) {
  return later - earlier > duration + kStampTolerance;
}

/// `a ≤ b` for two stamps, ties within kStampTolerance counted as equal.
inline bool notAfter(double a, double b) { return a <= b + kStampTolerance; }

/// `a < b` for two stamps by more than kStampTolerance.
inline bool clearlyBefore(double a, double b) { return a < b - kStampTolerance; }

}  // namespace dualgraph
