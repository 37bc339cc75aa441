// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/calibration/calibration_problem.h"

#include <algorithm>
#include <cmath>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

constexpr int kGlobal = kCalibrationGlobalUnknowns;

}  // namespace

// One matched detection's four corners predicted at τ: pixels, camera-frame points, the pose and its Jacobian.
struct CalibrationProblem::Prediction {
  bool ok = false;
  std::array<Projection, 4> projection;
  std::array<Eigen::Matrix<double, 2, 3>, 4> d_pixel_d_point;
  std::array<Eigen::Vector3d, 4> p_camera;
  std::array<Eigen::Vector3d, 4> p_world;  ///< the map corners after the gate's correction
  Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
  DriftPoseJacobian pose_jacobian;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

CalibrationProblem::CalibrationProblem(const std::vector<GateCornerMatch>& matches,
                                       const std::vector<OdometrySample>& odometry, const CameraModel& camera,
                                       const CalibrationSolverParams& params)
    : matches_(matches), odometry_(odometry), camera_(camera), params_(params) {
  for (const GateCornerMatch& match : matches_) gate_ids_.push_back(match.gate_id);
  std::sort(gate_ids_.begin(), gate_ids_.end());
  gate_ids_.erase(std::unique(gate_ids_.begin(), gate_ids_.end()), gate_ids_.end());
  for (const GateCornerMatch& match : matches_) {
    MatchGate gate;
    gate.index =
        static_cast<int>(std::lower_bound(gate_ids_.begin(), gate_ids_.end(), match.gate_id) - gate_ids_.begin());
    for (const Eigen::Vector3d& corner : match.p_world) gate.centre += 0.25 * corner;
    match_gates_.push_back(gate);
  }
}

int CalibrationProblem::unknowns(const CalibrationState& state) const {
  return gateColumn(state, 0) + (params_.refine_gates ? 4 * static_cast<int>(gate_ids_.size()) : 0);
}

int CalibrationProblem::gateColumn(const CalibrationState& state, int gate) const {
  return kGlobal + (params_.refine_trajectory ? 4 * state.knots.count() : 0) + 4 * gate;
}

CalibrationProblem::Prediction CalibrationProblem::predict(size_t m, const VioDriftTrack& track,
                                                           const CalibrationState& state, double tau,
                                                           bool jacobians) const {
  Prediction out;
  auto world_T_body = track.worldTBody(tau, jacobians ? &out.pose_jacobian : nullptr);
  if (!world_T_body.ok()) return out;
  out.world_T_body = *world_T_body;
  const Eigen::Isometry3d body_T_world = world_T_body->inverse();
  const Eigen::Vector3d& body_t_camera = camera_.body_T_camera.translation();
  const MatchGate& gate = match_gates_[m];
  const Eigen::Vector4d correction =
      params_.refine_gates ? state.gates[static_cast<size_t>(gate.index)] : Eigen::Vector4d::Zero();
  const Eigen::Matrix3d turn = rotationAboutZ(correction[3]);
  for (size_t i = 0; i < 4; ++i) {
    out.p_world[i] = gate.centre + correction.head<3>() + turn * (matches_[m].p_world[i] - gate.centre);
    out.p_camera[i] = state.body_R_camera.transpose() * (body_T_world * out.p_world[i] - body_t_camera);
    out.projection[i] =
        jacobians ? camera_.project(out.p_camera[i], &out.d_pixel_d_point[i]) : camera_.project(out.p_camera[i]);
  }
  out.ok = true;
  return out;
}

std::vector<double> CalibrationProblem::residualNorms(const CalibrationState& state) const {
  const VioDriftTrack track(odometry_, state.knots);
  std::vector<double> norms;
  for (size_t m = 0; m < matches_.size(); ++m) {
    const Prediction p = predict(m, track, state, matches_[m].t - state.time_offset, false);
    for (size_t i = 0; p.ok && i < 4; ++i) {
      if (p.projection[i].in_front) norms.push_back((p.projection[i].pixel - matches_[m].pixels[i]).norm());
    }
  }
  return norms;
}

double CalibrationProblem::priorCost(const CalibrationState& state, Eigen::MatrixXd* H, Eigen::VectorXd* g) const {
  double cost = 0.0;
  // Independent scalar priors ½ information (x_b − x_a − 0)² (a = −1: on x_b alone), into H and g.
  const auto add = [&](int a, int b, double step, double information) {
    cost += 0.5 * information * step * step;
    if (H == nullptr) return;
    (*H)(b, b) += information;
    (*g)[b] += information * step;
    if (a < 0) return;
    (*H)(a, a) += information, (*H)(a, b) -= information, (*H)(b, a) -= information;
    (*g)[a] -= information * step;
  };
  if (params_.refine_trajectory) {
    const int K = state.knots.count();
    const double root = std::sqrt(state.knots.spacing);
    const double yaw_information = 1.0 / std::pow(params_.knot_sigma_yaw * root, 2);
    const double offset_information = 1.0 / std::pow(params_.knot_sigma_offset * root, 2);
    for (int k = 0; k + 1 < K; ++k) {
      const size_t a = static_cast<size_t>(k);
      add(kGlobal + k, kGlobal + k + 1, state.knots.yaw[a + 1] - state.knots.yaw[a], yaw_information);
      for (int axis = 0; axis < 3; ++axis) {
        const int column = kGlobal + K + 3 * k + axis;
        add(column, column + 3, state.knots.offset[a + 1][axis] - state.knots.offset[a][axis], offset_information);
      }
    }
  }
  if (params_.refine_gates) {
    const double position_information = 1.0 / std::pow(params_.gate_sigma_position, 2);
    const double yaw_information = 1.0 / std::pow(params_.gate_sigma_yaw, 2);
    for (int gate = 0; gate < static_cast<int>(gate_ids_.size()); ++gate) {
      const Eigen::Vector4d& correction = state.gates[static_cast<size_t>(gate)];
      for (int axis = 0; axis < 4; ++axis) {
        add(-1, gateColumn(state, gate) + axis, correction[axis], axis < 3 ? position_information : yaw_information);
      }
    }
  }
  return cost;
}

double CalibrationProblem::evaluate(const CalibrationState& state, double scale, Eigen::MatrixXd* H, Eigen::VectorXd* g,
                                    CalibrationSolution* stats) const {
  const VioDriftTrack track(odometry_, state.knots);
  const double c2 = scale * scale;
  double cost = 0.0, sum_squares = 0.0, inlier_squares = 0.0;
  if (stats != nullptr) stats->detections = stats->corners = stats->inlier_corners = 0;
  for (size_t m = 0; m < matches_.size(); ++m) {
    const Prediction p = predict(m, track, state, matches_[m].t - state.time_offset, H != nullptr);
    if (!p.ok) continue;
    if (stats != nullptr) ++stats->detections;
    Eigen::Matrix<double, 8, 1> residual = Eigen::Matrix<double, 8, 1>::Zero();
    Eigen::Matrix<double, 8, 1> weight = Eigen::Matrix<double, 8, 1>::Zero();
    for (size_t i = 0; i < 4; ++i) {
      if (!p.projection[i].in_front) continue;
      const Eigen::Vector2d r = p.projection[i].pixel - matches_[m].pixels[i];
      const double s = r.squaredNorm();
      cost += 0.5 * c2 * std::log1p(s / c2);
      residual.segment<2>(2 * static_cast<long>(i)) = r;
      weight.segment<2>(2 * static_cast<long>(i)).setConstant(1.0 / (1.0 + s / c2));
      if (stats == nullptr) continue;
      ++stats->corners;
      sum_squares += s;
      if (s <= 9.0 * c2) ++stats->inlier_corners, inlier_squares += s;
    }
    if (H != nullptr) accumulate(m, track, state, p, residual, weight, *H, *g);
  }
  if (stats != nullptr) {
    stats->rms_px = stats->corners > 0 ? std::sqrt(sum_squares / stats->corners) : 0.0;
    stats->inlier_rms_px = stats->inlier_corners > 0 ? std::sqrt(inlier_squares / stats->inlier_corners) : 0.0;
  }
  return cost + priorCost(state, H, g);
}

CalibrationState CalibrationProblem::plus(const CalibrationState& state, const Eigen::VectorXd& dx) const {
  CalibrationState out = state;
  out.time_offset += dx[0];
  out.body_R_camera = state.body_R_camera * so3Exp(dx.segment<3>(1));
  approximateNearestRotation(out.body_R_camera);
  const int K = out.knots.count();
  for (int k = 0; params_.refine_trajectory && k < K; ++k) {
    out.knots.yaw[static_cast<size_t>(k)] += dx[kGlobal + k];
    out.knots.offset[static_cast<size_t>(k)] += dx.segment<3>(kGlobal + K + 3 * k);
  }
  for (int gate = 0; params_.refine_gates && gate < static_cast<int>(out.gates.size()); ++gate) {
    out.gates[static_cast<size_t>(gate)] += dx.segment<4>(gateColumn(state, gate));
  }
  return out;
}

// One detection's 8 rows over the columns it touches (δ, ω | ψ_0 … ψ_s+1, c_s, c_s+1 | its gate), into H and g.
void CalibrationProblem::accumulate(size_t m, const VioDriftTrack& track, const CalibrationState& state,
                                    const Prediction& p, const Eigen::Matrix<double, 8, 1>& residual,
                                    const Eigen::Matrix<double, 8, 1>& weight, Eigen::MatrixXd& H,
                                    Eigen::VectorXd& g) const {
  const KnotSegment& segment = p.pose_jacobian.segment;
  const int K = state.knots.count(), yaw_columns = segment.index + 2;
  std::vector<int> columns = {0, 1, 2, 3};
  if (params_.refine_trajectory) {
    for (int j = 0; j < yaw_columns; ++j) columns.push_back(kGlobal + j);
    for (int j = 0; j < 6; ++j) columns.push_back(kGlobal + K + 3 * segment.index + j);
  }
  const long gate_block = static_cast<long>(columns.size());
  for (int j = 0; params_.refine_gates && j < 4; ++j) columns.push_back(gateColumn(state, match_gates_[m].index) + j);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(8, static_cast<long>(columns.size()));
  const double tau = matches_[m].t - state.time_offset;
  const Prediction later = predict(m, track, state, tau + params_.time_step, false);
  const Prediction earlier = predict(m, track, state, tau - params_.time_step, false);
  const Eigen::Matrix3d camera_R_body = state.body_R_camera.transpose();
  const Eigen::Matrix3d& world_R_body = p.world_T_body.linear();
  const Eigen::Matrix3d world_R_odom = world_R_body * p.pose_jacobian.odom_R_body.transpose();
  const Eigen::Vector3d& centre = match_gates_[m].centre;
  for (size_t i = 0; i < 4; ++i) {
    if (!p.projection[i].in_front) continue;
    const long row = 2 * static_cast<long>(i);
    if (later.ok && earlier.ok && later.projection[i].in_front && earlier.projection[i].in_front) {
      J.block<2, 1>(row, 0) = -(later.projection[i].pixel - earlier.projection[i].pixel) / (2.0 * params_.time_step);
    }
    const Eigen::Matrix<double, 2, 3>& J_pixel_point = p.d_pixel_d_point[i];
    J.block<2, 3>(row, 1) = J_pixel_point * skew(p.p_camera[i]);  // p_camera = Exp(ω)ᵀ q: ∂/∂ω = [p_camera]×
    const Eigen::Matrix<double, 2, 3> J_position = -J_pixel_point * camera_R_body * world_R_body.transpose();
    if (params_.refine_trajectory) {
      const Eigen::Vector3d p_odom = world_R_odom.transpose() * (p.p_world[i] - p.world_T_body.translation());
      const Eigen::Vector2d J_turn = -J_pixel_point * camera_R_body * p.pose_jacobian.odom_R_body.transpose() *
                                     Eigen::Vector3d::UnitZ().cross(p_odom);  // ∂/∂ψ(τ) through world_R_body
      J.block(row, kGlobal, 2, yaw_columns) = J_position * p.pose_jacobian.d_position_d_yaw;
      J.block<2, 1>(row, kGlobal + segment.index) += (1.0 - segment.weight) * J_turn;
      J.block<2, 1>(row, kGlobal + segment.index + 1) += segment.weight * J_turn;
      J.block<2, 3>(row, kGlobal + yaw_columns) = (1.0 - segment.weight) * J_position;
      J.block<2, 3>(row, kGlobal + yaw_columns + 3) = segment.weight * J_position;
    }
    if (params_.refine_gates) {  // the corner moves with the gate: ∂pixel/∂p_world = −J_position
      J.block<2, 3>(row, gate_block) = -J_position;
      J.block<2, 1>(row, gate_block + 3) =
          -J_position * Eigen::Vector3d::UnitZ().cross(
                            p.p_world[i] - centre - state.gates[static_cast<size_t>(match_gates_[m].index)].head<3>());
    }
  }
  const Eigen::MatrixXd weighted = weight.asDiagonal() * J;
  const Eigen::MatrixXd JtWJ = J.transpose() * weighted;
  const Eigen::VectorXd JtWr = weighted.transpose() * residual;
  for (size_t a = 0; a < columns.size(); ++a) {
    g[columns[a]] += JtWr[static_cast<long>(a)];
    for (size_t b = 0; b < columns.size(); ++b)
      H(columns[a], columns[b]) += JtWJ(static_cast<long>(a), static_cast<long>(b));
  }
}

}  // namespace dualgraph
