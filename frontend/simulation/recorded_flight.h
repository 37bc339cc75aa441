// SPDX-License-Identifier: MIT
// Recorded-flight mode: virtual gates on a recorded ground-truth path, detections synthesised from it, the VIO as recorded.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/track.h"
#include "dualgraph/frontend/io/sequence_folder.h"
#include "dualgraph/frontend/simulation/body_trajectory.h"
#include "dualgraph/frontend/simulation/detection_simulator.h"
#include "dualgraph/frontend/simulation/field_errors.h"

namespace dualgraph {

/// Where virtual gates go on a recorded path, as a venue would put them: where the drone flies through a gate's
/// opening (within `max_passage_offset` of its centre, its normal within `max_crossing_angle_deg` of the horizontal direction
/// of travel) and its camera sees the whole gate on the approach for at least `min_approach_view` seconds without
/// a break (the detector's geometry: range, view angle, the four corners inside the image). Spots every 0.05 s of
/// flight are ranked by their approach view, the longest first; each is kept when it is at least `min_separation`
/// from every gate kept and at least `spacing` metres of path from each. Deterministic: no random draw.
struct GatePlacementParams {
  double spacing = 4.0;         ///< path length flown between two gates' spots, at least [m], > 0
  double min_separation = 2.0;  ///< between gate centres [m], ≥ 0
  double min_speed = 0.2;       ///< horizontal speed below which the direction of travel is undefined [m/s], > 0
  double size = 1.5;            ///< side of the inner square [m], > 0
  int max_gates = 100;          ///< ≥ 1
  double min_approach_view = 1.0;       ///< the whole gate in view without a break before the crossing [s], ≥ 0
  double approach_window = 8.0;         ///< how long before the crossing the approach is looked at [s], > 0
  double max_crossing_angle_deg = 60.0; ///< between the gate's normal and the direction of travel [deg], in [0, 85]
  /// How far from the opening's centre the body may pass, across and up [m], in [0, size/2): a gate whose centre
  /// sits below the path is seen whole by a camera pitched down (EuRoC's looks ≈ 20° below the horizon).
  double max_passage_offset = 0.5;
  int min_gates = 3;            ///< fewer places than this: an error (no sequence that can never lock), ≥ 1
};

/// One placed gate's approach: how long the camera saw it whole, without a break, before the drone flew through.
struct PlacedGateApproach {
  int gate_id = -1;
  double crossing_time = 0.0;  ///< the ground truth's time at the gate [s]
  double view_s = 0.0;         ///< [s]
};

/// Gates on `truth` (world frame, ids 0, 1, … in the order flown) seen through `camera` (its body_T_camera) with
/// the geometry of `detector`; `approaches` (optional) gets each gate's approach. kInvalidArgument naming the
/// parameter out of range, or when fewer than `min_gates` places exist (the message says how many and why).
Result<Track> placeGatesOnPath(const SampledTrajectory& truth, const CameraModel& camera,
                               const DetectionSimParams& detector, const GatePlacementParams& params,
                               std::vector<PlacedGateApproach>* approaches = nullptr);

/// Everything a recorded-flight sequence depends on besides the two trajectories and the camera.
struct RecordedFlightParams {
  std::uint64_t seed = 1;      ///< detections (stream 2), map perturbation (3), camera mount (5)
  GatePlacementParams gates;   ///< used when no track is given
  DetectionSimParams detection;
  double map_position_sigma = 0.0;  ///< σ of the written map's gate centres, per axis [m]
  double map_yaw_sigma = 0.0;       ///< σ of the written map's gate yaw [rad]
  /// camera_time_offset and camera_mount_error_deg apply; the VIO's frame and drift are the recording's own, so
  /// vio_frame_yaw and vio_frame_offset must be 0.
  FieldErrorParams field;
};

/// A recorded flight with virtual gates: the sequence to run and what made it.
struct RecordedFlight {
  Sequence sequence;               ///< the recorded VIO and ground truth, synthesised corners, written map and camera
  Track true_gates;                ///< the gates the detections were made from (placed, or the track given)
  std::vector<SimulatedDetection> detections;  ///< with their truth
  DetectionSimStats detection_stats;
  double overlap_begin = 0.0;      ///< the span where both trajectories have samples: detections only there [s]
  double overlap_end = 0.0;
  double path_length = 0.0;        ///< ground truth's path over the overlap [m]
  bool gates_placed = true;        ///< false: `track` gave them
  std::vector<PlacedGateApproach> approaches;  ///< each placed gate's approach (empty when `track` gave them)
};

/// Places gates on `ground_truth` (or takes `track`'s, whose path is ignored), synthesises corner detections from
/// it with `camera` over the span both trajectories cover, and keeps `vio` as it is. kInvalidArgument naming the
/// parameter, or when the trajectories do not overlap by at least a second; the detector's and the camera's errors.
Result<RecordedFlight> simulateRecordedFlight(const OdometryLog& ground_truth, const OdometryLog& vio,
                                              const Track* track, const CameraModel& camera,
                                              const RecordedFlightParams& params);

/// sequence.yaml of a recorded flight: the source files, the seed, every parameter and a measured summary.
std::string recordedFlightYaml(const RecordedFlight& flight, const RecordedFlightParams& params,
                               const std::string& ground_truth_path, const std::string& vio_path);

/// Writes the sequence folder: vio.tum and gt.tum as byte copies of the recorded files (any format the recogniser
/// reads; stamps and rows exactly as recorded), corners.csv, gates.yaml, camera.yaml and sequence.yaml. kIoError
/// naming the file.
Status writeRecordedFlight(const std::string& dir, const RecordedFlight& flight, const RecordedFlightParams& params,
                           const std::string& ground_truth_path, const std::string& vio_path);

}  // namespace dualgraph
