// SPDX-License-Identifier: MIT
// The cross-reader bad-input catalogue's pieces: which loader a case goes through, a minimal valid
// sequence folder to spoil one file of, and the check that a status names file, line and field.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/status.h"
#include "dualgraph/frontend/io/localizer_params_yaml.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/types/register_types.h"

namespace dualgraph::testing {

/// The public loader a catalogue case is fed to.
enum class Loader {
  kG2o,              ///< readG2o with the built-in types
  kTum,              ///< readTumOdometry (also OpenVINS' TUM-like output)
  kEuroc,            ///< readEurocOdometry
  kCorners,          ///< readCornerDetections
  kPoses,            ///< readPoseDetections (default covariance 0.01·I)
  kTrack,            ///< loadTrackYaml (a sequence's gates.yaml is one)
  kCamera,           ///< loadCameraYaml
  kRatmJson,         ///< loadRatmCalibrationJson (radtan, 640×480)
  kLocalizerConfig,  ///< loadLocalizerParams
  kRunConfig,        ///< loadRunConfig
  kSequence,         ///< loadSequence on validSequence() with `file` replaced by `content`
};

/// Loads `path` (a file, or for kSequence the folder) with `loader`; only the status is kept.
inline Status loadWith(Loader loader, const std::string& path) {
  switch (loader) {
    case Loader::kG2o: {
      TypeRegistry registry;
      if (!registerBuiltinTypes(registry).ok()) return Status(StatusCode::kFailedPrecondition, "registry");
      Graph graph;
      return readG2o(path, registry, graph).status();
    }
    case Loader::kTum: return readTumOdometry(path).status();
    case Loader::kEuroc: return readEurocOdometry(path).status();
    case Loader::kCorners: return readCornerDetections(path).status();
    case Loader::kPoses: return readPoseDetections(path, 0.01 * Matrix6d::Identity()).status();
    case Loader::kTrack: return loadTrackYaml(path).status();
    case Loader::kCamera: return loadCameraYaml(path).status();
    case Loader::kRatmJson: return loadRatmCalibrationJson(path).status();
    case Loader::kLocalizerConfig: return loadLocalizerParams(path).status();
    case Loader::kRunConfig: return loadRunConfig(path).status();
    case Loader::kSequence: return loadSequence(path, 0.01 * Matrix6d::Identity()).status();
  }
  return Status(StatusCode::kFailedPrecondition, "unknown loader");
}

/// The files of a small valid sequence folder (three odometry samples, one pose detection, two
/// gates, a camera); each sequence case replaces one of them.
inline const char* const kValidSequence[][2] = {
    {"vio.tum", "0.0 0 0 0 0 0 0 1\n0.1 0.8 0 0 0 0 0 1\n0.2 1.6 0 0 0 0 0 1\n"},
    {"detections.csv", "t,gate_id,x,y,z,qx,qy,qz,qw\n0.1,1,4,0,0,0,0,0,1\n"},
    {"gates.yaml", "gates:\n  - {id: 1, position: [5, 0, 0], yaw: 0}\n  - {id: 2, position: [10, 2, 0], yaw: 0}\n"},
    {"camera.yaml",
     "model: radtan\nwidth: 640\nheight: 480\nfx: 300\nfy: 300\ncx: 320\ncy: 240\ndistortion: [0, 0, 0, 0]\n"},
    {"gt.tum", "0.0 0 0 0 0 0 0 1\n0.2 1.6 0 0 0 0 0 1\n"},
};

/// Writes the valid sequence into `dir` (created), then `file` with `content` (`file` may be a
/// new name, e.g. corners.csv next to detections.csv).
inline void writeSequenceWith(const std::filesystem::path& dir, const std::string& file, const std::string& content) {
  std::filesystem::create_directories(dir);
  for (const auto& entry : kValidSequence) std::ofstream(dir / entry[0], std::ios::binary) << entry[1];
  std::ofstream(dir / file, std::ios::binary | std::ios::trunc) << content;
}

/// A failed status whose message holds `path` followed by ":LINE:" (line > 0) or `path` alone,
/// and `field` (when not empty), on one line.
inline ::testing::AssertionResult namesFileLineAndField(const Status& status, const std::string& path, int line,
                                                        const std::string& field) {
  if (status.ok()) return ::testing::AssertionFailure() << "expected an error, got OK";
  const std::string& message = status.message();
  const std::string location = line > 0 ? path + ":" + std::to_string(line) + ":" : path;
  if (message.find(location) == std::string::npos) {
    return ::testing::AssertionFailure() << "does not name '" << location << "': " << message;
  }
  if (!field.empty() && message.find(field) == std::string::npos) {
    return ::testing::AssertionFailure() << "does not name '" << field << "': " << message;
  }
  if (message.find('\n') != std::string::npos) return ::testing::AssertionFailure() << "not one line: " << message;
  return ::testing::AssertionSuccess() << message;
}

}  // namespace dualgraph::testing
