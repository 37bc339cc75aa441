// SPDX-License-Identifier: MIT
#include <limits>
#include <sstream>

#include "dualgraph/frontend/simulation/race_sequence.h"

#include "dualgraph/frontend/io/track_io.h"

namespace dualgraph {

std::string detectorYaml(const DetectionSimParams& d) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  out << "detector:\n"
      << "  camera_rate: " << d.camera_rate << "\n  keep_every: " << d.keep_every << "\n"
      << "  pixel_sigma: " << d.pixel_sigma << "\n  blur_px_per_rad_s: " << d.blur_px_per_rad_s << "\n  min_range: " << d.min_range << "\n  max_range: " << d.max_range << "\n"
      << "  max_view_angle_deg: " << d.max_view_angle_deg << "\n  edge_margin: " << d.edge_margin << "\n"
      << "  miss_probability: " << d.miss_probability << "\n"
      << "  displaced_corner_probability: " << d.displaced_corner_probability << "\n"
      << "  displaced_corner_pixels: " << d.displaced_corner_pixels << "\n"
      << "  wrong_id_probability: " << d.wrong_id_probability << "\n"
      << "  false_gate_probability: " << d.false_gate_probability << "\n"
      << "  unknown_ids: " << (d.unknown_ids ? "true" : "false") << "\n"
      << "  partial_gates: " << (d.partial_gates ? "true" : "false") << "\n"
      << "  min_visible_corners: " << d.min_visible_corners << "\n";
  return out.str();
}

std::string raceSequenceYaml(const SimulatedRace& race, const Track& track, const RaceSimParams& p) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  const FlightParams& f = p.flight;
  const VioDriftParams& v = p.vio;
  out << "# A simulated race (dualgraph simulate). Every parameter and the seed: the same values give\n"
      << "# the same files. Units: m, s, rad, px unless the name says otherwise.\n"
      << "seed: " << p.seed << "\n"
      << "detections: " << detectionOutputName(p.output) << "\n"
      << "gt_rate_hz: " << p.gt_rate << "\nvio_rate_hz: " << p.vio_rate << "\n"
      << "map_position_sigma: " << p.map_position_sigma << "\nmap_yaw_sigma: " << p.map_yaw_sigma << "\n"
      << "field_errors:\n"
      << "  vio_frame_yaw: " << p.field.vio_frame_yaw << "\n  vio_frame_offset: " << p.field.vio_frame_offset << "\n"
      << "  camera_time_offset: " << p.field.camera_time_offset << "\n"
      << "  camera_mount_error_deg: " << p.field.camera_mount_error_deg << "\n"
      << "  vio_time_offset: " << p.field.vio_time_offset << "\n  time_origin: " << p.field.time_origin << "\n"
      << "track_scale: " << p.track_scale << "\n"
      << "flight:\n"
      << "  laps: " << (p.override_laps ? f.laps : track.laps) << "\n"
      << "  max_speed: " << (p.override_speed ? f.max_speed : track.speed) << "\n"
      << "  max_lateral_acceleration: " << f.max_lateral_acceleration << "\n"
      << "  max_longitudinal_acceleration: " << f.max_longitudinal_acceleration << "\n"
      << "  speed_smoothing: " << f.speed_smoothing << "\n  gravity: " << f.gravity << "\n"
      << "  lap_speed_variation: " << f.lap_speed_variation << "\n  lap_line_variation: " << f.lap_line_variation << "\n"
      << "vio:\n"
      << "  yaw_rate_bias: " << v.yaw_rate_bias << "\n  yaw_random_walk: " << v.yaw_random_walk << "\n"
      << "  velocity_bias: " << v.velocity_bias << "\n  vertical_velocity_bias: " << v.vertical_velocity_bias << "\n"
      << "  velocity_bias_random_walk: " << v.velocity_bias_random_walk << "\n  bias_spread: " << v.bias_spread << "\n"
      << "  scale_error_sigma: " << v.scale_error_sigma << "\n  scale_error_bias: " << v.scale_error_bias << "\n"
      << "  position_noise: " << v.position_noise << "\n"
      << "  rotation_noise: " << v.rotation_noise << "\n"
      << detectorYaml(p.detection)
      << "summary:  # measured on this flight, not parameters\n"
      << "  duration_s: " << race.flight.duration() << "\n  length_m: " << race.flight.length() << "\n"
      << "  top_speed_mps: " << race.flight.topSpeed() << "\n"
      << "  images: " << race.detection_stats.images << "\n  visible_gate_views: " << race.detection_stats.visible << "\n"
      << "  partial_gate_views: " << race.detection_stats.partial_views << "\n"
      << "  detections: " << race.detections.size() << "\n  missed: " << race.detection_stats.missed << "\n"
      << "  partial: " << race.detection_stats.partial << "\n"
      << "  displaced_corner: " << race.detection_stats.displaced_corner << "\n"
      << "  wrong_id: " << race.detection_stats.wrong_id << "\n  false_gates: " << race.detection_stats.false_gates << "\n"
      << "  pnp_rejected: " << race.pnp_rejected << "\n  pnp_partial_skipped: " << race.pnp_partial_skipped << "\n"
      << "  pixel_sigma_mean: " << race.detection_stats.mean_pixel_sigma << "\n"
      << "  pixel_sigma_max: " << race.detection_stats.max_pixel_sigma << "\n"
      << "track: |\n";
  std::istringstream track_text(trackToYaml(p.track_scale == 1.0 ? track : scaledTrack(track, p.track_scale)));
  for (std::string line; std::getline(track_text, line);) out << "  " << line << "\n";
  return out.str();
}

namespace {

// The race as a sequence, its odometry as simulated (absolute covariances, as vio.tum holds them).
Sequence asWritten(const SimulatedRace& race, const RaceSimParams& params, const std::string& name) {
  Sequence sequence;
  sequence.dir = name;
  sequence.odometry = race.vio;
  sequence.has_corners = params.output == RaceSimParams::DetectionOutput::kCorners;
  if (sequence.has_corners) {
    sequence.corners.reserve(race.detections.size());
    for (const SimulatedDetection& detection : race.detections) sequence.corners.push_back(detection.corners);
  } else {
    sequence.pose_detections = race.pose_detections;
  }
  sequence.map = race.map;
  sequence.camera = race.camera;
  OdometryLog truth;
  truth.samples.reserve(race.ground_truth.size());
  for (const auto& [t, world_T_body] : race.ground_truth) {
    OdometrySample sample;
    sample.t = t;
    sample.odom_T_body = world_T_body;
    truth.samples.push_back(sample);
  }
  sequence.ground_truth = std::move(truth);
  return sequence;
}

}  // namespace

Result<Sequence> raceSequence(const SimulatedRace& race, const RaceSimParams& params, const std::string& name) {
  Sequence sequence = asWritten(race, params, name);
  if (!sequence.odometry.absolute_covariances.empty()) {  // as loadSequence does with vio.tum's columns
    auto report = toRelativeCovariances(sequence.odometry);
    if (!report.ok()) return Status(report.status().code(), name + ": " + report.status().message());
    sequence.covariance_clamped = report->clamped;
    sequence.covariance_shrinks = report->shrinks;
  }
  return sequence;
}

Status writeRaceSequence(const std::string& dir, const SimulatedRace& race, const Track& track,
                         const RaceSimParams& params) {
  return writeSequence(dir, asWritten(race, params, dir), raceSequenceYaml(race, track, params));
}

}  // namespace dualgraph
