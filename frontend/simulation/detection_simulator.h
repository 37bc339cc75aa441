// SPDX-License-Identifier: MIT
// The simulated gate detector: noisy corner pixels, misses, displaced corners, wrong ids, false gates.
#pragma once

#include <cstdint>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/io/detection_io.h"
#include "dualgraph/frontend/simulation/body_trajectory.h"
#include "dualgraph/frontend/simulation/flight.h"
#include "dualgraph/frontend/gates/track.h"

namespace dualgraph {

/// What the simulated gate detector does (all seeded). Images come at camera_rate, of which only
/// every `keep_every`-th is processed (RATM: 120 Hz, 3 of 4 dropped → 30 Hz).
struct DetectionSimParams {
  double camera_rate = 120.0;          ///< [Hz], > 0
  int keep_every = 4;                  ///< ≥ 1
  double pixel_sigma = 1.0;            ///< Gaussian noise per corner coordinate [px], ≥ 0
  /// Motion blur [px per rad/s], ≥ 0: at each processed image the corner noise σ becomes
  /// √(pixel_sigma² + (blur_px_per_rad_s · |ω|)²), ω the body's true angular rate then (bodyAngularRate).
  double blur_px_per_rad_s = 0.0;
  double min_range = 0.5;              ///< camera → gate centre [m]
  double max_range = 15.0;             ///< [m]
  double max_view_angle_deg = 75.0;    ///< angle between the line of sight and the gate normal (either side) [deg]
  double edge_margin = 2.0;            ///< corners closer than this to the image border are not detected [px]
  double miss_probability = 0.1;       ///< a visible gate is not detected, per image
  double displaced_corner_probability = 0.01;  ///< one corner moved by displaced_corner_pixels in a random direction
  double displaced_corner_pixels = 25.0;       ///< [px]
  double wrong_id_probability = 0.01;          ///< the id of another gate (needs ≥ 2 gates)
  double false_gate_probability = 0.01;        ///< per processed image: a gate-like quadrilateral where there is none
  bool unknown_ids = false;            ///< write gate_id −1 everywhere (the association decides)
  /// Gates partly out of the image: a gate whose four corners are all in front of the camera but of which only
  /// k ≥ min_visible_corners (and < 4) project inside the image (edge_margin included) is reported as a partial
  /// detection, the other corners NaN (CornerDetection::visible); false: such a gate is not detected.
  bool partial_gates = false;
  int min_visible_corners = 2;         ///< 2 … 4: the fewest corners a partial detection has
};

/// kInvalidArgument naming the field for a parameter out of range (probabilities in [0, 1], …).
Status validateDetectionSimParams(const DetectionSimParams& params);

/// How a simulated detection came about (ground truth for tests and statistics).
enum class SimulatedDetectionKind { kTrue, kDisplacedCorner, kWrongId, kFalseGate };

/// One simulated detection: the corners as the CSV holds them, and the truth behind them.
struct SimulatedDetection {
  CornerDetection corners;                  ///< t, gate_id as written (−1 with unknown_ids), pixels tl tr br bl
  SimulatedDetectionKind kind = SimulatedDetectionKind::kTrue;
  int true_gate_id = -1;                    ///< −1 for a false gate
  Eigen::Isometry3d body_T_gate = Eigen::Isometry3d::Identity();  ///< true pose of the gate (identity for a false gate)
  bool seen_from_front = true;              ///< camera on the −x side of the gate frame
  /// Noise-free projections, same order; all four, also those of corners a partial detection does not hold.
  Eigen::Matrix<double, 2, 4> true_pixels = Eigen::Matrix<double, 2, 4>::Zero();
  double pixel_sigma = 0.0;                 ///< the corner noise σ applied (blur included; 0 for a false gate) [px]

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Counts of what the detector did over a flight. Gate detections reported = visible + partial_views − missed.
struct DetectionSimStats {
  int images = 0;            ///< processed images
  int visible = 0;           ///< whole gate views: range, angle and all four corners in the image
  int partial_views = 0;     ///< partial gate views (partial_gates): range, angle, 2 or 3 corners in the image
  int missed = 0;            ///< views not detected (whole and partial ones alike)
  int partial = 0;           ///< partial detections reported (partial_views less their misses)
  int displaced_corner = 0;  ///< (whole and partial detections; the displaced corner is a visible one)
  int wrong_id = 0;
  int false_gates = 0;
  double mean_pixel_sigma = 0.0;  ///< effective corner noise σ (blur included) over the gate detections reported [px]
  double max_pixel_sigma = 0.0;   ///< its largest value [px] (0 without gate detections)
};

/// |ω|, the body's true angular rate at t [rad/s] from the flight's attitude (bodyAngularRate of its
/// FlightTrajectory).
double bodyAngularRate(const Flight& flight, double t);

/// What a camera sees of one gate, geometry only (no noise, no miss): in range and within the view angle
/// (`in_range`), every corner in front of the camera (`in_front`), which of the four corners (the gate frame's
/// order, GateSide::kFront) project inside the image with the detector's edge margin, and their pixels.
struct GateView {
  bool in_range = false;   ///< range within [min_range, max_range] and view angle within max_view_angle_deg
  bool in_front = true;    ///< (meaningful only in range)
  std::array<bool, 4> inside{};
  int inside_count = 0;
  Eigen::Matrix<double, 2, 4> pixels = Eigen::Matrix<double, 2, 4>::Zero();
  bool inRange() const { return in_range; }
  bool whole() const { return in_range && inside_count == 4; }  ///< the four corners in the image

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// The view of `gate` from a camera at `world_T_camera` with the detector's range, angle and edge limits;
/// `cos_max_view` = cos(params.max_view_angle_deg), passed in so that a caller looping over images computes it once.
GateView gateViewFrom(const Eigen::Isometry3d& world_T_camera, const TrackGate& gate, const CameraModel& camera,
                      const DetectionSimParams& params, double cos_max_view);

/// The gate detections of a flight: at every processed image, every gate whose four inner corners
/// project into the image (CameraModel::project, the flight's true world_T_body) within the range and
/// view-angle limits (with partial_gates also those with at least min_visible_corners in it), in time order,
/// gates in track order, false gates last. The corners are in the order cornerLabelOrder (gates/partial_gate.h) gives the four true
/// projections (inside the image or not). Deterministic for a seed; with blur 0 and partial_gates false the
/// random draws are those of the detector without either.
Result<std::vector<SimulatedDetection>> simulateDetections(const Flight& flight, const Track& track,
                                                           const CameraModel& camera,
                                                           const DetectionSimParams& params, std::uint64_t seed,
                                                           DetectionSimStats* stats = nullptr);

/// The same detector looking from any true trajectory (a recorded flight: SampledTrajectory): images at
/// truth.begin() + k / camera_rate up to truth.end(), stamped with those times. For a Flight the two are one.
Result<std::vector<SimulatedDetection>> simulateDetections(const BodyTrajectory& truth, const Track& track,
                                                           const CameraModel& camera,
                                                           const DetectionSimParams& params, std::uint64_t seed,
                                                           DetectionSimStats* stats = nullptr);

}  // namespace dualgraph
