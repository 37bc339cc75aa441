// SPDX-License-Identifier: MIT
// The simulated gate detector: noisy corner pixels, misses, displaced corners, wrong ids, false gates.
#pragma once

#include <cstdint>
#include <vector>

#include "core/status.h"
#include "frontend/gates/camera_model.h"
#include "frontend/io/detection_io.h"
#include "frontend/simulation/flight.h"
#include "frontend/gates/track.h"

namespace dualgraph {

/// What the simulated gate detector does (all seeded). Images come at camera_rate, of which only
/// every `keep_every`-th is processed (RATM: 120 Hz, 3 of 4 dropped → 30 Hz).
struct DetectionSimParams {
  double camera_rate = 120.0;          ///< [Hz], > 0
  int keep_every = 4;                  ///< ≥ 1
  double pixel_sigma = 1.0;            ///< Gaussian noise per corner coordinate [px], ≥ 0
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
  Eigen::Matrix<double, 2, 4> true_pixels = Eigen::Matrix<double, 2, 4>::Zero();  ///< noise-free, same order

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Counts of what the detector did over a flight.
struct DetectionSimStats {
  int images = 0;            ///< processed images
  int visible = 0;           ///< gate views passing range, angle and image checks
  int missed = 0;
  int displaced_corner = 0;
  int wrong_id = 0;
  int false_gates = 0;
};

/// Orders four pixels as DESIGN.md §6 writes them: the two upper ones (smaller v) left to right, then
/// the two lower ones right to left. `order[i]` is the input column that goes to position i.
std::array<int, 4> imageCornerOrder(const Eigen::Matrix<double, 2, 4>& pixels);

/// The gate detections of a flight: at every processed image, every gate whose four inner corners
/// project into the image (CameraModel::project, the flight's true world_T_body) within the range and
/// view-angle limits, in time order, gates in track order, false gates last. Deterministic for a seed.
Result<std::vector<SimulatedDetection>> simulateDetections(const Flight& flight, const Track& track,
                                                           const CameraModel& camera,
                                                           const DetectionSimParams& params, std::uint64_t seed,
                                                           DetectionSimStats* stats = nullptr);

}  // namespace dualgraph
