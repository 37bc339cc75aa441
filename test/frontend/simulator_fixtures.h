// SPDX-License-Identifier: MIT
#pragma once

// Shared by the race-simulator tests (simulator_*_test.cpp): the shipped RATM tracks, camera and
// flights, sampled truth, a temporary folder, and the 90°-turn alignment and NEES of a gate pose.
// Everything is deterministic (no time-based seeds).

#include <gtest/gtest.h>
#include <stdlib.h>  // mkdtemp

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/simulation/flight.h"
#include "dualgraph/frontend/gates/track.h"
#include "dualgraph/frontend/io/track_io.h"
#include "test/testing/shared_data.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph::simtest {

/// data/tracks/<name> (ratm_ellipse.yaml, ratm_lemniscate.yaml); fails the test if it does not load.
inline Track shippedTrack(const std::string& name) {
  auto track = loadTrackYaml(testing::sourcePath("data/tracks/" + name));
  EXPECT_TRUE(track.ok()) << track.status().toString();
  return track.ok() ? *track : Track();
}

/// data/cameras/ratm_piloted.yaml: the RATM fisheye with its ~28° up-tilted mount.
inline CameraModel ratmCamera() {
  auto camera = loadCameraYaml(testing::sourcePath("data/cameras/ratm_piloted.yaml"));
  EXPECT_TRUE(camera.ok()) << camera.status().toString();
  return camera.ok() ? *camera : CameraModel();
}

/// The flight of a shipped track with its laps (or `laps` when > 0) and top speed, default FlightParams.
inline Flight ratmFlight(const std::string& name, int laps = 0) {
  const Track track = shippedTrack(name);
  FlightParams params;
  params.laps = laps > 0 ? laps : track.laps;
  params.max_speed = track.speed;
  auto flight = Flight::plan(track.path, params);
  EXPECT_TRUE(flight.ok()) << flight.status().toString();
  return flight.ok() ? *flight : Flight();
}

/// A closed 7-waypoint course with height changes and unequal spacing (a kWaypoints path).
inline TrackPath waypointCoursePath() {
  TrackPath path;
  path.type = TrackPath::Type::kWaypoints;
  path.waypoints = {{0, 0, 1}, {8, 1, 1.5}, {12, 6, 2}, {7, 11, 1.2}, {0, 9, 1}, {-5, 6, 2.5}, {-4, 1, 1.5}};
  return path;
}

/// True poses of a flight sampled at `rate` [Hz] from t = 0 (the input simulateVio takes).
struct SampledTruth {
  std::vector<double> t;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> world_T_body;
};
inline SampledTruth sampleTruth(const Flight& flight, double rate) {
  SampledTruth truth;
  for (long k = 0; k / rate <= flight.duration(); ++k) {
    truth.t.push_back(k / rate);
    truth.world_T_body.push_back(flight.at(truth.t.back()).world_T_body);
  }
  return truth;
}

inline double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// Geodesic angle between the rotations of two poses [rad].
inline double rotationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return so3Log(a.linear().transpose() * b.linear()).norm();
}

/// The square gate's frame is fixed by the image corner order only up to 90° turns about its normal
/// (x): `estimate · Rx(q·90°)` for the q whose rotation is closest to `truth`, and the covariance of
/// the turned pose (a right perturbation moves with the turn: Ad(turn⁻¹) Σ Ad(turn⁻¹)ᵀ).
inline void alignQuarterTurn(Eigen::Isometry3d& estimate, Matrix6d* covariance, const Eigen::Isometry3d& truth) {
  Eigen::Isometry3d best_turn = Eigen::Isometry3d::Identity();
  double best_angle = 1e9;
  for (int quarter = 0; quarter < 4; ++quarter) {
    Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
    turn.linear() = Eigen::AngleAxisd(quarter * M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const double angle = rotationError(estimate * turn, truth);
    if (angle < best_angle) {
      best_angle = angle;
      best_turn = turn;
    }
  }
  estimate = estimate * best_turn;
  if (covariance != nullptr) {
    const Matrix6d adjoint = se3Adjoint(best_turn.inverse());
    *covariance = adjoint * *covariance * adjoint.transpose();
  }
}

/// A fresh folder under the system's temporary directory, removed with the object.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "dualgraph_simulator_test_XXXXXX").string();
    path_ = mkdtemp(pattern.data()) != nullptr ? pattern : "";
    EXPECT_FALSE(path_.empty());
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  std::string operator/(const std::string& name) const { return (std::filesystem::path(path_) / name).string(); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

inline std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << path;
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

/// Normalised estimation error squared of `estimate` against `truth` for a metric [t; θ] covariance in
/// the chart the graph's edges use: e = se3BoxMinus(estimate, truth), eᵀ Σ⁻¹ e.
inline double poseNees(const Eigen::Isometry3d& estimate, const Matrix6d& covariance, const Eigen::Isometry3d& truth) {
  const Vector6d error = se3BoxMinus(estimate, truth);
  return error.dot(covariance.ldlt().solve(error));
}

}  // namespace dualgraph::simtest
