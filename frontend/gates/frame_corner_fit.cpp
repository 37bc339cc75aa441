// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/frame_corner_fit.h"

#include <cmath>
#include <limits>

#include "dualgraph/frontend/gates/gate_symmetry.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

using Parameters = Eigen::Vector4d;  // x, y, z [m], yaw [rad]

Eigen::Isometry3d frameOf(const Parameters& p) { return gravityAligned(p(3), p.head<3>()); }

/// One corner: its point in the world, the body pose in the odometry frame, the camera on the body, the measured
/// normalised coordinates and the whitening of their covariance.
struct Corner {
  Eigen::Vector3d p_world;
  Eigen::Isometry3d odom_T_camera;
  Eigen::Vector2d measured;
  Eigen::Matrix2d whitening;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
using Corners = std::vector<Corner, Eigen::aligned_allocator<Corner>>;

/// Whitened residual of one corner under `frame` (NaN components when behind the camera).
Eigen::Vector2d residual(const Corner& c, const Eigen::Isometry3d& frame) {
  const Eigen::Vector3d p = (frame * c.odom_T_camera).inverse() * c.p_world;
  if (!(p.z() > 1e-3)) return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  return c.whitening * (p.head<2>() / p.z() - c.measured);
}

constexpr double kHuber = 2.0;

double huberWeight(double norm) { return norm <= kHuber ? 1.0 : kHuber / norm; }

/// Σ ρ(|r|) (Huber's, 2·ρ = r² inside) and the count of corners in front of their camera.
double cost(const Corners& corners, const Parameters& p, int* in_front = nullptr) {
  const Eigen::Isometry3d frame = frameOf(p);
  double total = 0.0;
  int front = 0;
  for (const Corner& c : corners) {
    const Eigen::Vector2d r = residual(c, frame);
    if (!r.allFinite()) {
      total += 2.0 * kHuber * 10.0;  // behind the camera: a large, bounded cost
      continue;
    }
    ++front;
    const double n = r.norm();
    total += n <= kHuber ? n * n : 2.0 * kHuber * n - kHuber * kHuber;
  }
  if (in_front != nullptr) *in_front = front;
  return total;
}

}  // namespace

double FrameCornerFit::positionSigmaAt(const Eigen::Isometry3d& odom_T_body) const {
  // d(R(yaw) p + t)/d(t, yaw) = [I, ẑ × (R p)].
  const Eigen::Vector3d rotated = world_T_odom.linear() * odom_T_body.translation();
  Eigen::Matrix<double, 3, 4> jacobian;
  jacobian.leftCols<3>().setIdentity();
  jacobian.col(3) = Eigen::Vector3d(-rotated.y(), rotated.x(), 0.0);
  return std::sqrt((jacobian * covariance * jacobian.transpose()).trace() / 3.0);
}

FrameCornerFit fitFrameOnCorners(const std::vector<FrameFitDetection, Eigen::aligned_allocator<FrameFitDetection>>& detections,
                                 const GateMap& map, const Eigen::Isometry3d& start, double max_distance) {
  FrameCornerFit fit;
  fit.world_T_odom = start;
  Corners corners;
  for (const FrameFitDetection& d : detections) {
    const GateObservation& o = d.observation;
    if (o.corner_rays.count != 4) continue;
    const Eigen::Isometry3d world_T_gate_seen = start * d.odom_T_body * o.body_T_gate;
    int best = -1;
    double nearest = max_distance;
    for (const auto& [id, world_T_gate] : map.world_T_gate) {
      if (o.gate_id >= 0 && map.contains(o.gate_id) && id != o.gate_id) continue;
      const double distance = (world_T_gate.translation() - world_T_gate_seen.translation()).norm();
      if (distance <= nearest) {
        nearest = distance;
        best = id;
      }
    }
    if (best < 0) continue;
    const Eigen::Isometry3d& world_T_gate = map.world_T_gate.at(best);
    // The side and the quarter turn of a banked view's corner labels: a corner p of the detected gate lies at
    // Sᵀ · p in the map gate's frame.
    const Eigen::Matrix3d symmetry =
        nearestGateSymmetry(world_T_gate.linear(), world_T_gate_seen.linear(), GateSides::kEither).transpose();
    const Eigen::Isometry3d odom_T_camera = d.odom_T_body * o.corner_rays.body_T_camera;
    for (int j = 0; j < 4; ++j) {
      const Eigen::LLT<Eigen::Matrix2d> llt(o.corner_rays.covariance[j]);
      if (llt.info() != Eigen::Success) continue;
      Corner c;
      c.p_world = world_T_gate * (symmetry * o.corner_rays.p_gate.col(j));
      c.odom_T_camera = odom_T_camera;
      c.measured = o.corner_rays.normalized.col(j);
      c.whitening = llt.matrixL().solve(Eigen::Matrix2d::Identity());
      corners.push_back(c);
    }
    ++fit.detections;
  }
  fit.corners = static_cast<int>(corners.size());
  if (fit.corners < 12) return fit;  // three gates' worth at least
  Parameters p(start.translation().x(), start.translation().y(), start.translation().z(), headingOf(start.linear()));
  const double start_cost = cost(corners, p);
  double current = start_cost;
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  for (int iteration = 0; iteration < 15; ++iteration) {
    const Eigen::Isometry3d frame = frameOf(p);
    normal.setZero();
    Eigen::Vector4d gradient = Eigen::Vector4d::Zero();
    for (const Corner& c : corners) {
      const Eigen::Vector2d r = residual(c, frame);
      if (!r.allFinite()) continue;
      Eigen::Matrix<double, 2, 4> jacobian;
      for (int k = 0; k < 4; ++k) {
        const double h = k < 3 ? 1e-6 : 1e-7;
        Parameters plus = p, minus = p;
        plus(k) += h;
        minus(k) -= h;
        jacobian.col(k) = (residual(c, frameOf(plus)) - residual(c, frameOf(minus))) / (2.0 * h);
      }
      if (!jacobian.allFinite()) continue;
      const double w = huberWeight(r.norm());
      normal += w * jacobian.transpose() * jacobian;
      gradient += w * jacobian.transpose() * r;
    }
    const Eigen::Vector4d step = normal.ldlt().solve(-gradient);
    if (!step.allFinite()) return fit;
    // Halve the step until the cost falls.
    double scale = 1.0;
    bool moved = false;
    for (int halving = 0; halving < 10; ++halving, scale *= 0.5) {
      const Parameters trial = p + scale * step;
      const double trial_cost = cost(corners, trial);
      if (trial_cost < current) {
        p = trial;
        current = trial_cost;
        moved = true;
        break;
      }
    }
    if (!moved || step.norm() * scale < 1e-7) break;
  }
  int in_front = 0;
  current = cost(corners, p, &in_front);
  fit.rms_before = std::sqrt(start_cost / (2.0 * corners.size()));
  fit.rms_after = std::sqrt(current / (2.0 * corners.size()));
  const double dof = 2.0 * in_front - 4.0;
  if (!(current < start_cost) || dof <= 0.0) return fit;
  const double variance_factor = std::max(1.0, current / dof);
  const Eigen::Matrix4d covariance = normal.inverse() * variance_factor;
  if (!covariance.allFinite()) return fit;
  fit.world_T_odom = frameOf(p);
  fit.covariance = covariance;
  fit.refined = true;
  return fit;
}

}  // namespace dualgraph
