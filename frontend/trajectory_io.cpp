// SPDX-License-Identifier: MIT
#include "frontend/trajectory_io.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "dual_graph/measurements.h"

namespace dualgraph {

Status writeTum(const std::string& path, const std::vector<std::pair<double, Eigen::Isometry3d>>& poses) {
  for (size_t i = 0; i < poses.size(); ++i) {
    const std::string what = path + ": pose " + std::to_string(i);
    if (!std::isfinite(poses[i].first)) return Status(StatusCode::kInvalidArgument, what + ": time stamp is not finite");
    DG_RETURN_IF_ERROR(checkRigidTransform(poses[i].second, what));
  }
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary);
    if (!out) return Status(StatusCode::kIoError, temporary + ": cannot open for writing");
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "# t tx ty tz qx qy qz qw\n";
    for (const auto& [t, pose] : poses) {
      Eigen::Quaterniond q(pose.linear());
      if (q.w() < 0.0) q.coeffs() = -q.coeffs();
      const Eigen::Vector3d p = pose.translation();
      out << t << ' ' << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z()
          << ' ' << q.w() << '\n';
    }
    out.close();
    if (!out) {
      std::remove(temporary.c_str());
      return Status(StatusCode::kIoError, path + ": write failed");
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    return Status(StatusCode::kIoError, path + ": cannot rename the temporary file into place");
  }
  return Status();
}

}  // namespace dualgraph
