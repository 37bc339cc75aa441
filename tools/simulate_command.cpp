// SPDX-License-Identifier: MIT
#include "tools/simulate_command.h"

#include <cmath>
#include <filesystem>
#include <iostream>

#include "frontend/io/camera_io.h"
#include "frontend/io/track_io.h"
#include "frontend/report/xy_plot.h"
#include "tools/data_dir.h"
#include "tools/staged_folder.h"

namespace dualgraph::tools {
namespace {

int fail(const std::string& message) {
  std::cerr << "dualgraph simulate: " << message << "\n";
  return 1;
}

// Unaligned position RMSE of the VIO against the truth at the same instants [m].
double vioRmse(const SimulatedRace& race) {
  double sum = 0.0;
  for (const OdometrySample& sample : race.vio.samples) {
    sum += (sample.odom_T_body.translation() - race.flight.at(sample.t).position).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(race.vio.samples.size()));
}

Status writePlot(const std::string& path, const SimulatedRace& race) {
  XyPlot plot;
  plot.title = "Simulated flight (XY)";
  PlotSeries truth{"ground truth", {}, {0, 0, 0}, true};
  for (const auto& [t, pose] : race.ground_truth) truth.points.emplace_back(pose.translation().head<2>());
  PlotSeries vio{"VIO", {}, {230, 120, 20}, false};
  for (const OdometrySample& sample : race.vio.samples) vio.points.emplace_back(sample.odom_T_body.translation().head<2>());
  plot.series = {vio, truth};  // the truth on top
  for (const TrackGate& gate : race.map.gates) plot.gates.push_back({gate.position.head<2>(), gate.yaw, gate.size});
  return writeXyPlotPng(path, plot);
}

}  // namespace

int runSimulateCommand(SimulateOptions o) {
  auto track = loadTrackYaml(o.track);
  if (!track.ok()) return fail(track.status().message());
  const std::string camera_path = o.camera.empty() ? bundledDataDir() + "/cameras/ratm_piloted.yaml" : o.camera;
  auto camera = loadCameraYaml(camera_path);
  if (!camera.ok()) return fail(camera.status().message());
  RaceSimParams& p = o.params;
  p.output = o.detections == "poses" ? RaceSimParams::DetectionOutput::kPoses : RaceSimParams::DetectionOutput::kCorners;
  if (o.laps > 0) {
    p.override_laps = true;
    p.flight.laps = o.laps;
  }
  if (o.speed > 0.0) {
    p.override_speed = true;
    p.flight.max_speed = o.speed;
  }
  auto race = simulateRace(*track, *camera, p);
  if (!race.ok()) return fail(o.track + ": " + race.status().message());
  // Staged: the sequence files and the plot appear in --out together or not at all.
  auto staged = StagedFolder::create(o.out);
  if (!staged.ok()) return fail(staged.status().message());
  const Status written = writeRaceSequence(staged->path(), *race, *track, *camera, p);
  if (!written.ok()) return fail(staged->unstaged(written).message());
  if (!o.no_plot) {
    const Status plotted = writePlot(staged->file("xy.png"), *race);
    if (!plotted.ok()) return fail(staged->unstaged(plotted).message());
  }
  const Status committed = staged->commit();
  if (!committed.ok()) return fail(committed.message());
  const DetectionSimStats& s = race->detection_stats;
  std::cout << "simulated " << (track->name.empty() ? o.track : track->name) << ", seed " << p.seed << ": "
            << race->flight.duration() << " s, " << race->flight.length() << " m, top speed "
            << race->flight.topSpeed() << " m/s\n"
            << "  VIO: " << race->vio.samples.size() << " samples, unaligned position RMSE " << vioRmse(*race) << " m\n"
            << "  detector: " << s.images << " images, " << s.visible << " gate views, " << race->detections.size()
            << " detections (" << s.missed << " missed, " << s.displaced_corner << " displaced corner, " << s.wrong_id
            << " wrong id, " << s.false_gates << " false gates)";
  if (p.output == RaceSimParams::DetectionOutput::kPoses) std::cout << ", PnP rejected " << race->pnp_rejected;
  std::cout << "\n  wrote " << o.out << "\n";
  return 0;
}

}  // namespace dualgraph::tools
