// SPDX-License-Identifier: MIT
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/status.h"
#include "frontend/camera_model.h"
#include "frontend/detection_io.h"
#include "frontend/odometry_io.h"
#include "frontend/track.h"

namespace dualgraph {

/// A sequence folder as `dualgraph simulate` writes it and `dualgraph run` reads it (DESIGN.md §6):
///   vio.tum        odometry odom_T_body, TUM, optionally with the 21 absolute-covariance columns (required)
///   corners.csv    gate corner pixels (needs camera.yaml)        } exactly one of the two
///   detections.csv gate poses body_T_gate, optional covariances   }
///   gates.yaml     the gate map (track YAML; a path in it is ignored) (required)
///   camera.yaml    the camera (required with corners.csv)
///   gt.tum         ground truth world_T_body (optional; enables metrics)
struct Sequence {
  std::string dir;
  OdometryLog odometry;  ///< relative covariances filled from the absolute ones when the file has them
  int covariance_clamped = 0;  ///< eigenvalues toRelativeCovariances raised to its floor
  bool has_corners = false;
  std::vector<CornerDetection> corners;        ///< when has_corners
  std::vector<GateObservation> pose_detections;  ///< otherwise
  Track map;
  std::optional<CameraModel> camera;
  std::optional<OdometryLog> ground_truth;

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Reads a sequence folder. `default_detection_covariance` is used for detections.csv rows without
/// covariance (metric [t; θ], m², rad²). Every reader's error is passed on unchanged (file, line, field);
/// missing required files, both or neither detection file, or corners without a camera are
/// kNotFound / kInvalidArgument naming the folder and the file.
Result<Sequence> loadSequence(const std::string& dir, const Matrix6d& default_detection_covariance);

}  // namespace dualgraph
