// SPDX-License-Identifier: MIT
#include "dualgraph/types/g2o_text.h"

#include <cmath>

#include "dualgraph/types/se3_math.h"

namespace dualgraph {

void writeNumbers(std::ostream& out, const double* values, int count) {
  const StreamPrecisionGuard precision(out, kG2oWritePrecision);
  for (int k = 0; k < count; ++k) {
    if (k > 0) out << ' ';
    out << values[k];
  }
}

Eigen::Matrix3d G2oPoseText::rotationFrom(const std::array<double, 4>& xyzw) const {
  Eigen::Quaterniond q = quatFromXyzw(xyzw[0], xyzw[1], xyzw[2], xyzw[3]);
  const bool as_written = reading_ == QuaternionReading::kAsWrittenNearUnit &&
                          std::fabs(q.norm() - 1.0) <= kQuaternionAsWrittenTolerance;
  if (!as_written) q.normalize();
  return q.toRotationMatrix();
}

Status G2oPoseText::read(TokenReader& in, Eigen::Isometry3d& pose) {
  Eigen::Vector3d translation;
  DG_RETURN_IF_ERROR(in.readDouble(translation.x(), "x"));
  DG_RETURN_IF_ERROR(in.readDouble(translation.y(), "y"));
  DG_RETURN_IF_ERROR(in.readDouble(translation.z(), "z"));
  std::array<double, 4> xyzw{};
  DG_RETURN_IF_ERROR(in.readDouble(xyzw[0], "qx"));
  DG_RETURN_IF_ERROR(in.readDouble(xyzw[1], "qy"));
  DG_RETURN_IF_ERROR(in.readDouble(xyzw[2], "qz"));
  DG_RETURN_IF_ERROR(in.readDouble(xyzw[3], "qw"));
  const double norm = Eigen::Vector4d(xyzw[0], xyzw[1], xyzw[2], xyzw[3]).norm();
  if (!std::isfinite(norm)) return in.error("quaternion (qx qy qz qw) has a non-finite norm");
  if (norm < kMinQuaternionNorm) return in.error("zero-norm quaternion (qx qy qz qw)");
  pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotationFrom(xyzw);
  pose.translation() = translation;
  read_xyzw_ = xyzw;
  has_read_ = true;
  return Status();
}

void G2oPoseText::write(std::ostream& out, const Eigen::Isometry3d& pose) const {
  std::array<double, 7> values{};
  values[0] = pose.translation().x();
  values[1] = pose.translation().y();
  values[2] = pose.translation().z();
  if (has_read_ && rotationFrom(read_xyzw_) == pose.linear()) {
    for (int k = 0; k < 4; ++k) values[3 + k] = read_xyzw_[k];
  } else {
    // g2o's toVectorQT: the normalised quaternion of the rotation block, sign as extracted.
    const Eigen::Quaterniond q = quatFromRotation(pose.linear());
    values[3] = q.x();
    values[4] = q.y();
    values[5] = q.z();
    values[6] = q.w();
  }
  writeNumbers(out, values.data(), 7);
}

}  // namespace dualgraph
