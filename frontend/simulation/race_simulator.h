// SPDX-License-Identifier: MIT
// simulateRace: a whole simulated race (flight, ground truth, drifting VIO, detections, map).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/simulation/detection_simulator.h"
#include "dualgraph/frontend/simulation/field_errors.h"
#include "dualgraph/frontend/simulation/flight.h"
#include "dualgraph/frontend/io/odometry_io.h"
#include "dualgraph/frontend/gates/track.h"
#include "dualgraph/frontend/simulation/vio_drift.h"

namespace dualgraph {

/// Everything a simulated race depends on besides the track and the camera. The seed decides every
/// random draw (VIO drift, detections, map perturbation, VIO frame, camera mount, lap variation, each from its
/// own derived stream), so the same parameters give byte-identical sequences.
struct RaceSimParams {
  std::uint64_t seed = 1;
  FlightParams flight;         ///< laps and max_speed are taken from the track unless overridden; variation_seed
                               ///< is always derived from `seed` (stream 6)
  bool override_laps = false;
  bool override_speed = false;
  VioDriftParams vio;
  DetectionSimParams detection;
  double gt_rate = 200.0;      ///< ground-truth samples [Hz], ≥ 100
  double vio_rate = 100.0;     ///< odometry samples [Hz], > 0
  enum class DetectionOutput { kCorners, kPoses } output = DetectionOutput::kCorners;
  double map_position_sigma = 0.0;  ///< σ of the perturbation of the written map's gate centres [m] (per axis)
  double map_yaw_sigma = 0.0;       ///< σ of the perturbation of the written map's gate yaw [rad]
  FieldErrorParams field;           ///< VIO frame, camera clock and mount (each from its own stream)
  /// The track flown and mapped is the given one scaled by this horizontally (scaledTrack): 2.5 turns the RATM
  /// ellipse's 8 m between gates into 20 m, a big hall where gates are seen from 10–15 m. > 0.
  double track_scale = 1.0;
};

/// `track` with every gate centre, path centre, ellipse semi-axis, lemniscate size and waypoint scaled by `scale`
/// in x and y [m]; heights, gate sizes and yaws kept.
Track scaledTrack(const Track& track, double scale);

/// "corners" or "poses".
const char* detectionOutputName(RaceSimParams::DetectionOutput output);

/// A simulated race: the flight, its ground truth, the drifting VIO, the detections and the map as
/// the sequence folder will hold it. `flight` keeps the simulator's clock (0 at take-off); every stamp below is that
/// time plus field.time_origin (plus vio_time_offset for the VIO, camera_time_offset for the detections).
struct SimulatedRace {
  Flight flight;
  std::vector<std::pair<double, Eigen::Isometry3d>> ground_truth;  ///< (t [s], world_T_body) at gt_rate
  OdometryLog vio;                           ///< odom_T_body at vio_rate with absolute covariances
  std::vector<SimulatedDetection> detections;
  DetectionSimStats detection_stats;
  std::vector<GateObservation> pose_detections;  ///< kPoses output: one per accepted PnP solution
  int pnp_rejected = 0;                          ///< kPoses output: detections PnP refused
  int pnp_partial_skipped = 0;                   ///< kPoses output: partial detections, not given to PnP (not in pnp_rejected)
  Track map;                                     ///< the written gates.yaml (perturbed when asked), no path
  CameraModel camera;                            ///< the written camera.yaml (with the mount error when asked)
  Eigen::Isometry3d world_T_odom = Eigen::Isometry3d::Identity();  ///< the VIO frame's truth (field errors)
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Flies `track` (which must have a path; scaled by params.track_scale) with `camera` and simulates all sensors.
/// kInvalidArgument for invalid parameters, a track without path or gates, an invalid camera.
Result<SimulatedRace> simulateRace(const Track& track, const CameraModel& camera, const RaceSimParams& params);

}  // namespace dualgraph
