// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/race_simulator.h"

#include <cmath>
#include <random>

#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/frontend/gates/gate_pnp.h"
#include "dualgraph/frontend/gates/gate_symmetry.h"

namespace dualgraph {
namespace {

Status invalidRace(const std::string& what) { return Status(StatusCode::kInvalidArgument, "race simulator: " + what); }

// The gate frame of a PnP solution is fixed by the image corner order only up to the square's 90°
// turns about its normal; a pose detector that knows the map reports the turn closest to the gate.
void alignToTrueGate(GateObservation& observation, const Eigen::Isometry3d& true_body_T_gate) {
  const Eigen::Matrix3d turn =
      nearestGateSymmetry(true_body_T_gate.linear(), observation.body_T_gate.linear(), GateSides::kKnown);
  if (turn.isIdentity(0.0)) return;
  observation = inTurnedGateFrame(std::move(observation), turn);
}

// The VIO frame of a flight: world_T_odom with a yaw and a horizontal offset drawn from stream 4 (identity
// when both are 0, without a draw, so a clean race keeps its bits).
Eigen::Isometry3d vioFrame(const FieldErrorParams& field, std::uint64_t seed) {
  Eigen::Isometry3d world_T_odom = Eigen::Isometry3d::Identity();
  if (field.vio_frame_yaw == 0.0 && field.vio_frame_offset == 0.0) return world_T_odom;
  std::mt19937_64 rng(simulationStreamSeed(seed, 4));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double yaw = field.vio_frame_yaw * (2.0 * unit(rng) - 1.0);
  const double radius = field.vio_frame_offset * std::sqrt(unit(rng));
  const double bearing = 2.0 * M_PI * unit(rng);
  world_T_odom.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  world_T_odom.translation() << radius * std::cos(bearing), radius * std::sin(bearing), 0.0;
  return world_T_odom;
}

// Every stamp onto the written clocks: the time origin, and the VIO's own offset (the detections already carry the
// camera's). A flight on the simulator's clock keeps its bits.
void shiftClocks(const FieldErrorParams& field, SimulatedRace& race) {
  if (field.time_origin == 0.0 && field.vio_time_offset == 0.0) return;
  for (auto& [t, pose] : race.ground_truth) t += field.time_origin;
  for (OdometrySample& sample : race.vio.samples) sample.t += field.time_origin + field.vio_time_offset;
  for (SimulatedDetection& detection : race.detections) detection.corners.t += field.time_origin;
  for (GateObservation& observation : race.pose_detections) observation.t += field.time_origin;
}

}  // namespace

Track scaledTrack(const Track& track, double scale) {
  Track scaled = track;
  for (TrackGate& gate : scaled.gates) gate.position.head<2>() *= scale;
  TrackPath& path = scaled.path;
  path.center *= scale;
  path.semi_axis_x *= scale;
  path.semi_axis_y *= scale;
  path.lemniscate_a *= scale;
  for (Eigen::Vector3d& waypoint : path.waypoints) waypoint.head<2>() *= scale;
  return scaled;
}

const char* detectionOutputName(RaceSimParams::DetectionOutput output) {
  return output == RaceSimParams::DetectionOutput::kPoses ? "poses" : "corners";
}

Result<SimulatedRace> simulateRace(const Track& given_track, const CameraModel& camera, const RaceSimParams& params) {
  if (given_track.gates.empty()) return invalidRace("the track has no gates");
  if (!(std::isfinite(params.track_scale) && params.track_scale > 0.0 && params.track_scale <= 100.0)) {
    return invalidRace("track_scale must be in (0, 100]");
  }
  const Track track = params.track_scale == 1.0 ? given_track : scaledTrack(given_track, params.track_scale);
  if (!(std::isfinite(params.gt_rate) && params.gt_rate >= 100.0)) return invalidRace("gt_rate must be >= 100 Hz");
  if (!(std::isfinite(params.vio_rate) && params.vio_rate > 0.0)) return invalidRace("vio_rate must be > 0");
  const std::string field_problem = fieldErrorsProblem(params.field, params.map_position_sigma, params.map_yaw_sigma);
  if (!field_problem.empty()) return invalidRace(field_problem);
  DG_RETURN_IF_ERROR(camera.validate());
  const FieldErrorParams& field = params.field;
  FlightParams flight_params = params.flight;
  if (!params.override_laps) flight_params.laps = track.laps;
  if (!params.override_speed) flight_params.max_speed = track.speed;
  flight_params.variation_seed = simulationStreamSeed(params.seed, 6);  // drawn from only with lap variation
  auto flight = Flight::plan(track.path, flight_params);
  if (!flight.ok()) return flight.status();

  SimulatedRace race;
  race.flight = std::move(flight).value();
  const double duration = race.flight.duration();
  for (long k = 0; k / params.gt_rate <= duration; ++k) {
    const double t = k / params.gt_rate;
    race.ground_truth.emplace_back(t, race.flight.at(t).world_T_body);
  }
  std::vector<double> vio_t;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> vio_truth;
  for (long k = 0; k / params.vio_rate <= duration; ++k) {
    vio_t.push_back(k / params.vio_rate);
    vio_truth.push_back(race.flight.at(vio_t.back()).world_T_body);
  }
  auto vio = simulateVio(vio_t, vio_truth, params.vio, simulationStreamSeed(params.seed, 1));
  if (!vio.ok()) return vio.status();
  race.vio = std::move(vio).value();
  race.world_T_odom = vioFrame(field, params.seed);
  if (!race.world_T_odom.matrix().isIdentity(0.0)) {  // right perturbations: the covariances stay as they are
    const Eigen::Isometry3d odom_T_world = race.world_T_odom.inverse();
    for (OdometrySample& sample : race.vio.samples) sample.odom_T_body = odom_T_world * sample.odom_T_body;
  }

  auto detections = simulateDetections(race.flight, track, camera, params.detection, simulationStreamSeed(params.seed, 2),
                                       &race.detection_stats);
  if (!detections.ok()) return detections.status();
  race.detections = std::move(detections).value();
  for (SimulatedDetection& detection : race.detections) detection.corners.t += field.camera_time_offset;
  race.camera = mountedCamera(camera, field, params.seed);

  if (params.output == RaceSimParams::DetectionOutput::kPoses) {
    GatePnpParams pnp;
    pnp.pixel_sigma = std::max(params.detection.pixel_sigma, 1e-3);
    for (const SimulatedDetection& d : race.detections) {
      if (!d.corners.complete()) {  // a partial detection: PnP here takes the four corners
        ++race.pnp_partial_skipped;
        continue;
      }
      GateCornerPixels pixels;
      for (int i = 0; i < 4; ++i) pixels.col(i) = d.corners.corners[static_cast<size_t>(i)];
      const bool truth_known = d.kind != SimulatedDetectionKind::kFalseGate;
      const int size_id = truth_known ? d.true_gate_id : d.corners.gate_id;  // a false gate: the size of the id it claims
      pnp.gate_size = track.gates.front().size;
      for (const TrackGate& gate : track.gates) {
        if (gate.id == size_id) pnp.gate_size = gate.size;
      }
      const GateSide side = d.seen_from_front ? GateSide::kFront : GateSide::kBack;
      const GatePnpSolution solution = solveGatePnp(pixels, camera, side, pnp);
      if (!solution.ok()) {
        ++race.pnp_rejected;
        continue;
      }
      GateObservation observation = solution.observation(d.corners.t, d.corners.gate_id);  // time offset included
      if (truth_known) alignToTrueGate(observation, d.body_T_gate);
      race.pose_detections.push_back(observation);
    }
  }

  race.map = perturbedMap(track, params.map_position_sigma, params.map_yaw_sigma, params.seed);
  shiftClocks(field, race);
  return race;
}

}  // namespace dualgraph
