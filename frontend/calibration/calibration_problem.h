// SPDX-License-Identifier: MIT
// CalibrationProblem (internal to solveCameraCalibration): the robust reprojection cost and its normal equations.
#pragma once

#include <Eigen/Core>
#include <map>
#include <vector>

#include "dualgraph/frontend/calibration/calibration_solver.h"

namespace dualgraph {

/// δ and ω: the unknowns before the knots' and the gates' in CalibrationProblem's vector.
constexpr int kCalibrationGlobalUnknowns = 4;

/// The unknowns of the calibration (solveCameraCalibration): δ [s], body_R_camera, the drift knots and, per map
/// gate seen, a correction (offset [m, world], yaw [rad] about the world z axis through the gate's centre).
struct CalibrationState {
  double time_offset = 0.0;
  Eigen::Matrix3d body_R_camera = Eigen::Matrix3d::Identity();
  DriftKnots knots;
  std::vector<Eigen::Vector4d, Eigen::aligned_allocator<Eigen::Vector4d>> gates;  ///< [x y z yaw] per gate index
};

/// ½ Σ ρ(‖r‖²) over the matched corners (CalibrationSolution's model, Cauchy scale c) plus the Gaussian priors
/// (knot random walk, gate corrections), and its Gauss–Newton normal equations JᵀWJ, JᵀWr (IRLS weights).
/// Unknown vector: [δ, ω (3) | ψ_0 … ψ_K−1 | c_0 … c_K−1 (3 each) | gate_0 … gate_G−1 (4 each)], the knot blocks
/// with refine_trajectory, the gate blocks with refine_gates; ω and the gate yaw are right / world-z increments.
/// Holds references: matches, odometry, camera and params must outlive it.
class CalibrationProblem {
 public:
  CalibrationProblem(const std::vector<GateCornerMatch>& matches, const std::vector<OdometrySample>& odometry,
                     const CameraModel& camera, const CalibrationSolverParams& params);

  /// The gate ids in the matches, in the order of CalibrationState::gates.
  const std::vector<int>& gateIds() const { return gate_ids_; }
  int unknowns(const CalibrationState& state) const;
  /// ‖r‖ [px] of every corner in front of the camera.
  std::vector<double> residualNorms(const CalibrationState& state) const;
  /// The cost at `state` with Cauchy scale `scale` [px]; H, g (size unknowns, zeroed by the caller) get the
  /// normal equations when non-null; `stats` gets detections, corners, inliers (‖r‖ ≤ 3c) and RMS values.
  double evaluate(const CalibrationState& state, double scale, Eigen::MatrixXd* H, Eigen::VectorXd* g,
                  CalibrationSolution* stats = nullptr) const;
  /// state ⊞ dx.
  CalibrationState plus(const CalibrationState& state, const Eigen::VectorXd& dx) const;

 private:
  struct Prediction;
  struct MatchGate {
    int index = 0;                                     ///< into gate_ids_
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< mean of the four map corners [m]
  };
  Prediction predict(size_t m, const VioDriftTrack& track, const CalibrationState& state, double tau,
                     bool jacobians) const;
  double priorCost(const CalibrationState& state, Eigen::MatrixXd* H, Eigen::VectorXd* g) const;
  void accumulate(size_t m, const VioDriftTrack& track, const CalibrationState& state, const Prediction& p,
                  const Eigen::Matrix<double, 8, 1>& residual, const Eigen::Matrix<double, 8, 1>& weight,
                  Eigen::MatrixXd& H, Eigen::VectorXd& g) const;
  int gateColumn(const CalibrationState& state, int gate) const;

  const std::vector<GateCornerMatch>& matches_;
  const std::vector<OdometrySample>& odometry_;
  const CameraModel& camera_;
  const CalibrationSolverParams& params_;
  std::vector<int> gate_ids_;
  std::vector<MatchGate, Eigen::aligned_allocator<MatchGate>> match_gates_;  ///< per match
};

}  // namespace dualgraph
