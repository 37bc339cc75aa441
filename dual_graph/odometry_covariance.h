// SPDX-License-Identifier: MIT
// RelativeCovarianceStream: a VIO's absolute pose covariances turned into per-increment ones, sample by sample.
#pragma once

#include <optional>

#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/measurements.h"

namespace dualgraph {

/// Turns the absolute covariance a VIO reports with each pose (6×6, metric [t; θ] in m² and rad², a right
/// perturbation in the body frame: odom_T_body_true = odom_T_body · exp(ε)) into the covariance of the increment
/// from the previous sample, as the Localizer needs it. For a random-walk error with inc = odom_T_body(k−1)⁻¹ ·
/// odom_T_body(k): Σ_k = Ad(inc⁻¹) Σ_{k−1} Ad(inc⁻¹)ᵀ + Σ_rel, so Σ_rel = Σ_k − Ad(inc⁻¹) Σ_{k−1} Ad(inc⁻¹)ᵀ,
/// symmetrised, its eigenvalues raised to max(floor, 1e-11 · largest) (counted in `clamped`: absolute covariances
/// that shrink — a loop closure, a reset — are not a random walk; those that shrink by more than 1 % of the
/// largest variance are counted in `shrinks`). An all-zero absolute covariance is "unknown", as none. The first
/// sample, and a sample after one without a covariance, gets none (the Localizer's per-metre model covers that
/// increment). One instance per odometry stream; holds only the previous sample. Not thread-safe (one producer).
class RelativeCovarianceStream {
 public:
  explicit RelativeCovarianceStream(double floor = 1e-10) : floor_(floor) {}

  /// The relative covariance of `odom_T_body`'s increment from the previous `next` call's sample (none for the
  /// first, or when either has no absolute covariance); remembers this one. kNumericalError for a non-finite
  /// result (nothing remembered then); kInvalidArgument for a non-positive floor.
  Result<std::optional<Matrix6d>> next(const Eigen::Isometry3d& odom_T_body,
                                       const std::optional<Matrix6d>& absolute_covariance);
  /// Eigenvalues raised to the floor so far.
  int clamped() const { return clamped_; }
  /// Samples whose absolute covariance shrank from the previous one's propagated by more than 1 % of its largest
  /// variance (a reset or a loop closure, not rounding).
  int shrinks() const { return shrinks_; }
  /// Forgets the previous sample (after a gap in the odometry the next increment has no covariance).
  void reset() { previous_.reset(); }

 private:
  struct Previous {
    Eigen::Isometry3d odom_T_body;
    Matrix6d absolute;
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  double floor_;
  std::optional<Previous> previous_;
  int clamped_ = 0;
  int shrinks_ = 0;
  static constexpr double kShrinkFraction = 0.01;
};

}  // namespace dualgraph
