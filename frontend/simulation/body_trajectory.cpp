// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/simulation/body_trajectory.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {

Result<SampledTrajectory> SampledTrajectory::create(std::vector<std::pair<double, Eigen::Isometry3d>> samples) {
  if (samples.size() < 2) {
    return Status(StatusCode::kInvalidArgument, "recorded trajectory: needs at least two samples, has " +
                                                    std::to_string(samples.size()));
  }
  for (size_t i = 0; i < samples.size(); ++i) {
    const auto& [t, pose] = samples[i];
    if (!std::isfinite(t) || !pose.matrix().allFinite()) {
      return Status(StatusCode::kInvalidArgument, "recorded trajectory: sample " + std::to_string(i) + " is not finite");
    }
    if (i > 0 && !(t > samples[i - 1].first)) {
      return Status(StatusCode::kInvalidArgument,
                    "recorded trajectory: sample " + std::to_string(i) + " does not follow the previous in time");
    }
  }
  return SampledTrajectory(std::move(samples));
}

Eigen::Isometry3d SampledTrajectory::worldTBody(double t) const {
  if (!(t > samples_.front().first)) return samples_.front().second;
  if (!(t < samples_.back().first)) return samples_.back().second;
  const auto after = std::upper_bound(samples_.begin(), samples_.end(), t,
                                      [](double value, const auto& sample) { return value < sample.first; });
  const auto before = after - 1;
  const double s = (t - before->first) / (after->first - before->first);
  const Eigen::Quaterniond q0(before->second.linear());
  const Eigen::Quaterniond q1(after->second.linear());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q0.slerp(s, q1).normalized().toRotationMatrix();
  pose.translation() = (1.0 - s) * before->second.translation() + s * after->second.translation();
  return pose;
}

double bodyAngularRate(const BodyTrajectory& trajectory, double t) {
  constexpr double kHalfInterval = 1e-3;  // [s]
  const double before = std::clamp(t - kHalfInterval, trajectory.begin(), trajectory.end());
  const double after = std::clamp(t + kHalfInterval, trajectory.begin(), trajectory.end());
  if (!(after > before)) return 0.0;
  const Eigen::Matrix3d turn = trajectory.worldTBody(before).linear().transpose() * trajectory.worldTBody(after).linear();
  return so3Log(turn).norm() / (after - before);
}

}  // namespace dualgraph
