// SPDX-License-Identifier: MIT
#include "frontend/io/sequence_folder.h"

#include <filesystem>

#include "core/atomic_file.h"
#include "frontend/io/camera_io.h"
#include "frontend/io/track_io.h"
#include "frontend/io/trajectory_io.h"

namespace dualgraph {

Result<Sequence> loadSequence(const std::string& dir, const Matrix6d& default_detection_covariance) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(dir, error)) return Status(StatusCode::kNotFound, dir + ": not a sequence folder");
  const fs::path folder(dir);
  auto file = [&](const char* name) { return (folder / name).string(); };
  auto exists = [&](const char* name) { return fs::exists(folder / name, error); };

  Sequence sequence;
  sequence.dir = dir;
  if (!exists("vio.tum")) return Status(StatusCode::kNotFound, file("vio.tum") + ": missing (the odometry is required)");
  auto odometry = readTumOdometry(file("vio.tum"));
  if (!odometry.ok()) return odometry.status();
  sequence.odometry = std::move(odometry).value();
  if (!sequence.odometry.absolute_covariances.empty()) {
    auto report = toRelativeCovariances(sequence.odometry);
    if (!report.ok()) return Status(report.status().code(), file("vio.tum") + ": " + report.status().message());
    sequence.covariance_clamped = report->clamped;
  }

  const bool corners = exists("corners.csv");
  const bool poses = exists("detections.csv");
  if (corners == poses) {
    return Status(StatusCode::kInvalidArgument,
                  dir + (corners ? ": both corners.csv and detections.csv present (which one is meant?)"
                                 : ": no detections (corners.csv or detections.csv)"));
  }
  sequence.has_corners = corners;
  if (corners) {
    auto read = readCornerDetections(file("corners.csv"));
    if (!read.ok()) return read.status();
    sequence.corners = std::move(read).value();
  } else {
    auto read = readPoseDetections(file("detections.csv"), default_detection_covariance);
    if (!read.ok()) return read.status();
    sequence.pose_detections = std::move(read).value();
  }

  if (!exists("gates.yaml")) return Status(StatusCode::kNotFound, file("gates.yaml") + ": missing (the gate map)");
  auto map = loadTrackYaml(file("gates.yaml"));
  if (!map.ok()) return map.status();
  sequence.map = std::move(map).value();

  if (exists("camera.yaml")) {
    auto camera = loadCameraYaml(file("camera.yaml"));
    if (!camera.ok()) return camera.status();
    sequence.camera = std::move(camera).value();
  } else if (corners) {
    return Status(StatusCode::kNotFound, file("camera.yaml") + ": missing (corner detections need the camera)");
  }
  if (exists("gt.tum")) {
    auto truth = readTumOdometry(file("gt.tum"));
    if (!truth.ok()) return truth.status();
    sequence.ground_truth = std::move(truth).value();
  }
  return sequence;
}

Status writeSequence(const std::string& dir, const Sequence& sequence, const std::string& provenance_yaml) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) return Status(StatusCode::kIoError, dir + ": cannot create the folder: " + error.message());
  const std::filesystem::path folder(dir);
  auto file = [&](const char* name) { return (folder / name).string(); };
  if (sequence.ground_truth) DG_RETURN_IF_ERROR(writeTumOdometry(file("gt.tum"), *sequence.ground_truth));
  DG_RETURN_IF_ERROR(writeTumOdometry(file("vio.tum"), sequence.odometry));
  if (sequence.has_corners) {
    DG_RETURN_IF_ERROR(writeCornerDetections(file("corners.csv"), sequence.corners));
  } else {
    DG_RETURN_IF_ERROR(writePoseDetections(file("detections.csv"), sequence.pose_detections));
  }
  DG_RETURN_IF_ERROR(saveTrackYaml(file("gates.yaml"), sequence.map));
  if (sequence.camera) DG_RETURN_IF_ERROR(saveCameraYaml(file("camera.yaml"), *sequence.camera));
  if (provenance_yaml.empty()) return Status();
  return writeFileAtomically(file("sequence.yaml"), [&](std::ostream& out) {
    out << provenance_yaml;
    return Status();
  });
}

}  // namespace dualgraph
