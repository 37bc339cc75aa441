// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/trajectory_io.h"

#include <cmath>
#include <limits>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
void writeTumRow(std::ostream& out, double t, const Eigen::Isometry3d& pose) {
  Eigen::Quaterniond q(pose.linear());
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d p = pose.translation();
  out << t << ' ' << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' '
      << q.w();
}

Status writeTum(const std::string& path, const StampedPoses& poses) {
  for (size_t i = 0; i < poses.size(); ++i) {
    const std::string what = path + ": pose " + std::to_string(i);
    if (!std::isfinite(poses[i].first)) return Status(StatusCode::kInvalidArgument, what + ": time stamp is not finite");
    DG_RETURN_IF_ERROR(checkRigidTransform(poses[i].second, what));
  }
  return writeFileAtomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "# t tx ty tz qx qy qz qw\n";
    for (const auto& [t, pose] : poses) {
      writeTumRow(out, t, pose);
      out << '\n';
    }
    return Status();
  });
}

Status writeTumOdometry(const std::string& path, const OdometryLog& log) {
  const bool with_covariance = !log.absolute_covariances.empty();
  if (with_covariance && log.absolute_covariances.size() != log.samples.size()) {
    return Status(StatusCode::kInvalidArgument, path + ": " + std::to_string(log.absolute_covariances.size()) +
                                                    " covariances for " + std::to_string(log.samples.size()) + " samples");
  }
  for (size_t i = 0; i < log.samples.size(); ++i) {
    const std::string what = path + ": sample " + std::to_string(i);
    if (!std::isfinite(log.samples[i].t)) return Status(StatusCode::kInvalidArgument, what + ": time stamp is not finite");
    if (i > 0 && !(log.samples[i].t > log.samples[i - 1].t)) {
      return Status(StatusCode::kInvalidArgument, what + ": time stamp does not increase");
    }
    DG_RETURN_IF_ERROR(checkRigidTransform(log.samples[i].odom_T_body, what));
    if (with_covariance && !log.absolute_covariances[i].allFinite()) {
      return Status(StatusCode::kInvalidArgument, what + ": covariance is not finite");
    }
  }
  return writeFileAtomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "# t tx ty tz qx qy qz qw" << (with_covariance ? " cov_00 cov_01 ... cov_55 (upper triangle, [t; theta])" : "")
        << '\n';
    for (size_t i = 0; i < log.samples.size(); ++i) {
      writeTumRow(out, log.samples[i].t, log.samples[i].odom_T_body);
      if (with_covariance) {
        for (int r = 0; r < 6; ++r) {
          for (int c = r; c < 6; ++c) out << ' ' << log.absolute_covariances[i](r, c);
        }
      }
      out << '\n';
    }
    return Status();
  });
}

StampedPoses stampedPosesFromSamples(const std::vector<OdometrySample>& samples) {
  StampedPoses poses;
  poses.reserve(samples.size());
  for (const OdometrySample& sample : samples) poses.emplace_back(sample.t, sample.odom_T_body);
  return poses;
}

}  // namespace dualgraph
