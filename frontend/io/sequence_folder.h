// SPDX-License-Identifier: MIT
// Sequence, the input of `dualgraph run`, and its folder: loadSequence reads it, writeSequence writes it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/frontend/gates/track.h"

namespace dualgraph {

/// A sequence: what `dualgraph run` localises, read from a folder (loadSequence), or made in memory by the
/// simulator (raceSequence) and written as a folder (writeSequence). The folder (frontend/io/FORMATS.md):
///   vio.tum        odometry odom_T_body (required unless loadSequence is given another file): TUM, TUM with
///                  the 21 absolute-covariance columns, OpenVINS traj_estimate or EuRoC CSV (readTrajectory)
///   corners.csv    gate corner pixels (needs camera.yaml)        } exactly one of the two
///   detections.csv gate poses body_T_gate, optional covariances   }
///   gates.yaml     the gate map (track YAML; a path in it is ignored) (required)
///   camera.yaml    the camera (required with corners.csv)
///   gt.tum         ground truth world_T_body (optional; enables metrics): TUM, EuRoC CSV or OpenVINS
struct Sequence {
  std::string dir;       ///< the folder it was read from, or a name for messages when made in memory
  std::string vio_path;  ///< the odometry file read (DIR/vio.tum or the one given); empty when made in memory
  TrajectoryFormat vio_format = TrajectoryFormat::kTum;  ///< its format, as recognised
  OdometryLog odometry;  ///< relative covariances filled from the absolute ones when the file has them
  int covariance_clamped = 0;  ///< eigenvalues toRelativeCovariances raised to its floor
  int covariance_shrinks = 0;  ///< samples whose absolute covariance really shrank (a VIO reset or loop closure)
  bool has_corners = false;
  std::vector<CornerDetection> corners;        ///< when has_corners
  std::vector<GateObservation> pose_detections;  ///< otherwise
  std::vector<int> pose_detection_lines;         ///< their lines in detections.csv (empty when made in memory)
  Track map;
  std::optional<CameraModel> camera;
  std::optional<OdometryLog> ground_truth;

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Reads a sequence folder. `default_detection_covariance` is used for detections.csv rows without
/// covariance (metric [t; θ], m², rad²). Every reader's error is passed on unchanged (file, line, field);
/// missing required files, both or neither detection file, or corners without a camera are
/// kNotFound / kInvalidArgument naming the folder and the file. A non-empty `vio_path` is read instead of
/// DIR/vio.tum (which may then be absent), e.g. OpenVINS' traj_estimate.txt where it was written, or `-` for
/// standard input (read once, as a pipe is; errors name it "stdin").
Result<Sequence> loadSequence(const std::string& dir, const Matrix6d& default_detection_covariance,
                              const std::string& vio_path = "");

/// Checks that every detection's gate id is −1 (unknown: the association decides) or a gate of `sequence.map`.
/// A detection naming another gate is kNotFound "DIR/corners.csv:LINE: field 'gate_id': gate 7 is not in the
/// map (DIR/gates.yaml has 0, 1, 2, 3)", unless `skip_unknown`: then every such detection is removed and the
/// count returned (the caller warns). Not for mapping runs, whose detectors may name gates the map lacks.
Result<int> checkDetectionGateIds(Sequence& sequence, bool skip_unknown);

/// Writes `sequence` as the folder `dir` (created if missing) that loadSequence reads back: vio.tum (with
/// the 21 absolute-covariance columns when the odometry has them), corners.csv or detections.csv,
/// gates.yaml, camera.yaml (when there is a camera), gt.tum (when there is ground truth) and, when
/// `provenance_yaml` is not empty, sequence.yaml holding that text (how the sequence was made). Each file
/// is written atomically. The readers' own kInvalidArgument for values they could not read back;
/// kIoError naming the file or folder that could not be written.
Status writeSequence(const std::string& dir, const Sequence& sequence, const std::string& provenance_yaml = "");

}  // namespace dualgraph
