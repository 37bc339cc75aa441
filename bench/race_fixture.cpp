// SPDX-License-Identifier: MIT
#include "bench/race_fixture.h"

#include <map>
#include <utility>

#include "bench/bench_data.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/run_config.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/simulation/race_profiles.h"
#include "dualgraph/frontend/simulation/race_sequence.h"

namespace dualgraph::bench {
namespace {

Result<Sequence> simulate() {
  Result<Track> track = loadTrackYaml(repositoryDataPath("tracks/ratm_ellipse.yaml"));
  if (!track.ok()) return track.status();
  Result<CameraModel> camera = loadCameraYaml(repositoryDataPath("cameras/ratm_piloted.yaml"));
  if (!camera.ok()) return camera.status();
  RaceSimParams params;
  params.seed = 1;
  Result<SimulatedRace> race = simulateRace(*track, *camera, params);
  if (!race.ok()) return race.status();
  return raceSequence(*race, params, "ratm_ellipse seed 1 (simulated)");
}

}  // namespace

const Result<Sequence>& ratmSequence() {
  static const Result<Sequence> sequence = simulate();
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
  if (sequence.odometry.samples.empty() || !sequence.has_corners) {
    return Status(StatusCode::kInvalidArgument, "expected corners and odometry");
  }
  Result<GateMap> map = sequence.map.gateMap();
  if (!map.ok()) return map.status();
  Result<std::unique_ptr<Localizer>> localizer = Localizer::create(params.localizer, *map);
  if (!localizer.ok()) return localizer.status();
  Result<GateFrontend> frontend = GateFrontend::create(params.frontend, sequence.map, sequence.camera);
  if (!frontend.ok()) return frontend.status();
  Result<SequenceRunResult> run = runSequenceWith(**localizer, *frontend, sequence);
  if (!run.ok()) return run.status();
  return localizer;
}

const Result<Sequence>& realisticRace(const std::string& track_name, std::uint64_t seed) {
  static std::map<std::pair<std::string, std::uint64_t>, Result<Sequence>> cache;
  const auto key = std::make_pair(track_name, seed);
  auto found = cache.find(key);
  if (found != cache.end()) return found->second;
  auto simulate = [&]() -> Result<Sequence> {
    Result<Track> track = loadTrackYaml(bench::repositoryDataPath("tracks/" + track_name + ".yaml"));
    if (!track.ok()) return track.status();
    Result<CameraModel> camera = loadCameraYaml(bench::repositoryDataPath("cameras/ratm_piloted.yaml"));
    if (!camera.ok()) return camera.status();
    RaceSimParams params;
    params.seed = seed;
    DG_RETURN_IF_ERROR(applySimulationProfile("realistic", params));
    Result<SimulatedRace> race = simulateRace(*track, *camera, params);
    if (!race.ok()) return race.status();
    return raceSequence(*race, params, track_name + " seed " + std::to_string(seed) + " (simulated, realistic)");
  };
  return cache.emplace(key, simulate()).first->second;
}

}  // namespace dualgraph::bench
