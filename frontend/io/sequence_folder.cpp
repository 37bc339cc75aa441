// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/sequence_folder.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/io/trajectory_io.h"

namespace dualgraph {

Result<Sequence> loadSequence(const std::string& dir, const Matrix6d& default_detection_covariance,
                              const std::string& vio_path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(dir, error)) return Status(StatusCode::kNotFound, dir + ": not a sequence folder");
  const fs::path folder(dir);
  auto file = [&](const char* name) { return (folder / name).string(); };
  auto exists = [&](const char* name) { return fs::exists(folder / name, error); };

  Sequence sequence;
  sequence.dir = dir;
  sequence.vio_path = vio_path.empty() ? file("vio.tum") : vio_path;
  if (sequence.vio_path != "-" && !fs::exists(sequence.vio_path, error)) {  // `-`: standard input
    return Status(StatusCode::kNotFound, sequence.vio_path + ": missing (the odometry is required)");
  }
  auto odometry = readTrajectory(sequence.vio_path, &sequence.vio_format);
  if (!odometry.ok()) return odometry.status();
  sequence.odometry = std::move(odometry).value();
  if (!sequence.odometry.absolute_covariances.empty()) {
    auto report = toRelativeCovariances(sequence.odometry);
    if (!report.ok()) return Status(report.status().code(), sequence.vio_path + ": " + report.status().message());
    sequence.covariance_clamped = report->clamped;
    sequence.covariance_shrinks = report->shrinks;
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
    auto read = readPoseDetections(file("detections.csv"), default_detection_covariance, &sequence.pose_detection_lines);
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
    auto truth = readTrajectory(file("gt.tum"));
    if (!truth.ok()) return truth.status();
    sequence.ground_truth = std::move(truth).value();
  }
  return sequence;
}

Result<int> checkDetectionGateIds(Sequence& sequence, bool skip_unknown) {
  std::set<int> known;
  for (const TrackGate& gate : sequence.map.gates) known.insert(gate.id);
  auto unknown = [&](int gate_id) { return gate_id >= 0 && known.count(gate_id) == 0; };
  const size_t count = sequence.has_corners ? sequence.corners.size() : sequence.pose_detections.size();
  for (size_t i = 0; i < count && !skip_unknown; ++i) {
    const int gate_id = sequence.has_corners ? sequence.corners[i].gate_id : sequence.pose_detections[i].gate_id;
    if (!unknown(gate_id)) continue;
    const std::filesystem::path folder(sequence.dir);
    std::string where = (folder / (sequence.has_corners ? "corners.csv" : "detections.csv")).string();
    const int line = sequence.has_corners                          ? sequence.corners[i].line
                     : i < sequence.pose_detection_lines.size() ? sequence.pose_detection_lines[i]
                                                                : 0;
    where += line > 0 ? ":" + std::to_string(line) : " (detection " + std::to_string(i) + ")";
    std::string ids;
    for (int id : known) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
    return Status(StatusCode::kNotFound, where + ": field 'gate_id': gate " + std::to_string(gate_id) +
                                             " is not in the map (" + (folder / "gates.yaml").string() + " has " +
                                             (ids.empty() ? "none" : ids) + "); --skip-unknown-gates drops such detections");
  }
  int skipped = 0;
  if (sequence.has_corners) {
    const size_t before = sequence.corners.size();
    sequence.corners.erase(std::remove_if(sequence.corners.begin(), sequence.corners.end(),
                                          [&](const CornerDetection& d) { return unknown(d.gate_id); }),
                           sequence.corners.end());
    skipped = static_cast<int>(before - sequence.corners.size());
  } else {
    std::vector<GateObservation> kept;
    std::vector<int> kept_lines;
    for (size_t i = 0; i < sequence.pose_detections.size(); ++i) {
      if (unknown(sequence.pose_detections[i].gate_id)) {
        ++skipped;
        continue;
      }
      kept.push_back(sequence.pose_detections[i]);
      if (i < sequence.pose_detection_lines.size()) kept_lines.push_back(sequence.pose_detection_lines[i]);
    }
    sequence.pose_detections = std::move(kept);
    sequence.pose_detection_lines = std::move(kept_lines);
  }
  return skipped;
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
