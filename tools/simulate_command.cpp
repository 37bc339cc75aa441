// SPDX-License-Identifier: MIT
#include "tools/simulate_command.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <set>

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

// The profile's parameters, except those the command line gave (`given`: the option names it counted, so a
// flag given with the clean value, `--blur 0`, wins over the profile too).
Status applyProfileUnderFlags(const std::string& profile, const std::set<std::string>& given, RaceSimParams& p) {
  const RaceSimParams flags = p;
  DG_RETURN_IF_ERROR(applySimulationProfile(profile, p));
  auto keep = [&given](const char* option, const auto& flag, auto& out) {
    if (given.count(option) > 0) out = flag;
  };
  keep("--pixel-sigma", flags.detection.pixel_sigma, p.detection.pixel_sigma);
  keep("--blur", flags.detection.blur_px_per_rad_s, p.detection.blur_px_per_rad_s);
  keep("--min-visible-corners", flags.detection.min_visible_corners, p.detection.min_visible_corners);
  keep("--lap-speed-variation", flags.flight.lap_speed_variation, p.flight.lap_speed_variation);
  keep("--lap-line-variation", flags.flight.lap_line_variation, p.flight.lap_line_variation);
  keep("--max-range", flags.detection.max_range, p.detection.max_range);
  keep("--miss-probability", flags.detection.miss_probability, p.detection.miss_probability);
  keep("--displaced-corner-probability", flags.detection.displaced_corner_probability, p.detection.displaced_corner_probability);
  keep("--wrong-id-probability", flags.detection.wrong_id_probability, p.detection.wrong_id_probability);
  keep("--false-gate-probability", flags.detection.false_gate_probability, p.detection.false_gate_probability);
  keep("--unknown-ids", flags.detection.unknown_ids, p.detection.unknown_ids);
  keep("--yaw-rate-bias", flags.vio.yaw_rate_bias, p.vio.yaw_rate_bias);
  keep("--velocity-bias", flags.vio.velocity_bias, p.vio.velocity_bias);
  keep("--velocity-bias-random-walk", flags.vio.velocity_bias_random_walk, p.vio.velocity_bias_random_walk);
  keep("--scale-error-sigma", flags.vio.scale_error_sigma, p.vio.scale_error_sigma);
  keep("--map-sigma", flags.map_position_sigma, p.map_position_sigma);
  keep("--map-yaw-sigma", flags.map_yaw_sigma, p.map_yaw_sigma);
  keep("--vio-frame-yaw", flags.field.vio_frame_yaw, p.field.vio_frame_yaw);
  keep("--vio-frame-offset", flags.field.vio_frame_offset, p.field.vio_frame_offset);
  keep("--camera-time-offset", flags.field.camera_time_offset, p.field.camera_time_offset);
  keep("--camera-mount-error", flags.field.camera_mount_error_deg, p.field.camera_mount_error_deg);
  return Status();
}

}  // namespace

int runSimulateCommand(SimulateOptions o) {
  auto track = loadTrackYaml(o.track);
  if (!track.ok()) return fail(track.status().message());
  const std::string camera_path = o.camera.empty() ? bundledDataDir() + "/cameras/ratm_piloted.yaml" : o.camera;
  auto camera = loadCameraYaml(camera_path);
  if (!camera.ok()) return fail(camera.status().message());
  RaceSimParams& p = o.params;
  const Status profiled = applyProfileUnderFlags(o.profile, o.given, p);
  if (!profiled.ok()) return fail(profiled.message());
  if (!o.partial_gates.empty()) p.detection.partial_gates = o.partial_gates == "on";
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
  const Status written = writeRaceSequence(staged->path(), *race, *track, p);
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
            << " wrong id, " << s.false_gates << " false gates";
  if (p.detection.partial_gates) std::cout << ", " << s.partial << " partial";
  std::cout << "), corner noise " << s.mean_pixel_sigma << " px on average, up to " << s.max_pixel_sigma << " px";
  if (p.output == RaceSimParams::DetectionOutput::kPoses) {
    std::cout << ", PnP rejected " << race->pnp_rejected;
    if (race->pnp_partial_skipped > 0) std::cout << " (" << race->pnp_partial_skipped << " partial skipped)";
  }
  std::cout << "\n  wrote " << o.out << "\n";
  return 0;
}

}  // namespace dualgraph::tools
