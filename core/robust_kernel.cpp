// SPDX-License-Identifier: MIT
#include "dualgraph/core/robust_kernel.h"

#include <cmath>
#include <cstdlib>

namespace dualgraph {

Eigen::Vector3d HuberKernel::robustify(double s) const {
  const double d2 = delta_ * delta_;
  if (s <= d2) return Eigen::Vector3d(s, 1.0, 0.0);
  const double r = std::sqrt(s);
  return Eigen::Vector3d(2.0 * delta_ * r - d2, delta_ / r, -0.5 * delta_ / (r * s));
}

Eigen::Vector3d CauchyKernel::robustify(double s) const {
  const double d2 = delta_ * delta_;
  const double aux = 1.0 / (1.0 + s / d2);
  return Eigen::Vector3d(d2 * std::log1p(s / d2), aux, -aux * aux / d2);
}

Eigen::Vector3d TukeyKernel::robustify(double s) const {
  const double d2 = delta_ * delta_;
  if (s > d2) return Eigen::Vector3d(d2 / 3.0, 0.0, 0.0);
  const double a = 1.0 - s / d2;
  return Eigen::Vector3d(d2 / 3.0 * (1.0 - a * a * a), a * a, -2.0 * a / d2);
}

Eigen::Vector3d DcsKernel::robustify(double s) const {
  const double w = std::min(1.0, 2.0 * delta_ / (delta_ + s));
  return Eigen::Vector3d(w * w * s, w * w, 0.0);
}

Result<std::shared_ptr<const RobustKernel>> makeRobustKernel(const std::string& spec) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos) {
    return Status(StatusCode::kInvalidArgument,
                  "robust kernel '" + spec + "' must be NAME:DELTA, e.g. huber:1.0");
  }
  const std::string name = spec.substr(0, colon);
  const std::string value = spec.substr(colon + 1);
  char* end = nullptr;
  const double delta = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !std::isfinite(delta) || delta <= 0.0) {
    return Status(StatusCode::kInvalidArgument,
                  "robust kernel '" + spec + "': DELTA must be a finite positive number");
  }
  if (name == "huber") return std::shared_ptr<const RobustKernel>(new HuberKernel(delta));
  if (name == "cauchy") return std::shared_ptr<const RobustKernel>(new CauchyKernel(delta));
  if (name == "tukey") return std::shared_ptr<const RobustKernel>(new TukeyKernel(delta));
  if (name == "dcs") return std::shared_ptr<const RobustKernel>(new DcsKernel(delta));
  return Status(StatusCode::kInvalidArgument,
                "unknown robust kernel '" + name + "' (huber, cauchy, tukey, dcs)");
}

}  // namespace dualgraph
