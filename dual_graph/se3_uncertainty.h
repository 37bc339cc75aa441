// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Geometry>

#include "core/status.h"
#include "types/se3_math.h"

namespace dualgraph {

/// Covariance of a_T_c = a_T_b · b_T_c when both factors carry independent right perturbations
/// (metric [t; θ]): a_T_b·exp(ε₁)·b_T_c·exp(ε₂) = a_T_c·exp(Ad(b_T_c⁻¹) ε₁ + ε₂), so
/// Σ_ac = Ad(c_T_b) Σ_ab Ad(c_T_b)ᵀ + Σ_bc (first order).
Matrix6d composeRelativeCovariance(const Matrix6d& covariance_ab, const Eigen::Isometry3d& b_T_c,
                                   const Matrix6d& covariance_bc);

/// The pose a fraction `alpha` ∈ [0, 1] of the way from `a` to `b` along the geodesic:
/// a · exp(alpha · log(a⁻¹ b)).
Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double alpha);

/// Straight-line distance [m] and rotation angle [rad] of a relative motion.
double translationOf(const Eigen::Isometry3d& increment);
double rotationAngleOf(const Eigen::Isometry3d& increment);

/// The per-metre odometry model: σ_t·√d and σ_r·√d with d = max(|translation|, min_distance), i.e.
/// diag(σ_t² d I₃, σ_r² d I₃), metric [t; θ].
Matrix6d odometryModelCovariance(const Eigen::Isometry3d& increment, double sigma_t, double sigma_r,
                                 double min_distance);

/// Ω = Σ⁻¹, symmetrised; kNotPositiveDefinite when Σ (or Ω) is not usable.
Result<Eigen::MatrixXd> informationFromCovariance(const Eigen::MatrixXd& covariance, const std::string& what);
/// Its fast path for a 6×6 or 3×3 (N = 6, 3), without heap allocation and without a message to build: true
/// with Ω in `information` (equal to informationFromCovariance's, bit for bit) when Σ is well conditioned
/// (inverseOfWellConditionedCovariance, measurements.h), the case of every covariance of the hot paths;
/// false when it cannot decide, and informationFromCovariance then gives the result or the error.
template <int N>
bool informationFromWellConditionedCovariance(const Eigen::Matrix<double, N, N>& covariance,
                                              Eigen::Matrix<double, N, N>& information);
/// Ω = Σ⁻¹ of a 6×6 or 3×3 Σ into `information`: that fast path when it decides, else informationFromCovariance,
/// whose error message starts with `what()`. `what` is called only then, so the hot paths build no message.
template <int N, typename What>
Status informationFromFixedCovariance(const Eigen::Matrix<double, N, N>& covariance, const What& what,
                                      Eigen::Matrix<double, N, N>& information) {
  if (informationFromWellConditionedCovariance<N>(covariance, information)) return Status();
  Result<Eigen::MatrixXd> checked = informationFromCovariance(covariance, what());
  if (!checked.ok()) return checked.status();
  information = *checked;
  return Status();
}

}  // namespace dualgraph
