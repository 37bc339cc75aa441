// SPDX-License-Identifier: MIT
// The frame a search locked on, fitted again on the gate corners themselves against the map gates.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dualgraph/dual_graph/gate_map.h"
#include "dualgraph/dual_graph/measurements.h"

namespace dualgraph {

/// One full-gate detection of the search's window: the odometry at its instant and its observation (corner rays).
struct FrameFitDetection {
  Eigen::Isometry3d odom_T_body = Eigen::Isometry3d::Identity();
  GateObservation observation;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// What the fit found.
struct FrameCornerFit {
  bool refined = false;  ///< the fit converged and explains the corners better than the frame it started from
  Eigen::Isometry3d world_T_odom = Eigen::Isometry3d::Identity();  ///< gravity-aligned: yaw and translation
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  ///< of (x, y, z [m], yaw [rad]), scaled by the fit's χ²/dof ≥ 1
  int detections = 0;    ///< detections used (each on the map gate its centre lies nearest, within `max_distance`)
  int corners = 0;
  double rms_before = 0.0;  ///< whitened corner residual RMS at the start [-]
  double rms_after = 0.0;   ///< and at the fit [-]
  /// The position σ per axis [m] this frame puts on a body at odom_T_body: √(trace(J Σ Jᵀ)/3).
  double positionSigmaAt(const Eigen::Isometry3d& odom_T_body) const;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Fits a gravity-aligned world_T_odom (x, y, z, yaw) to the detections' corner rays against the map gates by
/// Gauss–Newton with a Huber weight (k = 2 whitened), starting from `start`. Each detection's gate is the map gate
/// its PnP centre lies nearest under `start` (within `max_distance` [m]; its own id when it has one in the map),
/// its corners matched to that gate's up to the square's symmetry nearest its PnP frame (the side, and a quarter
/// turn about the normal: a detector orders the corners by the image, so a banked drone labels them a turn off). The search's PnP gate centres are biased short at range and
/// its yaw comes from two or three far gates; the corners over the window's motion constrain the frame better.
/// Detections without four corner rays are skipped. Deterministic; never prints. Thread-safe (pure).
FrameCornerFit fitFrameOnCorners(const std::vector<FrameFitDetection, Eigen::aligned_allocator<FrameFitDetection>>& detections,
                                 const GateMap& map, const Eigen::Isometry3d& start, double max_distance);

}  // namespace dualgraph
