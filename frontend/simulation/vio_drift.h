// SPDX-License-Identifier: MIT
// A seeded model of VIO drift (yaw, velocity bias, scale) with its reported covariance.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "dualgraph/core/status.h"
#include "dualgraph/frontend/io/odometry_io.h"

namespace dualgraph {

/// A seeded model of visual-inertial odometry drift, gravity-aligned like a real VIO: roll and pitch
/// stay observable (only white noise), yaw and position drift.
///
/// With the true poses world_T_body(k) at times t_k and Δt = t_k − t_{k−1}, the VIO frame `odom`
/// coincides with `world` at k = 0 (the paper's protocol: the world frame is known) and
///   ψ_k   = ψ_{k−1} + (b_ψ + n_ψ) Δt,                 n_ψ ~ N(0, σ_ψ² / Δt)   (yaw error) [rad]
///   b_v,k = b_v,k−1 + N(0, σ_bv² Δt I₃)                                       (velocity bias, world) [m/s]
///   p_k   = p_{k−1} + Rz(ψ_k) (1 + λ) (p_true,k − p_true,k−1) + b_v,k Δt       [m]
///   odom_T_body(k) = (Rz(ψ_k) R_true,k · exp(n_R),  p_k + n_p),  n_R, n_p white.
/// Per flight (from the seed): the yaw-rate bias b_ψ = ±yaw_rate_bias · m (random sign), the initial
/// velocity bias b_v,0 of norm velocity_bias · m in a random horizontal direction plus a vertical
/// component ±vertical_velocity_bias · m, and the scale error λ ~ N(0, scale_error_sigma²), with
/// m ~ U[1 − bias_spread, 1 + bias_spread]; with scale_error_bias > 0 (a monocular VIO's scale), λ also gets
/// ±scale_error_bias · m (random sign, drawn after the others so that 0 keeps a flight's bits).
///
/// Reported covariance (the 21 TUM columns, frontend/io/FORMATS.md): the absolute covariance of odom_T_body,
/// metric [t; θ], a right perturbation in the body frame, propagated as a random walk
/// Σ_k = Ad(inc⁻¹) Σ_{k−1} Ad(inc⁻¹)ᵀ + Q Δt with Q = diag(q_t, q_t, q_t, q_r, q_r, q_r):
///   q_t = (velocity_bias · (1 + bias_spread))² + (vertical_velocity_bias · (1 + bias_spread))²
///         + (scale_error_sigma · speed)² + σ_bv² · t_k     [m²/s], with `speed` the current true
///         speed (σ_bv² t_k: the variance the velocity bias's random walk has reached);
///   q_r = (yaw_rate_bias · (1 + bias_spread))² + σ_ψ²   [rad²/s],
/// so that `toRelativeCovariances` gives back Q Δt: an honest bound on the drift between keyframes
/// (biases treated as a random walk with a 1 s correlation time), not a tuned number. The scale bias is left out
/// of it, as a monocular VIO does not know its scale error.
struct VioDriftParams {
  double yaw_rate_bias = 0.002;             ///< [rad/s] magnitude of b_ψ (≈ 11° per 95 s)
  double yaw_random_walk = 0.0005;          ///< σ_ψ [rad/√s]
  double velocity_bias = 0.015;             ///< [m/s], horizontal norm of b_v,0
  double vertical_velocity_bias = 0.004;    ///< [m/s]
  double velocity_bias_random_walk = 0.002; ///< σ_bv [m/s/√s] per axis
  double bias_spread = 0.25;                ///< m ∈ [1 − spread, 1 + spread], in [0, 1)
  double scale_error_sigma = 0.005;         ///< σ of λ (dimensionless)
  double scale_error_bias = 0.0;            ///< magnitude of λ's bias (dimensionless; 0.075: a monocular VIO)
  double position_noise = 0.001;            ///< white n_p per axis [m]
  double rotation_noise = 0.0005;           ///< white n_R per axis [rad]
};

/// kInvalidArgument naming the field unless every parameter is finite and ≥ 0 and bias_spread < 1.
Status validateVioDriftParams(const VioDriftParams& params);

/// The drifting odometry of a flight given by true poses `world_T_body` at increasing times `t` [s]
/// (same length ≥ 2), with one absolute covariance per sample (OdometryLog). Deterministic for a seed.
/// kInvalidArgument for invalid params, mismatched or short inputs, non-increasing times or
/// non-finite poses.
Result<OdometryLog> simulateVio(const std::vector<double>& t,
                                const std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>>& world_T_body,
                                const VioDriftParams& params, std::uint64_t seed);

}  // namespace dualgraph
