// SPDX-License-Identifier: MIT
// Detection files: the corner-pixel CSV and the pose (+ covariance) CSV, read and written.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/frontend/gates/corner_detection.h"

namespace dualgraph {

/// Corner detections CSV: `t,gate_id,u_tl,v_tl,u_tr,v_tr,u_br,v_br,u_bl,v_bl`. A header line is
/// optional (a first non-comment line whose first field is `t`); when present it must be exactly
/// these names. Time stamps non-decreasing (one image may hold several gates); gate_id ≥ -1;
/// pixel coordinates finite, except for a corner the detector did not see (a gate partly out of the image):
/// both its coordinates `nan` (or empty), NaN in memory; at least 2 corners seen. `#` comments and blank lines skipped; errors name file, line and field.
Result<std::vector<CornerDetection>> readCornerDetections(const std::string& path);

/// Pose detections CSV: `t,gate_id,x,y,z,qx,qy,qz,qw` — body_T_gate (translation [m] of the gate
/// centre in the body frame, Hamilton quaternion [x y z w], normalised on reading) — optionally
/// followed by the 21 upper-triangular entries `cov_00,cov_01,...,cov_55` of its covariance, metric
/// [t; θ] (m², rad²), a right perturbation in the gate frame. Rows without covariance get
/// `default_covariance` (checked once; same convention). Header optional as above (with or without
/// the covariance names); each row may or may not carry a covariance; time stamps non-decreasing;
/// gate_id ≥ -1. An unknown gate (-1) is kept as read: it must be associated before the Localizer sees
/// it (validateGateObservation rejects gate_id < 0). `lines` (optional) receives each observation's 1-based
/// file line, for later messages.
Result<std::vector<GateObservation>> readPoseDetections(const std::string& path, const Matrix6d& default_covariance,
                                                        std::vector<int>* lines = nullptr);

class RowReader;

/// One data row of corners.csv (10 fields, as readCornerDetections reads them) into `out` (its line set). With
/// `previous_t`, a stamp before it is an error. Errors name the row's source, line and field.
Status readCornerRow(const RowReader& row, const double* previous_t, CornerDetection& out);
/// One data row of detections.csv (9 fields, or 30 with the covariance; `default_covariance` otherwise, not checked
/// here), as readPoseDetections reads them, into `out`. With `previous_t`, a stamp before it is an error.
Status readPoseRow(const RowReader& row, const double* previous_t, const Matrix6d& default_covariance,
                   GateObservation& out);

/// Writes corner detections in the CSV form readCornerDetections reads (with the header line,
/// 17 significant digits; `nan,nan` for a corner not seen). Atomic (temporary file + rename). kInvalidArgument
/// naming the detection for a non-finite value (other than a corner NaN in both coordinates), fewer than 2 corners, gate_id < -1 or a decreasing time stamp; kIoError on write failure.
Status writeCornerDetections(const std::string& path, const std::vector<CornerDetection>& detections);
/// Writes kPose observations as the pose detections CSV with all 21 covariance columns and the header.
/// Atomic. kInvalidArgument naming the observation for a kPosition one, non-finite values, a non-rigid
/// pose, an invalid covariance (checkCovariance), gate_id < -1 or a decreasing time stamp.
Status writePoseDetections(const std::string& path, const std::vector<GateObservation>& observations);

}  // namespace dualgraph
