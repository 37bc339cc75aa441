// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/recorded_flight.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include <Eigen/Eigenvalues>

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
  if (!(std::isfinite(p.min_approach_view) && p.min_approach_view >= 0.0)) {
    return recordedFlightError("gate min_approach_view must be >= 0");
  }
  if (!(std::isfinite(p.approach_window) && p.approach_window > 0.0)) return recordedFlightError("gate approach_window must be > 0");
  if (!(std::isfinite(p.max_crossing_angle_deg) && p.max_crossing_angle_deg >= 0.0 && p.max_crossing_angle_deg <= 85.0)) {
    return recordedFlightError("gate max_crossing_angle_deg must be in [0, 85]");
  }
  if (p.min_gates < 1) return recordedFlightError("min_gates must be >= 1");
  if (!(std::isfinite(p.max_passage_offset) && p.max_passage_offset >= 0.0 && p.max_passage_offset < 0.5 * p.size)) {
    return recordedFlightError("gate max_passage_offset must be in [0, size/2)");
  }
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

// A spot on the path where a gate could go: the body's position then, and how long its approach is in view.
struct GateSpot {
  double t = 0.0;
  double flown = 0.0;  // path length flown before t [m]
  TrackGate gate;
  double view_s = 0.0;
};

// The camera's pose at every image the detector processes (truth.begin() + k · keep_every / camera_rate).
struct ImagePoses {
  double begin = 0.0;
  double period = 0.0;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> world_T_camera;
};

ImagePoses imagePoses(const SampledTrajectory& truth, const CameraModel& camera, const DetectionSimParams& detector) {
  ImagePoses poses;
  poses.begin = truth.begin();
  poses.period = detector.keep_every / detector.camera_rate;
  for (long k = 0;; ++k) {
    const double t = truth.begin() + static_cast<double>(k * detector.keep_every) / detector.camera_rate;
    if (t > truth.end()) break;
    poses.world_T_camera.push_back(truth.worldTBody(t) * camera.body_T_camera);
  }
  return poses;
}

// The longest unbroken run of processed images in [t − window, t) from which `gate` is whole in view [s]; stops
// early, returning at most `to_beat`, once the images left cannot make a run longer than `to_beat`.
double approachView(const ImagePoses& images, const TrackGate& gate, const CameraModel& camera,
                    const DetectionSimParams& detector, double cos_max_view, double t, double window, double to_beat) {
  const long count = static_cast<long>(images.world_T_camera.size());
  const long first = std::max(0L, static_cast<long>(std::ceil((t - window - images.begin) / images.period)));
  const long end = std::min(count, static_cast<long>(std::ceil((t - images.begin) / images.period)));  // past the last
  int run = 0;
  int longest = 0;
  for (long k = first; k < end; ++k) {
    if (std::max<long>(longest, run + (end - k)) * images.period <= to_beat) return std::max(longest, run) * images.period;
    run = gateViewFrom(images.world_T_camera[static_cast<size_t>(k)], gate, camera, detector, cos_max_view).whole() ? run + 1 : 0;
    longest = std::max(longest, run);
  }
  return longest * images.period;
}

// The best gate at time t: upright, the body's path through its opening at most `max_passage_offset` from its
// centre (across and below; the camera looks from above the centre when it is below), its normal turned from the
// direction of travel by the angle within the crossing limit that gives the longest approach view; among equals the
// smallest turn and offset.
GateSpot bestGateAt(const SampledTrajectory& truth, const ImagePoses& images, const CameraModel& camera,
                    const DetectionSimParams& detector, const GatePlacementParams& params, double t, double travel_yaw) {
  constexpr double kTurnStep = 15.0 * M_PI / 180.0;
  const double cos_max_view = std::cos(detector.max_view_angle_deg * M_PI / 180.0);
  const int turns = static_cast<int>(std::floor(params.max_crossing_angle_deg * M_PI / 180.0 / kTurnStep + 1e-9));
  const double h = params.max_passage_offset;
  const double offsets[][2] = {{0, 0}, {0, -0.5 * h}, {0, -h}, {0.5 * h, 0}, {-0.5 * h, 0}, {h, 0}, {-h, 0},
                               {0.5 * h, -0.5 * h}, {-0.5 * h, -0.5 * h}, {h, -h}, {-h, -h}, {0.5 * h, -h}, {-0.5 * h, -h}};
  const Eigen::Vector3d body = truth.worldTBody(t).translation();
  GateSpot best;
  best.t = t;
  best.gate.size = params.size;
  best.view_s = -1.0;
  for (const auto& offset : offsets) {
    for (int k = 0; k <= 2 * turns; ++k) {
      const int turn = (k + 1) / 2 * (k % 2 == 0 ? -1 : 1);  // 0, +1, −1, +2, −2, …
      TrackGate gate = best.gate;
      gate.yaw = std::remainder(travel_yaw + turn * kTurnStep, 2.0 * M_PI);
      const Eigen::Vector3d across(-std::sin(gate.yaw), std::cos(gate.yaw), 0.0);
      gate.position = body + offset[0] * across + Eigen::Vector3d(0, 0, offset[1]);
      const double view =
          approachView(images, gate, camera, detector, cos_max_view, t, params.approach_window, best.view_s);
      if (view > best.view_s) {
        best.gate = gate;
        best.view_s = view;
      }
    }
  }
  return best;
}

// The gates' centres all on one horizontal line (the smaller spread across the line below 0.25 m), or the gates
// one pattern under a turn about the vertical (every gate onto another within 0.25 m and 10°, as a square's four
// corners): the frame cannot be told from such a set. Empty when it is neither.
std::string degenerateLayout(const Track& track) {
  const size_t n = track.gates.size();
  if (n < 2) return "";
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const TrackGate& gate : track.gates) mean += gate.position.head<2>() / static_cast<double>(n);
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const TrackGate& gate : track.gates) {
    const Eigen::Vector2d d = gate.position.head<2>() - mean;
    scatter += d * d.transpose() / static_cast<double>(n);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> spread(scatter);
  if (std::sqrt(std::max(spread.eigenvalues()(0), 0.0)) < 0.25) return "all on one line";
  constexpr double kPosition = 0.25;
  constexpr double kYaw = 10.0 * M_PI / 180.0;
  for (size_t j = 1; j < n; ++j) {  // the turn that takes gate 0 onto gate j
    const double turn = track.gates[j].yaw - track.gates[0].yaw;
    const Eigen::Rotation2Dd rotation(turn);
    const Eigen::Vector2d shift = track.gates[j].position.head<2>() - rotation * track.gates[0].position.head<2>();
    const bool symmetric = std::all_of(track.gates.begin(), track.gates.end(), [&](const TrackGate& a) {
      const Eigen::Vector2d moved = rotation * a.position.head<2>() + shift;
      return std::any_of(track.gates.begin(), track.gates.end(), [&](const TrackGate& b) {
        return (moved - b.position.head<2>()).norm() < kPosition && std::abs(a.position.z() - b.position.z()) < kPosition &&
               std::abs(std::remainder(a.yaw + turn - b.yaw, 2.0 * M_PI)) < kYaw;
      });
    });
    if (symmetric) return "one pattern under a turn of " + formatFixed(turn * 180.0 / M_PI, 0) + " deg";
  }
  return "";
}

}  // namespace

Result<Track> placeGatesOnPath(const SampledTrajectory& truth, const CameraModel& camera,
                               const DetectionSimParams& detector, const GatePlacementParams& params,
                               std::vector<PlacedGateApproach>* approaches) {
  DG_RETURN_IF_ERROR(validatePlacement(params));
  DG_RETURN_IF_ERROR(validateDetectionSimParams(detector));
  DG_RETURN_IF_ERROR(camera.validate());
  constexpr double kHalfWindow = 0.5;    // the direction of travel: displacement over ±0.5 s [s]
  constexpr double kCandidateStep = 0.05;  // spots looked at along the path [s]
  Track track;
  track.name = "virtual gates on a recorded flight";
  const ImagePoses images = imagePoses(truth, camera, detector);
  std::vector<GateSpot> spots;  // every spot that can hold a gate
  const auto& samples = truth.samples();
  double flown = 0.0;
  double last_candidate = -std::numeric_limits<double>::infinity();
  int moving_spots = 0;
  for (size_t i = 1; i < samples.size(); ++i) {
    flown += (samples[i].second.translation() - samples[i - 1].second.translation()).norm();
    const double t = samples[i].first;
    if (t - last_candidate < kCandidateStep) continue;
    last_candidate = t;
    const double t0 = std::max(t - kHalfWindow, truth.begin());
    const double t1 = std::min(t + kHalfWindow, truth.end());
    const Eigen::Vector3d travel = truth.worldTBody(t1).translation() - truth.worldTBody(t0).translation();
    if (!(t1 > t0 && travel.head<2>().norm() >= params.min_speed * (t1 - t0))) continue;
    ++moving_spots;
    GateSpot spot = bestGateAt(truth, images, camera, detector, params, t, std::atan2(travel.y(), travel.x()));
    spot.flown = flown;
    if (spot.view_s >= params.min_approach_view && spot.view_s > 0.0) spots.push_back(spot);
  }
  // The longest approaches first, each kept when it is apart from every gate kept, in space and along the path.
  std::stable_sort(spots.begin(), spots.end(), [](const GateSpot& a, const GateSpot& b) { return a.view_s > b.view_s; });
  std::vector<GateSpot> placed;
  for (const GateSpot& spot : spots) {
    if (static_cast<int>(placed.size()) >= params.max_gates) break;
    const bool apart = std::all_of(placed.begin(), placed.end(), [&](const GateSpot& other) {
      return (other.gate.position - spot.gate.position).norm() >= params.min_separation &&
             std::abs(other.flown - spot.flown) >= params.spacing;
    });
    if (apart) placed.push_back(spot);
  }
  std::sort(placed.begin(), placed.end(), [](const GateSpot& a, const GateSpot& b) { return a.t < b.t; });
  if (static_cast<int>(placed.size()) < params.min_gates) {
    return recordedFlightError(
        "only " + std::to_string(placed.size()) + " place(s) on this flight where the drone flies through a gate (within " +
        formatFixed(params.max_crossing_angle_deg, 0) + " deg of its direction of travel, at >= " + formatFixed(params.min_speed, 2) +
        " m/s) that its camera sees whole for " + formatFixed(params.min_approach_view, 2) + " s on the approach, at least " +
        formatFixed(params.min_separation, 1) + " m apart (" + std::to_string(params.min_gates) + " needed to find the VIO's frame; " +
        formatFixed(flown, 1) + " m flown, " + std::to_string(moving_spots) + " moving spots looked at): give the gates with --track");
  }
  if (approaches != nullptr) approaches->clear();
  for (const GateSpot& spot : placed) {
    TrackGate gate = spot.gate;
    gate.id = static_cast<int>(track.gates.size());
    track.gates.push_back(gate);
    if (approaches != nullptr) approaches->push_back({gate.id, spot.t, spot.view_s});
  }
  const std::string degenerate = degenerateLayout(track);
  if (!degenerate.empty()) {
    return recordedFlightError("the " + std::to_string(track.gates.size()) + " places found for gates are " + degenerate +
                               ": the VIO's frame could not be told from them; give the gates with --track");
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
    auto placed = placeGatesOnPath(*truth, camera, params.detection, params.gates, &flight.approaches);
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
      << "\n  min_speed: " << p.gates.min_speed << "\n  size: " << p.gates.size << "\n  max_gates: " << p.gates.max_gates
      << "\n  min_approach_view: " << p.gates.min_approach_view << "\n  approach_window: " << p.gates.approach_window
      << "\n  max_crossing_angle_deg: " << p.gates.max_crossing_angle_deg
      << "\n  max_passage_offset: " << p.gates.max_passage_offset << "\n  min_gates: " << p.gates.min_gates << "\n"
      << "map_position_sigma: " << p.map_position_sigma << "\nmap_yaw_sigma: " << p.map_yaw_sigma << "\n"
      << "field_errors:\n  camera_time_offset: " << p.field.camera_time_offset << "\n"
      << "  camera_mount_error_deg: " << p.field.camera_mount_error_deg << "\n"
      << detectorYaml(p.detection)
      << "summary:  # measured on this flight, not parameters\n"
      << "  overlap_begin_s: " << flight.overlap_begin << "\n  overlap_end_s: " << flight.overlap_end << "\n"
      << "  duration_s: " << flight.overlap_end - flight.overlap_begin << "\n  length_m: " << flight.path_length << "\n"
      << "  gates: " << flight.true_gates.gates.size() << "\n";
  if (!flight.approaches.empty()) {
    out << "  gate_approaches:  # each placed gate: the crossing time and how long it was whole in view before [s]\n";
    for (const PlacedGateApproach& a : flight.approaches) {
      out << "    - {gate: " << a.gate_id << ", crossing_t: " << a.crossing_time << ", view_s: " << a.view_s << "}\n";
    }
  }
  out
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
