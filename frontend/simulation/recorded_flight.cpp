// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/recorded_flight.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/io/track_io.h"
#include "dualgraph/frontend/simulation/race_sequence.h"

namespace dualgraph {
namespace {

Status recordedFlightError(const std::string& what) { return Status(StatusCode::kInvalidArgument, "recorded flight: " + what); }

Status validatePlacement(const GatePlacementParams& p) {
  if (!(std::isfinite(p.spacing) && p.spacing > 0.0)) return recordedFlightError("gate spacing must be > 0");
  if (!(std::isfinite(p.min_separation) && p.min_separation >= 0.0)) return recordedFlightError("gate min_separation must be >= 0");
  if (!(std::isfinite(p.min_speed) && p.min_speed > 0.0)) return recordedFlightError("gate min_speed must be > 0");
  if (!(std::isfinite(p.size) && p.size > 0.0)) return recordedFlightError("gate size must be > 0");
  if (p.max_gates < 1) return recordedFlightError("max_gates must be >= 1");
  return Status();
}

std::vector<std::pair<double, Eigen::Isometry3d>> samplesWithin(const OdometryLog& log, double begin, double end) {
  std::vector<std::pair<double, Eigen::Isometry3d>> out;
  for (const OdometrySample& sample : log.samples) {
    if (sample.t >= begin && sample.t <= end) out.emplace_back(sample.t, sample.odom_T_body);
  }
  return out;
}

double pathLength(const SampledTrajectory& truth) {
  double length = 0.0;
  const auto& samples = truth.samples();
  for (size_t i = 1; i < samples.size(); ++i) {
    length += (samples[i].second.translation() - samples[i - 1].second.translation()).norm();
  }
  return length;
}

}  // namespace

Result<Track> placeGatesOnPath(const SampledTrajectory& truth, const GatePlacementParams& params) {
  DG_RETURN_IF_ERROR(validatePlacement(params));
  constexpr double kHalfWindow = 0.5;  // the direction of travel: displacement over ±0.5 s [s]
  constexpr double kRetryStep = 0.5;   // a spot refused is tried again this much further along [m]
  Track track;
  track.name = "virtual gates on a recorded flight";
  const auto& samples = truth.samples();
  double flown = 0.0;
  double next_at = 0.5 * params.spacing;
  for (size_t i = 1; i < samples.size() && static_cast<int>(track.gates.size()) < params.max_gates; ++i) {
    flown += (samples[i].second.translation() - samples[i - 1].second.translation()).norm();
    if (flown < next_at) continue;
    const double t = samples[i].first;
    const double t0 = std::max(t - kHalfWindow, truth.begin());
    const double t1 = std::min(t + kHalfWindow, truth.end());
    const Eigen::Vector3d travel = truth.worldTBody(t1).translation() - truth.worldTBody(t0).translation();
    const Eigen::Vector3d position = samples[i].second.translation();
    const bool moving = t1 > t0 && travel.head<2>().norm() >= params.min_speed * (t1 - t0);
    const bool apart = std::all_of(track.gates.begin(), track.gates.end(), [&](const TrackGate& gate) {
      return (gate.position - position).norm() >= params.min_separation;
    });
    if (!moving || !apart) {
      next_at = flown + kRetryStep;
      continue;
    }
    TrackGate gate;
    gate.id = static_cast<int>(track.gates.size());
    gate.position = position;
    gate.yaw = std::atan2(travel.y(), travel.x());
    gate.size = params.size;
    track.gates.push_back(gate);
    next_at = flown + params.spacing;
  }
  if (track.gates.empty()) {
    return recordedFlightError("no gate could be placed: the path is " + std::to_string(flown) + " m long, a gate needs half a spacing (" +
                   std::to_string(0.5 * params.spacing) + " m) flown at >= " + std::to_string(params.min_speed) + " m/s");
  }
  return track;
}

Result<RecordedFlight> simulateRecordedFlight(const OdometryLog& ground_truth, const OdometryLog& vio,
                                              const Track* track, const CameraModel& camera,
                                              const RecordedFlightParams& params) {
  if (ground_truth.samples.size() < 2) return recordedFlightError("the ground truth needs at least two poses");
  if (vio.samples.empty()) return recordedFlightError("the VIO has no poses");
  if (params.field.vio_frame_yaw != 0.0 || params.field.vio_frame_offset != 0.0) {
    return recordedFlightError("vio_frame_yaw and vio_frame_offset must be 0: the recorded VIO keeps its own frame");
  }
  const std::string field_problem = fieldErrorsProblem(params.field, params.map_position_sigma, params.map_yaw_sigma);
  if (!field_problem.empty()) return recordedFlightError(field_problem);
  RecordedFlight flight;
  flight.overlap_begin = std::max(ground_truth.samples.front().t, vio.samples.front().t);
  flight.overlap_end = std::min(ground_truth.samples.back().t, vio.samples.back().t);
  if (!(flight.overlap_end - flight.overlap_begin >= 1.0)) {
    std::ostringstream why;
    why.precision(std::numeric_limits<double>::max_digits10);
    why << "the ground truth [" << ground_truth.samples.front().t << ", " << ground_truth.samples.back().t
        << "] s and the VIO [" << vio.samples.front().t << ", " << vio.samples.back().t
        << "] s overlap by less than 1 s (not the same flight, or not the same clock?)";
    return recordedFlightError(why.str());
  }
  auto truth = SampledTrajectory::create(samplesWithin(ground_truth, flight.overlap_begin, flight.overlap_end));
  if (!truth.ok()) return truth.status();
  flight.path_length = pathLength(*truth);
  if (track != nullptr) {
    if (track->gates.empty()) return recordedFlightError("the track has no gates");
    flight.true_gates.name = track->name;
    flight.true_gates.gates = track->gates;
    flight.gates_placed = false;
  } else {
    auto placed = placeGatesOnPath(*truth, params.gates);
    if (!placed.ok()) return placed.status();
    flight.true_gates = std::move(placed).value();
  }
  auto detections = simulateDetections(*truth, flight.true_gates, camera, params.detection,
                                       simulationStreamSeed(params.seed, 2), &flight.detection_stats);
  if (!detections.ok()) return detections.status();
  flight.detections = std::move(detections).value();
  Sequence& sequence = flight.sequence;
  sequence.odometry = vio;
  sequence.ground_truth = ground_truth;
  sequence.has_corners = true;
  sequence.corners.reserve(flight.detections.size());
  for (SimulatedDetection& detection : flight.detections) {
    detection.corners.t += params.field.camera_time_offset;
    sequence.corners.push_back(detection.corners);
  }
  sequence.map = perturbedMap(flight.true_gates, params.map_position_sigma, params.map_yaw_sigma, params.seed);
  sequence.camera = mountedCamera(camera, params.field, params.seed);
  return flight;
}

std::string recordedFlightYaml(const RecordedFlight& flight, const RecordedFlightParams& p,
                               const std::string& ground_truth_path, const std::string& vio_path) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  const DetectionSimStats& s = flight.detection_stats;
  out << "# A recorded flight with virtual gates (dualgraph simulate --flight --vio): the VIO and the ground truth as\n"
      << "# recorded (vio.tum, gt.tum are byte copies), gates placed on the ground-truth path, corners synthesised\n"
      << "# from it. Units: m, s, rad, px unless the name says otherwise.\n"
      << "recorded_flight:\n  ground_truth: \"" << ground_truth_path << "\"\n  vio: \"" << vio_path << "\"\n"
      << "seed: " << p.seed << "\n"
      << "detections: corners\n"
      << "gates: " << (flight.gates_placed ? "placed" : "given") << "\n"
      << "gate_placement:\n  spacing: " << p.gates.spacing << "\n  min_separation: " << p.gates.min_separation
      << "\n  min_speed: " << p.gates.min_speed << "\n  size: " << p.gates.size << "\n  max_gates: " << p.gates.max_gates << "\n"
      << "map_position_sigma: " << p.map_position_sigma << "\nmap_yaw_sigma: " << p.map_yaw_sigma << "\n"
      << "field_errors:\n  camera_time_offset: " << p.field.camera_time_offset << "\n"
      << "  camera_mount_error_deg: " << p.field.camera_mount_error_deg << "\n"
      << detectorYaml(p.detection)
      << "summary:  # measured on this flight, not parameters\n"
      << "  overlap_begin_s: " << flight.overlap_begin << "\n  overlap_end_s: " << flight.overlap_end << "\n"
      << "  duration_s: " << flight.overlap_end - flight.overlap_begin << "\n  length_m: " << flight.path_length << "\n"
      << "  gates: " << flight.true_gates.gates.size() << "\n"
      << "  images: " << s.images << "\n  visible_gate_views: " << s.visible << "\n"
      << "  partial_gate_views: " << s.partial_views << "\n"
      << "  detections: " << flight.detections.size() << "\n  missed: " << s.missed << "\n  partial: " << s.partial << "\n"
      << "  displaced_corner: " << s.displaced_corner << "\n  wrong_id: " << s.wrong_id << "\n"
      << "  false_gates: " << s.false_gates << "\n"
      << "  pixel_sigma_mean: " << s.mean_pixel_sigma << "\n  pixel_sigma_max: " << s.max_pixel_sigma << "\n"
      << "track: |\n";
  std::istringstream track_text(trackToYaml(flight.true_gates));
  for (std::string line; std::getline(track_text, line);) out << "  " << line << "\n";
  return out.str();
}

Status writeRecordedFlight(const std::string& dir, const RecordedFlight& flight, const RecordedFlightParams& params,
                           const std::string& ground_truth_path, const std::string& vio_path) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) return Status(StatusCode::kIoError, dir + ": cannot create the folder: " + error.message());
  const fs::path folder(dir);
  // The two trajectories as recorded (writeSequence would write them again from what was read).
  for (const auto& [from, name] : {std::make_pair(vio_path, "vio.tum"), std::make_pair(ground_truth_path, "gt.tum")}) {
    fs::copy_file(from, folder / name, fs::copy_options::overwrite_existing, error);
    if (error) return Status(StatusCode::kIoError, (folder / name).string() + ": cannot copy " + from + ": " + error.message());
  }
  DG_RETURN_IF_ERROR(writeCornerDetections((folder / "corners.csv").string(), flight.sequence.corners));
  DG_RETURN_IF_ERROR(saveTrackYaml((folder / "gates.yaml").string(), flight.sequence.map));
  DG_RETURN_IF_ERROR(saveCameraYaml((folder / "camera.yaml").string(), *flight.sequence.camera));
  const std::string provenance = recordedFlightYaml(flight, params, ground_truth_path, vio_path);
  return writeFileAtomically((folder / "sequence.yaml").string(), [&](std::ostream& out) {
    out << provenance;
    return Status();
  });
}

}  // namespace dualgraph
