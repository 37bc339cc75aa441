// SPDX-License-Identifier: MIT
// writeSequence (race_simulator.h): the sequence folder of a simulated race.
#include <filesystem>
#include <limits>
#include <sstream>

#include "core/atomic_file.h"
#include "frontend/camera_io.h"
#include "frontend/race_simulator.h"
#include "frontend/track_io.h"
#include "frontend/trajectory_io.h"

namespace dualgraph {
namespace {

// sequence.yaml: the seed and every parameter, so that the sequence can be made again.
std::string sequenceYaml(const SimulatedRace& race, const Track& track, const RaceSimParams& p) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  const FlightParams& f = p.flight;
  const VioDriftParams& v = p.vio;
  const DetectionSimParams& d = p.detection;
  out << "# A simulated race (dualgraph simulate). Every parameter and the seed: the same values give\n"
      << "# the same files. Units: m, s, rad, px unless the name says otherwise.\n"
      << "seed: " << p.seed << "\n"
      << "detections: " << detectionOutputName(p.output) << "\n"
      << "gt_rate_hz: " << p.gt_rate << "\nvio_rate_hz: " << p.vio_rate << "\n"
      << "map_position_sigma: " << p.map_position_sigma << "\nmap_yaw_sigma: " << p.map_yaw_sigma << "\n"
      << "flight:\n"
      << "  laps: " << (p.override_laps ? f.laps : track.laps) << "\n"
      << "  max_speed: " << (p.override_speed ? f.max_speed : track.speed) << "\n"
      << "  max_lateral_acceleration: " << f.max_lateral_acceleration << "\n"
      << "  max_longitudinal_acceleration: " << f.max_longitudinal_acceleration << "\n"
      << "  speed_smoothing: " << f.speed_smoothing << "\n  gravity: " << f.gravity << "\n"
      << "vio:\n"
      << "  yaw_rate_bias: " << v.yaw_rate_bias << "\n  yaw_random_walk: " << v.yaw_random_walk << "\n"
      << "  velocity_bias: " << v.velocity_bias << "\n  vertical_velocity_bias: " << v.vertical_velocity_bias << "\n"
      << "  velocity_bias_random_walk: " << v.velocity_bias_random_walk << "\n  bias_spread: " << v.bias_spread << "\n"
      << "  scale_error_sigma: " << v.scale_error_sigma << "\n  position_noise: " << v.position_noise << "\n"
      << "  rotation_noise: " << v.rotation_noise << "\n"
      << "detector:\n"
      << "  camera_rate: " << d.camera_rate << "\n  keep_every: " << d.keep_every << "\n"
      << "  pixel_sigma: " << d.pixel_sigma << "\n  min_range: " << d.min_range << "\n  max_range: " << d.max_range << "\n"
      << "  max_view_angle_deg: " << d.max_view_angle_deg << "\n  edge_margin: " << d.edge_margin << "\n"
      << "  miss_probability: " << d.miss_probability << "\n"
      << "  displaced_corner_probability: " << d.displaced_corner_probability << "\n"
      << "  displaced_corner_pixels: " << d.displaced_corner_pixels << "\n"
      << "  wrong_id_probability: " << d.wrong_id_probability << "\n"
      << "  false_gate_probability: " << d.false_gate_probability << "\n"
      << "  unknown_ids: " << (d.unknown_ids ? "true" : "false") << "\n"
      << "summary:  # measured on this flight, not parameters\n"
      << "  duration_s: " << race.flight.duration() << "\n  length_m: " << race.flight.length() << "\n"
      << "  top_speed_mps: " << race.flight.topSpeed() << "\n"
      << "  images: " << race.detection_stats.images << "\n  visible_gate_views: " << race.detection_stats.visible << "\n"
      << "  detections: " << race.detections.size() << "\n  missed: " << race.detection_stats.missed << "\n"
      << "  displaced_corner: " << race.detection_stats.displaced_corner << "\n"
      << "  wrong_id: " << race.detection_stats.wrong_id << "\n  false_gates: " << race.detection_stats.false_gates << "\n"
      << "  pnp_rejected: " << race.pnp_rejected << "\n"
      << "track: |\n";
  std::istringstream track_text(trackToYaml(track));
  for (std::string line; std::getline(track_text, line);) out << "  " << line << "\n";
  return out.str();
}

}  // namespace

Status writeSequence(const std::string& dir, const SimulatedRace& race, const Track& track,
                     const CameraModel& camera, const RaceSimParams& params) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) return Status(StatusCode::kIoError, dir + ": cannot create the folder: " + error.message());
  const std::filesystem::path folder(dir);
  DG_RETURN_IF_ERROR(writeTum((folder / "gt.tum").string(), race.ground_truth));
  DG_RETURN_IF_ERROR(writeTumOdometry((folder / "vio.tum").string(), race.vio));
  if (params.output == RaceSimParams::DetectionOutput::kCorners) {
    std::vector<CornerDetection> corners;
    corners.reserve(race.detections.size());
    for (const SimulatedDetection& detection : race.detections) corners.push_back(detection.corners);
    DG_RETURN_IF_ERROR(writeCornerDetections((folder / "corners.csv").string(), corners));
  } else {
    DG_RETURN_IF_ERROR(writePoseDetections((folder / "detections.csv").string(), race.pose_detections));
  }
  DG_RETURN_IF_ERROR(saveTrackYaml((folder / "gates.yaml").string(), race.map));
  DG_RETURN_IF_ERROR(saveCameraYaml((folder / "camera.yaml").string(), camera));
  const std::string text = sequenceYaml(race, track, params);
  return writeFileAtomically((folder / "sequence.yaml").string(), [&](std::ostream& out) {
    out << text;
    return Status();
  });
}

}  // namespace dualgraph
