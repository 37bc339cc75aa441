// SPDX-License-Identifier: MIT
// Internal to gate_pnp.cpp: the corners' reprojection residuals, the tilt-grid posterior and the two-mode moment.
#pragma once
// Internal to frontend/gates/gate_pnp.cpp: the reprojection residuals and the tilt-grid posterior
// covariance of a gate's pose. Not installed, not part of the public API.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/corner_detection.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph::pnp_detail {

using Matrix86d = Eigen::Matrix<double, 8, 6>;
using Vector8d = Eigen::Matrix<double, 8, 1>;
using Corners3 = Eigen::Matrix<double, 3, 4>;

/// Reprojection residuals project(camera_T_gate · p_gate) − pixel [px], stacked per corner; false if
/// a corner is not in front of the camera.
bool residuals(const Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const GateCornerPixels& pixels,
               const CameraModel& camera, Vector8d& r);

/// J = ∂r/∂ε of se3BoxPlus(camera_T_gate, ε) (ε = [ε_t; ε_θ], m and rad) [px per m, px per rad], analytic
/// through CameraModel::project's ∂pixel/∂p; false if a corner is not in front of the camera.
bool jacobian(const Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const CameraModel& camera,
              Matrix86d& J_r_eps);

/// What tiltPosteriorCovariance needs to know about the view.
struct TiltPosteriorInput {
  Eigen::Isometry3d camera_T_gate;  ///< the maximum-likelihood pose the moment is taken about
  Matrix86d jacobian;               ///< ∂pixels/∂ε at camera_T_gate [px per m, px per rad]
  double ssr = 0.0;                 ///< its sum of squared residuals [px²]
  const Eigen::Isometry3d* other_tilt = nullptr;  ///< the other (mirrored) tilt's pose, or null
  double other_ssr = 0.0;                         ///< its sum of squared residuals [px²]
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Second moment E[ε εᵀ] of the pose posterior about `camera_T_gate` (ε its right perturbation in the
/// chart of se3BoxPlus, [m, rad]) under isotropic pixel noise σ and a flat prior, integrated over the
/// gate's tilt (the two rotations about axes across the line of sight: the directions a small or far
/// square's image hardly fixes and whose likelihood is not Gaussian — flat-topped near a frontal view,
/// two-peaked with the mirrored tilt). The tilt is integrated on an 11 × 11 lattice (±4 Laplace standard
/// deviations, the second axis sheared along the first's regression; stretched to ≤ 41 columns reaching
/// the other tilt when that one's likelihood ratio is above e⁻³⁰); the other four coordinates
/// (translation, roll about the line of sight) are Gaussian given the tilt: their mean re-fitted by
/// Gauss–Newton at each node, their covariance that node's Laplace one. False when no node has a finite
/// weight.
bool tiltPosteriorCovariance(const TiltPosteriorInput& input, const Corners3& p_gate, const GateCornerPixels& pixels,
                             const CameraModel& camera, double pixel_sigma, Matrix6d& covariance);

/// Two poses explain the pixels: the second moment of the two-mode posterior about `centre`,
/// Σ = w_c Σ_c + w_o (Σ_o + δ δᵀ), each mode's Σ its Laplace covariance (Σ_o moved into the centre's chart: right
/// perturbation in the gate frame), weights ∝ each mode's posterior mass (peak likelihood exp(−SSR / 2σ²) times its
/// volume √det Σ) and δ the other mode's offset. Instead of Σ_c alone, which is far too confident when the wrong
/// mode wins (measured NEES ≈ 29 on near-frontal views). Covariances in m² and rad², SSRs in px², sigma2 the pixel
/// variance [px²]. False when it is not finite.
bool twoModeMoment(const Eigen::Isometry3d& centre, const Matrix6d& centre_covariance, double centre_ssr,
                   const Eigen::Isometry3d& other, const Matrix6d& other_covariance, double other_ssr, double sigma2,
                   Matrix6d& moment);

}  // namespace dualgraph::pnp_detail
