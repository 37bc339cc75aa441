// SPDX-License-Identifier: MIT
// SE(3) covariance maths (composition, Σ → Ω) and checks of covariances and rigid transforms.
#pragma once

#include <Eigen/Geometry>

#include "dualgraph/core/status.h"
#include "dualgraph/types/se3_math.h"

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
/// True when `increment` moved at least `distance` [m] or turned at least `angle` [rad] (a keyframe's, a node's test).
inline bool incrementExceeds(const Eigen::Isometry3d& increment, double distance, double angle) {
  return translationOf(increment) >= distance || rotationAngleOf(increment) >= angle;
}

/// OK when `m` is finite, symmetric to 1e-9 relative and positive definite (Cholesky succeeds and the
/// smallest eigenvalue is above 1e-12 of the largest); otherwise kNotPositiveDefinite / kInvalidArgument
/// with a message starting with `what`.
Status checkCovariance(const Eigen::MatrixXd& m, const std::string& what);
/// The same; when the check itself inverted the symmetric part of `m` (6×6 and 3×3, decided by the norm bound),
/// that inverse is left in `inverse` (else it is emptied), so a caller that needs it does not factorise twice.
Status checkCovariance(const Eigen::MatrixXd& m, const std::string& what, Eigen::MatrixXd* inverse);
/// checkCovariance's fast path for a 6×6 or 3×3 (N = 6, 3), without heap allocation: true when the
/// symmetric part S of `m` passes checkCovariance by the norm bound ‖S‖∞·‖S⁻¹‖∞ < 1e11 (the answer for
/// every covariance of the hot paths), with S⁻¹ in `inverse`; false when that test does not decide (a
/// NaN, an indefinite or ill-conditioned S): checkCovariance then gives the verdict and its message.
template <int N>
bool inverseOfWellConditionedCovariance(const Eigen::Matrix<double, N, N>& m, Eigen::Matrix<double, N, N>& inverse);
/// checkCovariance's OK for a 6×6 or 3×3 without heap or message: true when `m` is finite, symmetric as
/// checkCovariance judges it and well conditioned by the norm bound (then checkCovariance is OK); false when this
/// does not decide — ask checkCovariance for the verdict and its message. For per-sample checks.
template <int N>
bool surelyValidCovariance(const Eigen::Matrix<double, N, N>& m);
/// kInvalidArgument when the pose has a non-finite entry or a rotation that is not a rotation.
Status checkRigidTransform(const Eigen::Isometry3d& pose, const std::string& what);
/// checkRigidTransform's OK, without a message to build.
bool isRigidTransform(const Eigen::Isometry3d& pose);


/// Ω = Σ⁻¹, symmetrised; kNotPositiveDefinite when Σ (or Ω) is not usable.
Result<Eigen::MatrixXd> informationFromCovariance(const Eigen::MatrixXd& covariance, const std::string& what);
/// Its fast path for a 6×6 or 3×3 (N = 6, 3), without heap allocation and without a message to build: true
/// with Ω in `information` (equal to informationFromCovariance's, bit for bit) when Σ is well conditioned
/// (inverseOfWellConditionedCovariance above), the case of every covariance of the hot paths;
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

/// Ω_g2o = informationMetricToG2o(Σ⁻¹) for a metric [t; θ] covariance; kNotPositiveDefinite when Σ is unusable.
Result<Matrix6d> poseInformationFromMetricCovariance(const Matrix6d& covariance_metric, const std::string& what);
/// Ω = Σ⁻¹ for a 3×3 position covariance.
Result<Eigen::Matrix3d> pointInformationFromCovariance(const Eigen::Matrix3d& covariance, const std::string& what);

}  // namespace dualgraph
