// SPDX-License-Identifier: MIT
// Internal to gate_pnp.cpp: the gate pose under a prior that it stands upright (its z axis along gravity).
#pragma once
// Not installed, not part of the public API.

#include "dualgraph/frontend/gates/gate_pnp_posterior.h"

namespace dualgraph::pnp_detail {

/// The prior "the gate's z axis points along `up` (a unit vector in the camera frame: gravity's opposite, from the
/// VIO's attitude)" with standard deviation `sigma` [rad] on each of the two tilts across it.
struct UprightPrior {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double sigma = 0.0;  ///< [rad]
};

/// The two tilt residuals [rad] of camera_T_gate against the prior (the x and y components of `up` in the gate
/// frame, zero when upright) and their Jacobian with respect to the right perturbation ε = [ε_t; ε_θ] of
/// se3BoxPlus (translation columns zero).
void uprightResiduals(const Eigen::Isometry3d& camera_T_gate, const UprightPrior& prior, Eigen::Vector2d& c,
                      Eigen::Matrix<double, 2, 6>& J_c);

/// Maximum a posteriori refinement of `camera_T_gate` (Gauss–Newton on the pixel error / pixel_sigma and the tilt
/// residuals / prior.sigma, halving steps that do not lower the cost). Returns the cost (sum of both squared
/// whitened residuals), or −1 when a corner falls behind the camera.
double refineUpright(Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const GateCornerPixels& pixels,
                     const CameraModel& camera, double pixel_sigma, const UprightPrior& prior, int iterations);

/// The posterior covariance at the refined pose, metric [t; θ] in se3BoxPlus's chart: (JᵀJ/σ² + J_cᵀJ_c/σ_c²)⁻¹;
/// false when a corner is behind the camera.
bool uprightCovariance(const Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const CameraModel& camera,
                       double pixel_sigma, const UprightPrior& prior, Matrix6d& covariance);

}  // namespace dualgraph::pnp_detail
