// SPDX-License-Identifier: MIT
// VioDriftTrack: world_T_body(t) as the VIO re-integrated under a smooth yaw and offset correction (knots).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/localizer.h"
#include "dualgraph/dual_graph/measurements.h"

namespace dualgraph {

/// Where one instant falls between two knots: value(t) = (1 − weight) · knot[index] + weight · knot[index + 1].
struct KnotSegment {
  int index = 0;        ///< the knot at or before t (the last but one when t is at or past the last knot)
  double weight = 0.0;  ///< ∈ [0, 1]
};

/// The unknowns of a VioDriftTrack: K ≥ 2 knots at t0 + k · spacing [s], each a yaw correction ψ_k [rad] and an
/// offset c_k [m, world]; ψ(t), c(t) linear between knots, the end knots held beyond.
struct DriftKnots {
  double t0 = 0.0;
  double spacing = 1.0;
  std::vector<double> yaw;
  std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> offset;

  int count() const { return static_cast<int>(yaw.size()); }
  double time(int k) const { return t0 + spacing * k; }
  KnotSegment segment(double t) const;
  double yawAt(double t) const;
  Eigen::Vector3d offsetAt(double t) const;
};

/// ∂world_T_body(τ)/∂knots (VioDriftTrack::worldTBody): the position's derivative w.r.t. every knot yaw that
/// moves it (ψ_0 … ψ_{segment.index + 1}; later ones do not), and what the rotation and offset need.
struct DriftPoseJacobian {
  KnotSegment segment;  ///< τ's: ∂c(τ)/∂c_index = 1 − weight, ∂c(τ)/∂c_index+1 = weight; likewise ψ(τ)
  Eigen::Matrix3Xd d_position_d_yaw;                          ///< 3 × (segment.index + 2) [m/rad]
  Eigen::Matrix3d odom_R_body = Eigen::Matrix3d::Identity();  ///< world_R_body = Rz(ψ(τ)) · odom_R_body
};

/// A gravity-aligned VIO's drift undone: the VIO's rotation turned by a smooth yaw ψ(t), its position increments
/// re-integrated under that yaw, plus a smooth offset c(t) (DriftKnots):
///   world_R_body(τ) = Rz(ψ(τ)) · odom_R_body(τ),
///   world_p_body(τ) = c(τ) + Σ_{0 < i, t_i ≤ τ} Rz(ψ(t_i)) (p_i − p_{i−1}) + Rz(ψ(τ)) (p(τ) − p_last),
/// with odometry samples (t_i, odom_T_body = (R_i, p_i)) and odom_T_body(τ) interpolated (odometryPoseAt). This is
/// the VIO's own error model (a drifting yaw bends every later increment, a velocity bias adds an offset), so a
/// yaw-rate bias needs no more than linear knots wherever the VIO's origin lies, and knots seconds apart hold.
/// A view: `odometry` must outlive it; knots are copied and integrated once.
class VioDriftTrack {
 public:
  VioDriftTrack(const std::vector<OdometrySample>& odometry, DriftKnots knots);

  /// K knots covering the odometry's span at `spacing` [s] > 0 reproducing odometry placed by the fixed
  /// `world_T_odom` (its yaw kept, roll and pitch dropped). kInvalidArgument for fewer than 2 odometry samples,
  /// a span or spacing that is not finite and > 0.
  static Result<DriftKnots> constantKnots(const std::vector<OdometrySample>& odometry, double spacing,
                                          const Eigen::Isometry3d& world_T_odom);
  /// Knots reproducing a run's keyframes (world_T_body; initialising ones skipped) at the knot times: each keyframe's
  /// world_T_body · odom_T_body(t)⁻¹ as (x, y, z, yaw), yaw unwrapped, interpolated to the knot times; ψ_k its
  /// yaw and c_k what puts the re-integrated track on it. kFailedPrecondition when no keyframe lies inside the
  /// odometry; constantKnots' errors.
  static Result<DriftKnots> knotsFromKeyframes(const std::vector<CorrectedPose>& keyframes,
                                               const std::vector<OdometrySample>& odometry, double spacing);

  const DriftKnots& knots() const { return knots_; }
  /// world_T_body(τ) and, when asked, its Jacobian; kFailedPrecondition outside the odometry's span.
  Result<Eigen::Isometry3d> worldTBody(double tau, DriftPoseJacobian* jacobian = nullptr) const;

 private:
  const std::vector<OdometrySample>& odometry_;
  DriftKnots knots_;
  // Per sample i: the re-integrated position Σ Rz(ψ(t_i)) Δp, its segment, and the running sums over the
  // sample's segment of (1 − a) e_z × v and a e_z × v (v the turned increment): ∂/∂ψ of that sum.
  std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> sum_, lower_, upper_;
  std::vector<int> segment_;
  // Per segment: the totals of the same two sums.
  std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> lower_total_, upper_total_;
};

/// Rz(yaw): the rotation by `yaw` [rad] about the z axis.
Eigen::Matrix3d rotationAboutZ(double yaw);

}  // namespace dualgraph
