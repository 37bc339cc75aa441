// SPDX-License-Identifier: MIT
#include "tools/simulate_command.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <set>

#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/report/xy_plot.h"
#include "tools/data_dir.h"
#include "tools/staged_folder.h"

namespace dualgraph::tools {
namespace {

int fail(const std::string& message) {
  std::cerr << "dualgraph simulate: " << message << "\n";
  return 1;
}

// Unaligned position RMSE of the VIO against the truth at the instants its samples show [m].
double vioRmse(const SimulatedRace& race, const FieldErrorParams& race_field) {
  double sum = 0.0;
  for (const OdometrySample& sample : race.vio.samples) {
    const double flight_time = sample.t - race_field.time_origin - race_field.vio_time_offset;  // the instant shown
    sum += (sample.odom_T_body.translation() - race.flight.at(flight_time).position).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(race.vio.samples.size()));
}

Status writePlot(const std::string& path, const OdometryLog& truth_log, const OdometryLog& vio_log, const Track& map,
                 const char* title) {
  XyPlot plot;
  plot.title = title;
  PlotSeries truth{"ground truth", {}, {0, 0, 0}, true};
  for (const OdometrySample& sample : truth_log.samples) truth.points.emplace_back(sample.odom_T_body.translation().head<2>());
  PlotSeries vio{"VIO (its own frame)", {}, {230, 120, 20}, false};
  for (const OdometrySample& sample : vio_log.samples) vio.points.emplace_back(sample.odom_T_body.translation().head<2>());
  plot.series = {vio, truth};  // the truth on top
  for (const TrackGate& gate : map.gates) plot.gates.push_back({gate.position.head<2>(), gate.yaw, gate.size});
  return writeXyPlotPng(path, plot);
}

Status writePlot(const std::string& path, const SimulatedRace& race) {
  OdometryLog truth;
  for (const auto& [t, pose] : race.ground_truth) {
    OdometrySample sample;
    sample.t = t;
    sample.odom_T_body = pose;
    truth.samples.push_back(sample);
  }
  return writePlot(path, truth, race.vio, race.map, "Simulated flight (XY)");
}

// Every option whose default is the profile's: visit(name, from's field, to's field), in one place for the
// help text (profileOptionNames) and for applyProfileUnderFlags.
template <typename Visit>
void forEachProfileOption(const RaceSimParams& from, RaceSimParams& to, Visit&& visit) {
  visit("--pixel-sigma", from.detection.pixel_sigma, to.detection.pixel_sigma);
  visit("--blur", from.detection.blur_px_per_rad_s, to.detection.blur_px_per_rad_s);
  visit("--min-visible-corners", from.detection.min_visible_corners, to.detection.min_visible_corners);
  visit("--lap-speed-variation", from.flight.lap_speed_variation, to.flight.lap_speed_variation);
  visit("--lap-line-variation", from.flight.lap_line_variation, to.flight.lap_line_variation);
  visit("--max-range", from.detection.max_range, to.detection.max_range);
  visit("--miss-probability", from.detection.miss_probability, to.detection.miss_probability);
  visit("--displaced-corner-probability", from.detection.displaced_corner_probability, to.detection.displaced_corner_probability);
  visit("--wrong-id-probability", from.detection.wrong_id_probability, to.detection.wrong_id_probability);
  visit("--false-gate-probability", from.detection.false_gate_probability, to.detection.false_gate_probability);
  visit("--unknown-ids", from.detection.unknown_ids, to.detection.unknown_ids);
  visit("--yaw-rate-bias", from.vio.yaw_rate_bias, to.vio.yaw_rate_bias);
  visit("--velocity-bias", from.vio.velocity_bias, to.vio.velocity_bias);
  visit("--velocity-bias-random-walk", from.vio.velocity_bias_random_walk, to.vio.velocity_bias_random_walk);
  visit("--scale-error-sigma", from.vio.scale_error_sigma, to.vio.scale_error_sigma);
  visit("--map-sigma", from.map_position_sigma, to.map_position_sigma);
  visit("--map-yaw-sigma", from.map_yaw_sigma, to.map_yaw_sigma);
  visit("--vio-frame-yaw", from.field.vio_frame_yaw, to.field.vio_frame_yaw);
  visit("--vio-frame-offset", from.field.vio_frame_offset, to.field.vio_frame_offset);
  visit("--camera-time-offset", from.field.camera_time_offset, to.field.camera_time_offset);
  visit("--camera-mount-error", from.field.camera_mount_error_deg, to.field.camera_mount_error_deg);
  visit("--scale-error-bias", from.vio.scale_error_bias, to.vio.scale_error_bias);
  visit("--vio-time-offset", from.field.vio_time_offset, to.field.vio_time_offset);
  visit("--time-origin", from.field.time_origin, to.field.time_origin);
  visit("--track-scale", from.track_scale, to.track_scale);
}

// The profile's parameters and then the regimes', except those the command line gave (`given`: the option names it
// counted, so a flag given with the clean value, `--blur 0`, wins over the profile too).
Status applyProfileUnderFlags(const std::string& profile, const std::vector<std::string>& regimes,
                              const std::set<std::string>& given, RaceSimParams& p) {
  const RaceSimParams flags = p;
  DG_RETURN_IF_ERROR(applySimulationProfile(profile, p));
  for (const std::string& regime : regimes) DG_RETURN_IF_ERROR(applySimulationRegime(regime, p));
  forEachProfileOption(flags, p, [&given](const std::string& option, const auto& flag, auto& out) {
    if (given.count(option) > 0) out = flag;
  });
  return Status();
}

}  // namespace

const std::vector<std::string>& simulatedFlightOnlyOptions() {
  static const std::vector<std::string> names = {
      "--laps", "--speed", "--gt-rate", "--vio-rate", "--max-lateral-acceleration", "--max-longitudinal-acceleration",
      "--yaw-rate-bias", "--velocity-bias", "--velocity-bias-random-walk", "--scale-error-sigma", "--lap-speed-variation",
      "--lap-line-variation", "--vio-frame-yaw", "--vio-frame-offset", "--detections", "--regime", "--scale-error-bias",
      "--vio-time-offset", "--time-origin", "--track-scale"};
  return names;
}

const std::vector<std::string>& profileOptionNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    RaceSimParams scratch;
    forEachProfileOption(RaceSimParams{}, scratch, [&out](const std::string& option, const auto&, auto&) {
      out.push_back(option);
    });
    return out;
  }();
  return names;
}

namespace {

// The camera (--camera, or the bundled `default_camera`) and the simulator's parameters: the --profile's under the
// flags given, --partial-gates. The error message when one cannot be had.
Result<CameraModel> cameraAndProfile(SimulateOptions& o, const std::string& default_camera) {
  auto camera = loadCameraYaml(o.camera.empty() ? bundledDataDir() + "/cameras/" + default_camera : o.camera);
  if (!camera.ok()) return camera.status();
  DG_RETURN_IF_ERROR(applyProfileUnderFlags(o.profile, o.regimes, o.given, o.params));
  if (!o.partial_gates.empty()) o.params.detection.partial_gates = o.partial_gates == "on";
  return camera;
}

int runRecordedFlight(SimulateOptions& o) {
  std::unique_ptr<Track> track;
  if (!o.track.empty()) {
    auto loaded = loadTrackYaml(o.track);
    if (!loaded.ok()) return fail(loaded.status().message());
    track = std::make_unique<Track>(std::move(loaded).value());
  }
  auto camera = cameraAndProfile(o, "euroc_cam0.yaml");
  if (!camera.ok()) return fail(camera.status().message());
  const RaceSimParams& p = o.params;
  auto truth = readTrajectory(o.flight);
  if (!truth.ok()) return fail(truth.status().message());
  TrajectoryFormat vio_format = TrajectoryFormat::kTum;
  auto vio = readTrajectory(o.vio, &vio_format);
  if (!vio.ok()) return fail(vio.status().message());
  RecordedFlightParams recorded;
  recorded.seed = p.seed;
  recorded.gates = o.gates;
  recorded.detection = p.detection;
  recorded.map_position_sigma = p.map_position_sigma;
  recorded.map_yaw_sigma = p.map_yaw_sigma;
  recorded.field.camera_time_offset = p.field.camera_time_offset;
  recorded.field.camera_mount_error_deg = p.field.camera_mount_error_deg;
  auto flight = simulateRecordedFlight(*truth, *vio, track.get(), *camera, recorded);
  if (!flight.ok()) return fail(o.flight + " + " + o.vio + ": " + flight.status().message());
  auto staged = StagedFolder::create(o.out);
  if (!staged.ok()) return fail(staged.status().message());
  const Status written = writeRecordedFlight(staged->path(), *flight, recorded, o.flight, o.vio);
  if (!written.ok()) return fail(staged->unstaged(written).message());
  if (!o.no_plot) {
    const Status plotted = writePlot(staged->file("xy.png"), *truth, *vio, flight->sequence.map, "Recorded flight (XY)");
    if (!plotted.ok()) return fail(staged->unstaged(plotted).message());
  }
  const Status committed = staged->commit({o.track, o.flight, o.vio, o.camera});
  if (!committed.ok()) return fail(committed.message());
  const DetectionSimStats& s = flight->detection_stats;
  std::cout << "recorded flight " << o.flight << ": " << flight->overlap_end - flight->overlap_begin << " s with the VIO, "
            << flight->path_length << " m\n"
            << "  VIO: " << o.vio << " (" << trajectoryFormatName(vio_format) << "), " << vio->samples.size()
            << " samples, kept as recorded\n"
            << "  gates: " << flight->true_gates.gates.size();
  if (flight->gates_placed) {
    double shortest = std::numeric_limits<double>::infinity();
    for (const PlacedGateApproach& approach : flight->approaches) shortest = std::min(shortest, approach.view_s);
    std::cout << " placed where the drone flies through them (one per " << o.gates.spacing << " m flown at most, at least "
              << o.gates.min_separation << " m apart), each seen whole on its approach for " << shortest << " s or more";
  } else {
    std::cout << " from " << o.track;
  }
  std::cout << "\n  detector: " << s.images << " images, " << s.visible << " gate views, " << flight->detections.size()
            << " detections (" << s.missed << " missed, " << s.displaced_corner << " displaced corner, " << s.wrong_id
            << " wrong id, " << s.false_gates << " false gates), corner noise " << s.mean_pixel_sigma << " px\n"
            << "  wrote " << o.out << "\n";
  if (flight->detections.empty()) {
    std::cerr << "dualgraph simulate: warning: no gate was seen: check the camera's body_T_camera against the ground "
                 "truth's body frame (" << (o.camera.empty() ? "the bundled euroc_cam0.yaml" : o.camera) << ")\n";
  }
  return 0;
}

}  // namespace

int runSimulateCommand(SimulateOptions o) {
  if (!o.flight.empty()) return runRecordedFlight(o);  // the parser checked --vio with it, --track without
  auto track = loadTrackYaml(o.track);
  if (!track.ok()) return fail(track.status().message());
  auto camera = cameraAndProfile(o, "ratm_piloted.yaml");
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
  const Status written = writeRaceSequence(staged->path(), *race, *track, p);
  if (!written.ok()) return fail(staged->unstaged(written).message());
  if (!o.no_plot) {
    const Status plotted = writePlot(staged->file("xy.png"), *race);
    if (!plotted.ok()) return fail(staged->unstaged(plotted).message());
  }
  const Status committed = staged->commit({o.track, o.flight, o.vio, o.camera});
  if (!committed.ok()) return fail(committed.message());
  const DetectionSimStats& s = race->detection_stats;
  std::cout << "simulated " << (track->name.empty() ? o.track : track->name) << ", seed " << p.seed << ": "
            << race->flight.duration() << " s, " << race->flight.length() << " m, top speed "
            << race->flight.topSpeed() << " m/s\n"
            << "  VIO: " << race->vio.samples.size() << " samples, unaligned position RMSE " << vioRmse(*race, p.field) << " m\n"
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
