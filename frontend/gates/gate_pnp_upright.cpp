// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/gate_pnp_upright.h"

#include <Eigen/Cholesky>

namespace dualgraph::pnp_detail {
namespace {

/// The whitened cost and, when `J_all` is given, the whitened residuals' Jacobian; false when a corner is behind.
bool whitened(const Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const GateCornerPixels& pixels,
              const CameraModel& camera, double pixel_sigma, const UprightPrior& prior,
              Eigen::Matrix<double, 10, 1>& r_all, Eigen::Matrix<double, 10, 6>* J_all) {
  Vector8d r;
  if (!residuals(camera_T_gate, p_gate, pixels, camera, r)) return false;
  Eigen::Vector2d c;
  Eigen::Matrix<double, 2, 6> J_c;
  uprightResiduals(camera_T_gate, prior, c, J_c);
  r_all << r / pixel_sigma, c / prior.sigma;
  if (J_all != nullptr) {
    Matrix86d J;
    if (!jacobian(camera_T_gate, p_gate, camera, J)) return false;
    *J_all << J / pixel_sigma, J_c / prior.sigma;
  }
  return true;
}

}  // namespace

void uprightResiduals(const Eigen::Isometry3d& camera_T_gate, const UprightPrior& prior, Eigen::Vector2d& c,
                      Eigen::Matrix<double, 2, 6>& J_c) {
  // up in the gate frame; under R·exp(θ) it becomes (I − [θ]×)·v = v + [v]×·θ.
  const Eigen::Vector3d v = camera_T_gate.linear().transpose() * prior.up;
  c = v.head<2>();
  J_c.setZero();
  J_c.rightCols<3>() = skew(v).topRows<2>();
}

double refineUpright(Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const GateCornerPixels& pixels,
                     const CameraModel& camera, double pixel_sigma, const UprightPrior& prior, int iterations) {
  Eigen::Matrix<double, 10, 1> r;
  Eigen::Matrix<double, 10, 6> J;
  if (!whitened(camera_T_gate, p_gate, pixels, camera, pixel_sigma, prior, r, &J)) return -1.0;
  for (int it = 0; it < iterations; ++it) {
    const Vector6d step = -(J.transpose() * J).ldlt().solve(J.transpose() * r);
    if (!step.allFinite()) break;
    bool improved = false;
    for (double scale = 1.0; scale > 1e-3 && !improved; scale *= 0.5) {
      const Eigen::Isometry3d candidate = se3BoxPlus(camera_T_gate, scale * step);
      Eigen::Matrix<double, 10, 1> r_candidate;
      Eigen::Matrix<double, 10, 6> J_candidate;
      if (whitened(candidate, p_gate, pixels, camera, pixel_sigma, prior, r_candidate, &J_candidate) &&
          r_candidate.squaredNorm() <= r.squaredNorm()) {
        camera_T_gate = candidate;
        r = r_candidate;
        J = J_candidate;
        improved = true;
      }
    }
    if (!improved || step.norm() < 1e-12) break;
  }
  return r.squaredNorm();
}

bool uprightCovariance(const Eigen::Isometry3d& camera_T_gate, const Corners3& p_gate, const CameraModel& camera,
                       double pixel_sigma, const UprightPrior& prior, Matrix6d& covariance) {
  Matrix86d J;
  if (!jacobian(camera_T_gate, p_gate, camera, J)) return false;
  Eigen::Vector2d c;
  Eigen::Matrix<double, 2, 6> J_c;
  uprightResiduals(camera_T_gate, prior, c, J_c);
  const Matrix6d information = J.transpose() * J / (pixel_sigma * pixel_sigma) +
                               J_c.transpose() * J_c / (prior.sigma * prior.sigma);
  covariance = information.inverse();
  covariance = 0.5 * (covariance + covariance.transpose()).eval();
  return covariance.allFinite();
}

}  // namespace dualgraph::pnp_detail
