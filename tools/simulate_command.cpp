// SPDX-License-Identifier: MIT
#include "tools/simulate_command.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "frontend/camera_io.h"
#include "frontend/track_io.h"
#include "frontend/xy_plot.h"
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

std::string bundledDataDir() {
  if (const char* dir = std::getenv("DUALGRAPH_DATA_DIR")) return dir;
  return DUALGRAPH_DEFAULT_DATA_DIR;
}

CLI::App* addSimulateCommand(CLI::App& app, SimulateOptions& o) {
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a racing flight: ground truth, drifting VIO, gate detections");
  RaceSimParams& p = o.params;
  cmd->add_option("--track", o.track, "Track YAML (gates and path), e.g. data/tracks/ratm_ellipse.yaml")->required();
  cmd->add_option("--out", o.out, "Sequence folder to write (created)")->required();
  cmd->add_option("--seed", p.seed, "Seed of every random draw");
  cmd->add_option("--camera", o.camera, "Camera YAML (default: the bundled RATM piloted camera)");
  cmd->add_option("--laps", o.laps, "Laps (default: the track's)")->check(CLI::PositiveNumber);
  cmd->add_option("--speed", o.speed, "Top speed [m/s] (default: the track's)")->check(CLI::PositiveNumber);
  cmd->add_option("--detections", o.detections, "corners (pixels, corners.csv) or poses (PnP, detections.csv)")
      ->check(CLI::IsMember({"corners", "poses"}));
  cmd->add_option("--gt-rate", p.gt_rate, "Ground-truth rate [Hz] (>= 100)");
  cmd->add_option("--vio-rate", p.vio_rate, "Odometry rate [Hz]");
  cmd->add_option("--max-lateral-acceleration", p.flight.max_lateral_acceleration, "[m/s^2]");
  cmd->add_option("--max-longitudinal-acceleration", p.flight.max_longitudinal_acceleration, "[m/s^2]");
  cmd->add_option("--yaw-rate-bias", p.vio.yaw_rate_bias, "VIO yaw-rate bias magnitude [rad/s]");
  cmd->add_option("--velocity-bias", p.vio.velocity_bias, "VIO horizontal velocity bias [m/s]");
  cmd->add_option("--velocity-bias-random-walk", p.vio.velocity_bias_random_walk, "[m/s/sqrt(s)]");
  cmd->add_option("--scale-error-sigma", p.vio.scale_error_sigma, "VIO scale error sigma");
  cmd->add_option("--pixel-sigma", p.detection.pixel_sigma, "Corner noise [px]");
  cmd->add_option("--max-range", p.detection.max_range, "Detection range limit [m]");
  cmd->add_option("--miss-probability", p.detection.miss_probability, "Per visible gate and image");
  cmd->add_option("--displaced-corner-probability", p.detection.displaced_corner_probability, "Outlier rate");
  cmd->add_option("--wrong-id-probability", p.detection.wrong_id_probability, "Outlier rate");
  cmd->add_option("--false-gate-probability", p.detection.false_gate_probability, "Per image");
  cmd->add_flag("--unknown-ids", p.detection.unknown_ids, "Write gate_id -1 (the association decides)");
  cmd->add_option("--map-sigma", p.map_position_sigma, "Perturb the written map's gate centres [m]");
  cmd->add_option("--map-yaw-sigma", p.map_yaw_sigma, "Perturb the written map's gate yaw [rad]");
  cmd->add_flag("--no-plot", o.no_plot, "Do not write xy.png");
  return cmd;
}

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
  const Status written = writeSequence(staged->path(), *race, *track, *camera, p);
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
