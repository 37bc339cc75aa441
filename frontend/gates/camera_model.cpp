// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/camera_model.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
namespace {

Status invalid(const std::string& field, const std::string& why) {
  return Status(StatusCode::kInvalidArgument, "camera: field '" + field + "': " + why);
}

// OpenCV's fisheye solver marks points it cannot invert with −1e6; anything that far out is not a
// usable normalised coordinate (|x/z| = 1e5 is 89.9994° off axis).
constexpr double kFisheyeFailureMarker = -1e5;

}  // namespace

const char* distortionModelName(CameraModel::Distortion model) {
  return model == CameraModel::Distortion::kEquidistant ? "equidistant" : "radtan";
}

CameraModel CameraModel::pinhole(double fx, double fy, double cx, double cy, int width, int height,
                                 Distortion model) {
  CameraModel camera;
  camera.K << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  camera.model = model;
  camera.distortion = Eigen::VectorXd::Zero(model == Distortion::kRadTan ? 5 : 4);
  camera.width = width;
  camera.height = height;
  return camera;
}

namespace {

// The distorted normalised point of `xy` under `camera`'s lens model and, when `d_xy` is non-null,
// ∂distorted/∂xy. The one implementation behind distortNormalized and both project overloads.
Eigen::Vector2d distort(const CameraModel& camera, const Eigen::Vector2d& xy, Eigen::Matrix2d* d_xy) {
  const double x = xy.x();
  const double y = xy.y();
  const double r2 = x * x + y * y;
  const Eigen::VectorXd& distortion = camera.distortion;
  const auto k = [&distortion](int i) { return i < distortion.size() ? distortion[i] : 0.0; };
  if (camera.model == CameraModel::Distortion::kRadTan) {
    const double radial = 1.0 + r2 * (k(0) + r2 * (k(1) + r2 * k(4)));
    const double p1 = k(2);
    const double p2 = k(3);
    if (d_xy != nullptr) {
      const double d_radial_d_r2 = k(0) + r2 * (2.0 * k(1) + r2 * 3.0 * k(4));
      const double cross = 2.0 * x * y * d_radial_d_r2 + 2.0 * p1 * x + 2.0 * p2 * y;  // ∂x_d/∂y = ∂y_d/∂x
      *d_xy << radial + 2.0 * x * x * d_radial_d_r2 + 2.0 * p1 * y + 6.0 * p2 * x, cross,
          cross, radial + 2.0 * y * y * d_radial_d_r2 + 6.0 * p1 * y + 2.0 * p2 * x;
    }
    return {x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
            y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
  }
  const double r = std::sqrt(r2);
  if (r < 1e-12) {
    // θ_d / r = 1 + (k1 − 1/3) r² + O(r⁴) → 1 on the axis, and its r-derivative → 0: the Jacobian is I
    // (the neglected terms are below 1e-24).
    if (d_xy != nullptr) d_xy->setIdentity();
    return xy;
  }
  const double theta = std::atan(r);
  const double t2 = theta * theta;
  const double theta_d = theta * (1.0 + t2 * (k(0) + t2 * (k(1) + t2 * (k(2) + t2 * k(3)))));
  const double scale = theta_d / r;
  if (d_xy != nullptr) {
    // distorted = xy · s(r) with s = θ_d / r, so ∂distorted/∂xy = s I + (s'(r) / r) xy xyᵀ, and
    // s'(r) / r = (dθ_d/dθ · dθ/dr − s) / r². The difference is O(r²) and loses digits as r → 0, but
    // its error (≈ ε / r²) is multiplied by xy xyᵀ (≤ r²), so the Jacobian stays accurate to ≈ ε.
    const double d_theta_d_d_theta = 1.0 + t2 * (3.0 * k(0) + t2 * (5.0 * k(1) + t2 * (7.0 * k(2) + t2 * 9.0 * k(3))));
    const double d_scale_d_r_over_r = (d_theta_d_d_theta / (1.0 + r2) - scale) / r2;
    *d_xy = scale * Eigen::Matrix2d::Identity() + d_scale_d_r_over_r * (xy * xy.transpose());
  }
  return xy * scale;
}

}  // namespace

Eigen::Vector2d CameraModel::distortNormalized(const Eigen::Vector2d& xy) const { return distort(*this, xy, nullptr); }

Projection CameraModel::project(const Eigen::Vector3d& p_camera) const { return project(p_camera, nullptr); }

Projection CameraModel::project(const Eigen::Vector3d& p_camera, Eigen::Matrix<double, 2, 3>* d_pixel_d_point) const {
  Projection out;
  if (d_pixel_d_point != nullptr) d_pixel_d_point->setZero();
  if (!p_camera.allFinite() || !(p_camera.z() > 1e-9)) return out;
  const Eigen::Vector2d xy = p_camera.head<2>() / p_camera.z();
  Eigen::Matrix2d d_distorted_d_xy;
  const Eigen::Vector2d distorted = distort(*this, xy, d_pixel_d_point != nullptr ? &d_distorted_d_xy : nullptr);
  out.pixel = K.topLeftCorner<2, 2>() * distorted + K.topRightCorner<2, 1>();
  out.in_front = out.pixel.allFinite();
  out.in_image = out.in_front && out.pixel.x() >= -0.5 && out.pixel.x() < width - 0.5 && out.pixel.y() >= -0.5 &&
                 out.pixel.y() < height - 0.5;
  if (d_pixel_d_point != nullptr && out.in_front) {
    const double inv_z = 1.0 / p_camera.z();
    Eigen::Matrix<double, 2, 3> d_xy_d_point;  // (x/z, y/z) w.r.t. (x, y, z)
    d_xy_d_point << inv_z, 0.0, -xy.x() * inv_z, 0.0, inv_z, -xy.y() * inv_z;
    *d_pixel_d_point = K.topLeftCorner<2, 2>() * d_distorted_d_xy * d_xy_d_point;
  }
  return out;
}

Result<Eigen::Matrix2Xd> CameraModel::undistortToNormalized(const Eigen::Matrix2Xd& pixels) const {
  DG_RETURN_IF_ERROR(validate());
  for (Eigen::Index i = 0; i < pixels.cols(); ++i) {
    if (!pixels.col(i).allFinite()) {
      return Status(StatusCode::kInvalidArgument, "undistortToNormalized: pixel " + std::to_string(i) + " is not finite");
    }
  }
  Eigen::Matrix2Xd normalized(2, pixels.cols());
  if (pixels.cols() == 0) return normalized;
  std::vector<cv::Point2d> in(static_cast<size_t>(pixels.cols()));
  for (Eigen::Index i = 0; i < pixels.cols(); ++i) in[static_cast<size_t>(i)] = {pixels(0, i), pixels(1, i)};
  cv::Matx33d camera_matrix;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) camera_matrix(r, c) = K(r, c);
  }
  std::vector<double> coefficients(distortion.data(), distortion.data() + distortion.size());
  std::vector<cv::Point2d> out;
  try {
    if (model == Distortion::kRadTan) {
      cv::undistortPoints(in, out, camera_matrix, coefficients, cv::noArray(), cv::noArray(),
                          cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
    } else {
      cv::fisheye::undistortPoints(in, out, camera_matrix, coefficients, cv::noArray(), cv::noArray(),
                                   cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-14));
    }
  } catch (const cv::Exception& e) {
    return Status(StatusCode::kNumericalError, std::string("undistortToNormalized: OpenCV: ") + e.what());
  }
  for (Eigen::Index i = 0; i < pixels.cols(); ++i) {
    const cv::Point2d& p = out[static_cast<size_t>(i)];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || p.x < kFisheyeFailureMarker || p.y < kFisheyeFailureMarker) {
      return Status(StatusCode::kNumericalError,
                    "undistortToNormalized: pixel " + std::to_string(i) + " has no inverse under the " +
                        distortionModelName(model) + " model");
    }
    normalized.col(i) << p.x, p.y;
  }
  return normalized;
}

Status CameraModel::validate() const {
  if (!K.allFinite()) return invalid("K", "has a non-finite entry");
  if (!(K(0, 0) > 0.0)) return invalid("fx", "must be > 0, got " + std::to_string(K(0, 0)));
  if (!(K(1, 1) > 0.0)) return invalid("fy", "must be > 0, got " + std::to_string(K(1, 1)));
  if (K(0, 1) != 0.0 || K(1, 0) != 0.0 || K(2, 0) != 0.0 || K(2, 1) != 0.0 || K(2, 2) != 1.0) {
    return invalid("K", "must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew)");
  }
  const bool radtan = model == Distortion::kRadTan;
  const Eigen::Index n = distortion.size();
  if (radtan ? (n != 4 && n != 5) : n != 4) {
    return invalid("distortion", std::string("the ") + distortionModelName(model) + " model takes " +
                                     (radtan ? "4 or 5" : "4") + " coefficients, got " + std::to_string(n));
  }
  if (!distortion.allFinite()) return invalid("distortion", "has a non-finite coefficient");
  if (width <= 0) return invalid("width", "must be > 0, got " + std::to_string(width));
  if (height <= 0) return invalid("height", "must be > 0, got " + std::to_string(height));
  if (!std::isfinite(time_offset) || std::abs(time_offset) > 1.0) {
    return invalid("time_offset", "must be finite and at most 1 s in magnitude");
  }
  const Status rigid = checkRigidTransform(body_T_camera, "body_T_camera");
  if (!rigid.ok()) return invalid("body_T_camera", rigid.message());
  return Status::okStatus();
}

}  // namespace dualgraph
