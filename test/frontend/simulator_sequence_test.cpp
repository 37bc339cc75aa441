// SPDX-License-Identifier: MIT
// The race simulator's sequence folder (race_simulator.h: simulateRace; race_sequence.h: writeRaceSequence), read back
// with the frontend's own readers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/frontend/simulation/race_sequence.h"
#include "dualgraph/frontend/io/track_io.h"
#include "test/frontend/simulator_fixtures.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;
using simtest::fileBytes;
using simtest::TemporaryFolder;

RaceSimParams shortRace(std::uint64_t seed) {
  RaceSimParams params;
  params.seed = seed;
  params.override_laps = true;
  params.flight.laps = 2;
  return params;
}

struct Written {
  Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  CameraModel camera = simtest::ratmCamera();
  SimulatedRace race;
};

Written simulateAndWrite(const std::string& dir, const RaceSimParams& params) {
  Written out;
  auto race = simulateRace(out.track, out.camera, params);
  EXPECT_TRUE(race.ok()) << race.status().toString();
  if (!race.ok()) return out;
  out.race = std::move(race).value();
  const Status status = writeRaceSequence(dir, out.race, out.track, params);
  EXPECT_TRUE(status.ok()) << status.toString();
  return out;
}

void expectSamePose(const Eigen::Isometry3d& read, const Eigen::Isometry3d& written, const std::string& where) {
  EXPECT_TRUE(read.translation() == written.translation()) << where;  // 17 digits: bit-exact
  EXPECT_LT((read.linear() - written.linear()).cwiseAbs().maxCoeff(), 1e-15) << where;
}

const char* const kFiles[] = {"gt.tum", "vio.tum", "corners.csv", "gates.yaml", "camera.yaml", "sequence.yaml"};

TEST(SimulatedRace, VioUnalignedRmseOnRatmTracksIsInTheOpenVinsRange) {
  // Issue 4's acceptance criterion: raw VIO error 0.8–2.2 m RMSE (unaligned) on both RATM tracks, seeds 1–3.
  const CameraModel camera = simtest::ratmCamera();
  for (const char* name : {"ratm_ellipse.yaml", "ratm_lemniscate.yaml"}) {
    const Track track = simtest::shippedTrack(name);
    for (std::uint64_t seed : {1, 2, 3}) {
      RaceSimParams params;
      params.seed = seed;
      params.detection.camera_rate = 1.0;  // detections are not needed here
      auto race = simulateRace(track, camera, params);
      ASSERT_TRUE(race.ok()) << race.status().toString();
      double sum = 0.0;
      for (const OdometrySample& s : race->vio.samples) {
        sum += (s.odom_T_body.translation() - race->flight.at(s.t).position).squaredNorm();
      }
      const double rmse = std::sqrt(sum / static_cast<double>(race->vio.samples.size()));
      std::printf("[ measured ] %s seed %d: VIO RMSE %.3f m\n", name, static_cast<int>(seed), rmse);
      EXPECT_GE(rmse, 0.8) << name << " seed " << seed;
      EXPECT_LE(rmse, 2.2) << name << " seed " << seed;
    }
  }
}

TEST(SimulatedSequence, EveryFileReadsBackWithTheFrontendReaders) {
  TemporaryFolder folder;
  const RaceSimParams params = shortRace(5);
  const Written w = simulateAndWrite(folder.path(), params);
  for (const char* name : kFiles) EXPECT_TRUE(fs::exists(folder / name)) << name;

  auto gt = readTumOdometry(folder / "gt.tum");
  ASSERT_TRUE(gt.ok()) << gt.status().toString();
  ASSERT_EQ(gt->samples.size(), w.race.ground_truth.size());
  EXPECT_TRUE(gt->absolute_covariances.empty());
  EXPECT_NEAR(gt->samples[1].t - gt->samples[0].t, 1.0 / params.gt_rate, 1e-12);
  for (size_t k = 0; k < gt->samples.size(); ++k) {
    ASSERT_EQ(gt->samples[k].t, w.race.ground_truth[k].first);
    expectSamePose(gt->samples[k].odom_T_body, w.race.ground_truth[k].second, "gt " + std::to_string(k));
  }

  auto vio = readTumOdometry(folder / "vio.tum");
  ASSERT_TRUE(vio.ok()) << vio.status().toString();
  ASSERT_EQ(vio->samples.size(), w.race.vio.samples.size());
  ASSERT_EQ(vio->absolute_covariances.size(), vio->samples.size());
  for (size_t k = 0; k < vio->samples.size(); ++k) {
    ASSERT_EQ(vio->samples[k].t, w.race.vio.samples[k].t);
    expectSamePose(vio->samples[k].odom_T_body, w.race.vio.samples[k].odom_T_body, "vio " + std::to_string(k));
    ASSERT_TRUE(vio->absolute_covariances[k] == w.race.vio.absolute_covariances[k]) << "vio covariance " << k;
  }
  // The Localizer's path, absolute → relative: Q·Δt as vio_drift.h documents it, nothing clamped.
  auto relative = toRelativeCovariances(*vio);
  ASSERT_TRUE(relative.ok());
  EXPECT_EQ(relative->clamped, 0);
  const VioDriftParams& p = params.vio;
  const double bound = 1.0 + p.bias_spread, q_r = std::pow(p.yaw_rate_bias * bound, 2) + std::pow(p.yaw_random_walk, 2);
  for (size_t k = 1; k < vio->samples.size(); ++k) {
    const double t = vio->samples[k].t, dt = t - vio->samples[k - 1].t;
    const double speed = (w.race.flight.at(t).position - w.race.flight.at(vio->samples[k - 1].t).position).norm() / dt;
    const double q_t = std::pow(p.velocity_bias * bound, 2) + std::pow(p.vertical_velocity_bias * bound, 2) +
                       std::pow(p.scale_error_sigma * speed, 2) + std::pow(p.velocity_bias_random_walk, 2) * t;
    const Vector6d q = (Vector6d() << q_t, q_t, q_t, q_r, q_r, q_r).finished() * dt;
    const Matrix6d difference = *vio->samples[k].relative_covariance - Matrix6d(q.asDiagonal());
    ASSERT_LT(difference.cwiseAbs().maxCoeff(), 1e-6 * q.maxCoeff()) << "sample " << k << "\n" << *vio->samples[k].relative_covariance;
  }

  auto corners = readCornerDetections(folder / "corners.csv");
  ASSERT_TRUE(corners.ok()) << corners.status().toString();
  ASSERT_EQ(corners->size(), w.race.detections.size());
  ASSERT_GT(corners->size(), 100u);
  for (size_t i = 0; i < corners->size(); ++i) {
    const CornerDetection& written = w.race.detections[i].corners;
    ASSERT_EQ((*corners)[i].t, written.t);
    ASSERT_EQ((*corners)[i].gate_id, written.gate_id);
    for (size_t c = 0; c < 4; ++c) ASSERT_EQ((*corners)[i].corners[c], written.corners[c]) << "detection " << i;
  }

  auto gates = loadTrackYaml(folder / "gates.yaml");
  ASSERT_TRUE(gates.ok()) << gates.status().toString();
  EXPECT_EQ(gates->path.type, TrackPath::Type::kNone);
  ASSERT_EQ(gates->gates.size(), w.track.gates.size());
  for (size_t g = 0; g < gates->gates.size(); ++g) {
    EXPECT_EQ(gates->gates[g].id, w.track.gates[g].id);
    EXPECT_EQ(gates->gates[g].position, w.track.gates[g].position);  // unperturbed by default
    EXPECT_EQ(gates->gates[g].yaw, w.track.gates[g].yaw);
    EXPECT_EQ(gates->gates[g].size, w.track.gates[g].size);
  }

  auto camera = loadCameraYaml(folder / "camera.yaml");
  ASSERT_TRUE(camera.ok()) << camera.status().toString();
  EXPECT_EQ(camera->model, w.camera.model);
  EXPECT_EQ(camera->K, w.camera.K);
  EXPECT_EQ(camera->distortion, w.camera.distortion);
  EXPECT_EQ(camera->width, w.camera.width);
  expectSamePose(camera->body_T_camera, w.camera.body_T_camera, "body_T_camera");

  const std::string sequence = fileBytes(folder / "sequence.yaml");
  EXPECT_NE(sequence.find("seed: 5\n"), std::string::npos);
  EXPECT_NE(sequence.find("detections: corners\n"), std::string::npos);
  EXPECT_NE(sequence.find("  laps: 2\n"), std::string::npos);
  std::string track_text;  // the track, verbatim, indented under `track: |`
  std::istringstream lines(sequence.substr(sequence.find("track: |\n") + 9));
  for (std::string line; std::getline(lines, line);) track_text += line.substr(2) + "\n";
  auto track = parseTrackYaml(track_text, "sequence.yaml");
  ASSERT_TRUE(track.ok()) << track.status().toString();
  EXPECT_EQ(trackToYaml(*track), trackToYaml(w.track));
}

// The in-memory sequence of a race (what ablation and the benchmarks run) is the one its folder reads back
// as: same samples, detections, map and camera; poses equal up to the quaternion round trip of the files.
TEST(SimulatedSequence, InMemorySequenceEqualsTheFolderReadBack) {
  TemporaryFolder folder;
  const RaceSimParams params = shortRace(4);
  const Written written = simulateAndWrite(folder.path(), params);
  auto read = loadSequence(folder.path(), Matrix6d::Identity());
  ASSERT_TRUE(read.ok()) << read.status().toString();
  auto made = raceSequence(written.race, params, "in memory");
  ASSERT_TRUE(made.ok()) << made.status().toString();
  EXPECT_EQ(made->dir, "in memory");
  ASSERT_EQ(made->odometry.samples.size(), read->odometry.samples.size());
  for (size_t k = 0; k < made->odometry.samples.size(); ++k) {
    const OdometrySample& a = made->odometry.samples[k];
    const OdometrySample& b = read->odometry.samples[k];
    ASSERT_EQ(a.t, b.t);
    expectSamePose(b.odom_T_body, a.odom_T_body, "vio " + std::to_string(k));
    ASSERT_EQ(a.relative_covariance.has_value(), b.relative_covariance.has_value()) << k;
    if (a.relative_covariance) {
      EXPECT_LT((*a.relative_covariance - *b.relative_covariance).cwiseAbs().maxCoeff(), 1e-12) << k;
    }
  }
  EXPECT_EQ(made->covariance_clamped, read->covariance_clamped);
  ASSERT_TRUE(made->has_corners && read->has_corners);
  ASSERT_EQ(made->corners.size(), read->corners.size());
  for (size_t k = 0; k < made->corners.size(); ++k) {
    EXPECT_EQ(made->corners[k].t, read->corners[k].t);
    EXPECT_EQ(made->corners[k].gate_id, read->corners[k].gate_id);
    for (int c = 0; c < 4; ++c) EXPECT_TRUE(made->corners[k].corners[c] == read->corners[k].corners[c]) << k;
  }
  ASSERT_EQ(made->map.gates.size(), read->map.gates.size());
  for (size_t g = 0; g < made->map.gates.size(); ++g) {
    EXPECT_TRUE(made->map.gates[g].position == read->map.gates[g].position) << g;
    EXPECT_EQ(made->map.gates[g].yaw, read->map.gates[g].yaw) << g;
  }
  ASSERT_TRUE(made->camera && read->camera);
  ASSERT_TRUE(made->ground_truth && read->ground_truth);
  ASSERT_EQ(made->ground_truth->samples.size(), read->ground_truth->samples.size());
  expectSamePose(read->ground_truth->samples.back().odom_T_body, made->ground_truth->samples.back().odom_T_body, "gt");
}

TEST(SimulatedSequence, SameSeedGivesByteIdenticalFilesAnotherSeedDifferentOnes) {
  TemporaryFolder a, b, c;
  simulateAndWrite(a.path(), shortRace(5));
  simulateAndWrite(b.path(), shortRace(5));
  simulateAndWrite(c.path(), shortRace(6));
  for (const char* name : kFiles) EXPECT_EQ(fileBytes(a / name), fileBytes(b / name)) << name;
  for (const char* name : {"vio.tum", "corners.csv", "sequence.yaml"}) EXPECT_NE(fileBytes(a / name), fileBytes(c / name)) << name;
  // The flight, the unperturbed map and the camera do not depend on the seed.
  for (const char* name : {"gt.tum", "gates.yaml", "camera.yaml"}) EXPECT_EQ(fileBytes(a / name), fileBytes(c / name)) << name;
}

TEST(SimulatedSequence, PoseDetectionsParseAndLieWithinAFewSigmaOfTruth) {
  TemporaryFolder folder;
  RaceSimParams params = shortRace(8);
  params.output = RaceSimParams::DetectionOutput::kPoses;
  params.detection.displaced_corner_probability = params.detection.wrong_id_probability = 0.0;
  params.detection.false_gate_probability = 0.0;
  params.detection.max_range = 6.0;  // where the PnP covariance is honest (sensors test: NEES)
  const Written w = simulateAndWrite(folder.path(), params);
  EXPECT_FALSE(fs::exists(folder / "corners.csv"));
  auto poses = readPoseDetections(folder / "detections.csv", Matrix6d::Identity());
  ASSERT_TRUE(poses.ok()) << poses.status().toString();
  ASSERT_EQ(poses->size(), w.race.pose_detections.size());
  EXPECT_EQ(static_cast<int>(poses->size()) + w.race.pnp_rejected, static_cast<int>(w.race.detections.size()));
  ASSERT_GT(poses->size(), 100u);
  const GateMap map = w.track.gateMap().value();
  std::vector<double> nees;
  for (size_t i = 0; i < poses->size(); ++i) {
    const GateObservation& read = (*poses)[i];
    ASSERT_EQ(read.t, w.race.pose_detections[i].t);
    ASSERT_EQ(read.gate_id, w.race.pose_detections[i].gate_id);
    ASSERT_TRUE(read.pose_covariance == w.race.pose_detections[i].pose_covariance) << i;
    const Eigen::Isometry3d truth = w.race.flight.at(read.t).world_T_body.inverse() * map.world_T_gate.at(read.gate_id);
    nees.push_back(simtest::poseNees(read.body_T_gate, read.pose_covariance, truth));
  }
  std::sort(nees.begin(), nees.end());
  const double median = nees[nees.size() / 2], p99 = nees[nees.size() * 99 / 100];
  std::printf("[ measured ] %zu pose detections (%d rejected): NEES median %.2f, 99th percentile %.2f, max %.1f\n",
              nees.size(), w.race.pnp_rejected, median, p99, nees.back());
  EXPECT_NEAR(median, 5.35, 1.0);  // χ²₆'s median
  EXPECT_LT(p99, 22.46);           // χ²₆'s 99.9 % quantile: a few σ
}

TEST(SimulatedSequence, MapPerturbationMovesGatesByAboutItsSigma) {
  const Track track = simtest::shippedTrack("ratm_lemniscate.yaml");
  const CameraModel camera = simtest::ratmCamera();
  double position_squares = 0.0, yaw_squares = 0.0;
  int position_count = 0, yaw_count = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    RaceSimParams params = shortRace(seed);
    params.flight.laps = 1;
    params.detection.camera_rate = 1.0;
    params.map_position_sigma = 0.3;
    params.map_yaw_sigma = 0.05;
    auto race = simulateRace(track, camera, params);
    ASSERT_TRUE(race.ok());
    ASSERT_EQ(race->map.gates.size(), track.gates.size());
    for (size_t g = 0; g < track.gates.size(); ++g) {
      EXPECT_EQ(race->map.gates[g].id, track.gates[g].id);
      position_squares += (race->map.gates[g].position - track.gates[g].position).squaredNorm();
      position_count += 3;
      yaw_squares += std::pow(race->map.gates[g].yaw - track.gates[g].yaw, 2);
      ++yaw_count;
    }
  }
  // 60 position and 20 yaw draws: the RMS / σ lies in √(χ²_n / n)'s 99.8 % band.
  const double position_rms = std::sqrt(position_squares / position_count) / 0.3;
  const double yaw_rms = std::sqrt(yaw_squares / yaw_count) / 0.05;
  std::printf("[ measured ] map perturbation RMS / sigma: position %.3f, yaw %.3f\n", position_rms, yaw_rms);
  EXPECT_GT(position_rms, 0.727);
  EXPECT_LT(position_rms, 1.288);
  EXPECT_GT(yaw_rms, 0.54);
  EXPECT_LT(yaw_rms, 1.50);

  TemporaryFolder folder;  // the perturbed map is the one written
  RaceSimParams params = shortRace(3);
  params.map_position_sigma = 0.3;
  const Written w = simulateAndWrite(folder.path(), params);
  auto gates = loadTrackYaml(folder / "gates.yaml");
  ASSERT_TRUE(gates.ok());
  for (size_t g = 0; g < gates->gates.size(); ++g) {
    EXPECT_EQ(gates->gates[g].position, w.race.map.gates[g].position);
    EXPECT_GT((gates->gates[g].position - w.track.gates[g].position).norm(), 1e-3);
  }
}

TEST(SimulatedSequence, UnwritableFolderIsIoErrorAndLeavesNoTemporaryFile) {
  const Track track = simtest::shippedTrack("ratm_ellipse.yaml");
  const CameraModel camera = simtest::ratmCamera();
  RaceSimParams params = shortRace(2);
  params.flight.laps = 1;
  auto race = simulateRace(track, camera, params);
  ASSERT_TRUE(race.ok());
  TemporaryFolder folder;
  {
    std::ofstream(folder / "plain_file") << "x";
  }
  const Status under_file = writeRaceSequence(folder / "plain_file/sequence", *race, track, params);
  EXPECT_EQ(under_file.code(), StatusCode::kIoError) << under_file.toString();
  // corners.csv taken by a non-empty folder: its temporary file is written, the rename fails (also as
  // root, which ignores permission bits).
  fs::create_directories(folder / "seq/corners.csv/occupied");
  const Status blocked = writeRaceSequence(folder / "seq", *race, track, params);
  EXPECT_EQ(blocked.code(), StatusCode::kIoError) << blocked.toString();
  EXPECT_NE(blocked.message().find("corners.csv"), std::string::npos) << blocked.message();
  for (const auto& entry : fs::directory_iterator(folder / "seq")) {
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
  }
  EXPECT_TRUE(fs::exists(folder / "seq/vio.tum"));  // written before the failure, complete
  EXPECT_TRUE(readTumOdometry(folder / "seq/vio.tum").ok());
}

}  // namespace
}  // namespace dualgraph
