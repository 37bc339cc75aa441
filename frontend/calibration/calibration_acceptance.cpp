// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/calibration/calibration_acceptance.h"

#include <cmath>
#include <cstdio>

namespace dualgraph {
namespace {

constexpr double kDeg = 180.0 / M_PI;

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  char text[320];
  std::snprintf(text, sizeof(text), pattern, a, b, c);
  return text;
}

}  // namespace

CalibrationAcceptance judgeCalibration(const CameraModel& camera, const CameraCalibration& whole,
                                       const CameraCalibration* first_half, const CameraCalibration* second_half,
                                       const std::string& why_half_missing, const CalibrationAcceptanceParams& params) {
  CalibrationAcceptance out;
  // Significance, against the whole flight's own estimate.
  const double time_change = whole.camera.time_offset - camera.time_offset;
  const double mount_change = whole.mount_correction.norm();
  const double mount_sigma = whole.rotation_sigma.norm();
  const bool time_significant =
      std::abs(time_change) > std::max(3.0 * whole.time_offset_sigma, params.min_time_offset_change);
  const bool mount_significant = mount_change * kDeg > std::max(3.0 * mount_sigma * kDeg, params.min_mount_change_deg);
  out.time_offset_significant = time_significant;
  out.mount_significant = mount_significant;
  if (!time_significant) {
    out.why_not_time_offset = format("the clock offset moved %.1f ms, within max(3 sigma = %.1f ms, %.1f ms)",
                                     1e3 * time_change, 3e3 * whole.time_offset_sigma, 1e3 * params.min_time_offset_change);
  }
  if (!mount_significant) {
    out.why_not_mount = format("the mount correction %.2f deg is within max(3 sigma = %.2f deg, %.2f deg)",
                               mount_change * kDeg, 3.0 * mount_sigma * kDeg, params.min_mount_change_deg);
  }
  // Consistency, between the halves.
  out.halves_calibrated = first_half != nullptr && second_half != nullptr && first_half->converged && second_half->converged;
  if (!out.halves_calibrated) {
    std::string why = "a half of the flight so far could not be calibrated on its own (nothing shows the correction holds)";
    if (!why_half_missing.empty()) why += ": " + why_half_missing;
    if (time_significant) out.why_not_time_offset = why;
    if (mount_significant) out.why_not_mount = why;
    return out;
  }
  out.half_time_offsets[0] = first_half->camera.time_offset;
  out.half_time_offsets[1] = second_half->camera.time_offset;
  out.half_mount_change_deg[0] = first_half->mount_correction.norm() * kDeg;
  out.half_mount_change_deg[1] = second_half->mount_correction.norm() * kDeg;
  const double time_apart = std::abs(out.half_time_offsets[0] - out.half_time_offsets[1]);
  const double time_allowed = 3.0 * std::hypot(first_half->time_offset_sigma, second_half->time_offset_sigma) +
                              params.time_offset_agreement;
  const double mount_apart = (first_half->mount_correction - second_half->mount_correction).norm() * kDeg;
  const double mount_allowed =
      3.0 * std::hypot(first_half->rotation_sigma.norm(), second_half->rotation_sigma.norm()) * kDeg +
      params.mount_agreement_deg;
  // What the halves show of the mount together: their calibrations are independent (disjoint corners), so their
  // inverse-variance mean is what the flight shows without the VIO's drift model linking the halves — a mount
  // that only the whole shows rests on that model, where a VIO error can pass for a mount (a constant mount is in
  // what each half sees).
  const Eigen::Vector3d mount_weights[2] = {first_half->rotation_sigma.cwiseAbs2().cwiseMax(1e-24).cwiseInverse(),
                                            second_half->rotation_sigma.cwiseAbs2().cwiseMax(1e-24).cwiseInverse()};
  const Eigen::Vector3d halves_mount =
      (mount_weights[0].cwiseProduct(first_half->mount_correction) + mount_weights[1].cwiseProduct(second_half->mount_correction))
          .cwiseQuotient(mount_weights[0] + mount_weights[1]);
  const double halves_mount_sigma = (mount_weights[0] + mount_weights[1]).cwiseInverse().cwiseSqrt().norm();
  out.halves_mount_change_deg = halves_mount.norm() * kDeg;
  out.halves_mount_sigma_deg = halves_mount_sigma * kDeg;
  if (time_significant) {
    out.time_offset = time_apart <= time_allowed;
    if (!out.time_offset) {
      out.why_not_time_offset = format("the halves of the flight disagree on the clock offset (%.1f vs %.1f ms, allowed %.1f)",
                                       1e3 * out.half_time_offsets[0], 1e3 * out.half_time_offsets[1], 1e3 * time_allowed);
    }
  }
  if (mount_significant) {
    out.mount = mount_apart <= mount_allowed;
    if (!out.mount) {
      out.why_not_mount = format("the halves of the flight disagree on the mount correction by %.2f deg (allowed %.2f): a "
                                 "VIO attitude error, not the mount (whole flight: %.2f deg)",
                                 mount_apart, mount_allowed, mount_change * kDeg);
    } else if (!(out.halves_mount_change_deg > std::max(3.0 * out.halves_mount_sigma_deg, params.min_mount_change_deg))) {
      out.mount = false;
      out.why_not_mount = format("the halves together show a mount correction of only %.2f deg (3 sigma = %.2f deg): the "
                                 "whole flight's %.2f deg rests on the VIO's drift model linking them, not on what each half sees",
                                 out.halves_mount_change_deg, 3.0 * out.halves_mount_sigma_deg, mount_change * kDeg);
    }
  }
  return out;
}

CameraModel acceptedCamera(const CameraModel& camera, const CameraCalibration& whole, const CalibrationAcceptance& accepted) {
  CameraModel out = camera;
  if (accepted.time_offset) out.time_offset = whole.camera.time_offset;
  if (accepted.mount) out.body_T_camera.linear() = whole.camera.body_T_camera.linear();
  return out;
}

}  // namespace dualgraph
