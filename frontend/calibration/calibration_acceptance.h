// SPDX-License-Identifier: MIT
// Which parts of a flight's self-calibration to apply: only a clock offset or mount correction that is significant and consistent.
#pragma once

#include <string>

#include "dualgraph/frontend/calibration/camera_calibration.h"

namespace dualgraph {

/// The bar a calibrated part must clear to replace the given camera's. A part is **significant** when its change
/// exceeds 3σ of its own formal estimate and a floor below which it changes nothing that matters; it is
/// **consistent** when the flight's first and second halves, calibrated apart, agree on it within 3σ of their
/// difference plus `*_agreement` — a constant clock offset or mount error is the same in both halves, while a
/// VIO attitude error that the mount absorbs drifts from one half to the other. A mount correction must also be
/// **shown by the halves together**: their inverse-variance mean beyond 3σ of itself and the floor. The halves are
/// independent, the whole is not: its extra precision comes from the VIO's drift model linking them, and there a
/// VIO error can pass for a mount (bench/README.md, "A mount the halves must show").
struct CalibrationAcceptanceParams {
  double min_time_offset_change = 0.002;  ///< [s]
  double min_mount_change_deg = 0.25;     ///< [deg]
  double time_offset_agreement = 0.002;   ///< halves' offsets may differ by 3σ plus this [s]
  double mount_agreement_deg = 0.2;       ///< halves' mount corrections may differ by 3σ plus this [deg]
};

/// What to apply of a calibration, and why not the rest (empty when applied). A plain value.
struct CalibrationAcceptance {
  bool time_offset = false;
  bool mount = false;
  std::string why_not_time_offset;
  std::string why_not_mount;
  double half_time_offsets[2] = {0.0, 0.0};   ///< the halves' δ [s] (when both calibrated)
  double half_mount_change_deg[2] = {0.0, 0.0};  ///< the halves' mount corrections [deg]
  bool halves_calibrated = false;
  /// The halves' mount corrections' inverse-variance mean (what they show together): its size and 1σ [deg].
  double halves_mount_change_deg = 0.0, halves_mount_sigma_deg = 0.0;
  /// The whole flight's estimate of each part is beyond 3σ and the floor (checked before the halves).
  bool time_offset_significant = false;
  bool mount_significant = false;
};

/// Judges `whole` (started from `camera`) against the calibrations of its halves (null: a half could not be
/// calibrated, `why_half_missing` says why — then nothing is applied, since nothing shows the correction holds).
CalibrationAcceptance judgeCalibration(const CameraModel& camera, const CameraCalibration& whole,
                                       const CameraCalibration* first_half, const CameraCalibration* second_half,
                                       const std::string& why_half_missing = "",
                                       const CalibrationAcceptanceParams& params = {});

/// `camera` with the accepted parts of `whole` applied: its time_offset, its body_T_camera rotation.
CameraModel acceptedCamera(const CameraModel& camera, const CameraCalibration& whole, const CalibrationAcceptance& accepted);

}  // namespace dualgraph
