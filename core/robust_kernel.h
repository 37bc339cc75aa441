// SPDX-License-Identifier: MIT
// The robust kernels (Huber, Cauchy, Tukey, DCS) and their parser from specs like "huber:1.5".
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// A robust cost ρ applied to an edge's squared Mahalanobis error s = eᵀΩe (g2o's convention).
/// `robustify(s)` returns [ρ(s), ρ'(s), ρ''(s)]; the optimiser weights the edge's Ω by ρ'(s)
/// (iteratively reweighted least squares), and the robust χ² of the edge is ρ(s).
/// `delta` is the kernel width in units of the whitened error (not squared).
class RobustKernel {
 public:
  explicit RobustKernel(double delta) : delta_(delta) {}
  virtual ~RobustKernel() = default;
  virtual Eigen::Vector3d robustify(double squared_error) const = 0;
  virtual const char* name() const = 0;
  double delta() const { return delta_; }

 protected:
  double delta_;
};

/// Huber: quadratic for √s ≤ δ, linear beyond: ρ(s) = 2δ√s − δ².
class HuberKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  Eigen::Vector3d robustify(double squared_error) const override;
  const char* name() const override { return "huber"; }
};

/// Cauchy: ρ(s) = δ² log(1 + s/δ²).
class CauchyKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  Eigen::Vector3d robustify(double squared_error) const override;
  const char* name() const override { return "cauchy"; }
};

/// Tukey biweight: ρ(s) = δ²/3 (1 − (1 − s/δ²)³) for s ≤ δ², δ²/3 beyond (outliers get zero weight).
class TukeyKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  Eigen::Vector3d robustify(double squared_error) const override;
  const char* name() const override { return "tukey"; }
};

/// Dynamic Covariance Scaling (Agarwal et al., ICRA 2013) with Φ = δ: the error is scaled by
/// w = min(1, 2Φ/(Φ + s)); ρ(s) = w² s and the IRLS weight is w².
class DcsKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  Eigen::Vector3d robustify(double squared_error) const override;
  const char* name() const override { return "dcs"; }
};

/// Parses "huber:1.5", "cauchy:1", "tukey:4.685", "dcs:1"; δ must be finite and positive.
Result<std::shared_ptr<const RobustKernel>> makeRobustKernel(const std::string& spec);

}  // namespace dualgraph
