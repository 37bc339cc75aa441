// SPDX-License-Identifier: MIT
#include "bench/race_fixture.h"

#include <cstdlib>
#include <filesystem>

#include "bench/bench_data.h"
#include "frontend/camera_io.h"
#include "frontend/gate_frontend.h"
#include "frontend/odometry_io.h"
#include "frontend/race_simulator.h"
#include "frontend/run_config.h"
#include "frontend/track_io.h"

namespace dualgraph::bench {
namespace {

/// A folder under $TMPDIR (or /tmp) removed with the process's static objects.
struct TempFolder {
  std::string path;
  TempFolder() {
    std::string pattern = std::string(std::getenv("TMPDIR") != nullptr ? std::getenv("TMPDIR") : "/tmp") +
                          "/dualgraph_bench_XXXXXX";
    if (mkdtemp(pattern.data()) != nullptr) path = pattern;
  }
  ~TempFolder() {
    std::error_code ignored;
    if (!path.empty()) std::filesystem::remove_all(path, ignored);
  }
};

Result<Sequence> simulate(const std::string& dir) {
  if (dir.empty()) return Status(StatusCode::kIoError, "could not create a temporary folder");
  Result<Track> track = loadTrackYaml(repositoryDataPath("tracks/ratm_ellipse.yaml"));
  if (!track.ok()) return track.status();
  Result<CameraModel> camera = loadCameraYaml(repositoryDataPath("cameras/ratm_piloted.yaml"));
  if (!camera.ok()) return camera.status();
  RaceSimParams params;
  params.seed = 1;
  Result<SimulatedRace> race = simulateRace(*track, *camera, params);
  if (!race.ok()) return race.status();
  DG_RETURN_IF_ERROR(writeSequence(dir, *race, *track, *camera, params));
  return loadSequence(dir, SequenceRunParams{}.defaultPoseDetectionCovariance());
}

}  // namespace

const Result<Sequence>& ratmSequence() {
  static TempFolder folder;
  static const Result<Sequence> sequence = simulate(folder.path + "/ratm_ellipse_seed1");
  return sequence;
}

Result<SequenceRunParams> raceRunParams(double d_main, int main_window) {
  Result<SequenceRunParams> params = loadRunConfig(repositoryDataPath("config/default.yaml"));
  if (!params.ok()) return params;
  params->localizer.d_main = d_main;
  if (main_window >= 0) params->localizer.main_window = main_window;
  return params;
}

Result<std::unique_ptr<Localizer>> runRaceLocalizer(const Sequence& sequence, const SequenceRunParams& params) {
  const std::vector<OdometrySample>& samples = sequence.odometry.samples;
  if (samples.empty() || !sequence.has_corners) return Status(StatusCode::kInvalidArgument, "expected corners and odometry");
  Result<GateMap> map = sequence.map.gateMap();
  if (!map.ok()) return map.status();
  Result<std::unique_ptr<Localizer>> localizer = Localizer::create(params.localizer, *map);
  if (!localizer.ok()) return localizer.status();
  Result<GateFrontend> frontend = GateFrontend::create(params.frontend, sequence.map, sequence.camera);
  if (!frontend.ok()) return frontend.status();
  const std::vector<CornerDetection>& corners = sequence.corners;
  size_t next = 0;
  while (next < corners.size() && corners[next].t < samples.front().t) ++next;
  std::vector<OdometrySample> accepted;
  accepted.reserve(samples.size());
  for (const OdometrySample& sample : samples) {
    if ((*localizer)->addOdometry(sample).ok()) accepted.push_back(sample);
    if (accepted.empty()) continue;
    while (next < corners.size() && corners[next].t <= accepted.back().t) {
      size_t end = next + 1;  // the detections of one instant
      while (end < corners.size() && corners[end].t == corners[next].t) ++end;
      Result<Eigen::Isometry3d> odom_T_body = odometryIncrementBetween(accepted, accepted.front().t, corners[next].t);
      if (odom_T_body.ok()) {
        const Eigen::Isometry3d world_T_body = (*localizer)->mapTOdom() * accepted.front().odom_T_body * *odom_T_body;
        Result<std::vector<GateObservation>> observations = frontend->processCorners(
            {corners.begin() + static_cast<long>(next), corners.begin() + static_cast<long>(end)}, world_T_body);
        if (!observations.ok()) return observations.status();
        for (const GateObservation& observation : *observations) (void)(*localizer)->addObservation(observation);
      }
      next = end;
    }
  }
  DG_RETURN_IF_ERROR((*localizer)->finish());
  return localizer;
}

}  // namespace dualgraph::bench
