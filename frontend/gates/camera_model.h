// SPDX-License-Identifier: MIT
// CameraModel: a calibrated camera (OpenCV radtan or equidistant), projection and undistortion.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// Where a camera-frame point lands in the image (CameraModel::project).
struct Projection {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  ///< [px]; (0, 0) is the centre of the top-left pixel
  bool in_front = false;  ///< z_camera > 1e-9 m (and the model is defined there); else `pixel` is meaningless
  bool in_image = false;  ///< in front and −0.5 ≤ u < width − 0.5, −0.5 ≤ v < height − 0.5
  bool valid() const { return in_front && in_image; }
};

/// A calibrated camera, in OpenCV's conventions (frontend/gates/README.md, frontend/io/FORMATS.md).
///
/// Camera frame: origin at the optical centre, x right, y down, z along the optical axis (RDF) [m].
/// `body_T_camera` maps points from that frame to the body frame. A point p_camera = (x, y, z) goes to
/// the normalised plane (x/z, y/z), is distorted there, then `K` gives the pixel (u, v) [px].
///
/// Distortion models (OpenCV's formulas, so `undistortToNormalized` inverts `project` exactly):
///  - kRadTan (cv::projectPoints): `distortion` = k1 k2 p1 p2 [k3] (4 or 5 values);
///    r² = x² + y², x_d = x (1 + k1 r² + k2 r⁴ + k3 r⁶) + 2 p1 x y + p2 (r² + 2x²), y_d likewise.
///  - kEquidistant (cv::fisheye, Kannala–Brandt): `distortion` = k1 k2 k3 k4 (4 values);
///    θ = atan(r), θ_d = θ (1 + k1 θ² + k2 θ⁴ + k3 θ⁶ + k4 θ⁸), x_d = x θ_d / r.
/// `K` = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew).
struct CameraModel {
  enum class Distortion { kRadTan, kEquidistant };

  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  Distortion model = Distortion::kRadTan;
  Eigen::VectorXd distortion = Eigen::VectorXd::Zero(4);
  int width = 0;   ///< [px]
  int height = 0;  ///< [px]
  Eigen::Isometry3d body_T_camera = Eigen::Isometry3d::Identity();
  /// Camera-to-VIO clock offset [s]: a detection stamped t was taken at t − time_offset on the odometry's
  /// clock (the camera's stamps are late by it; negative when they are early). OpenVINS's
  /// `timeshift_cam_imu` (t_imu = t_cam + shift) is −time_offset. At most 1 s in magnitude.
  double time_offset = 0.0;

  /// Pinhole camera with fx, fy, cx, cy [px] and the given model with zero distortion.
  static CameraModel pinhole(double fx, double fy, double cx, double cy, int width, int height,
                             Distortion model = Distortion::kRadTan);

  /// Pixel of a point in the camera frame [m], with the flags of `Projection`.
  Projection project(const Eigen::Vector3d& p_camera) const;
  /// `project(p_camera)` (the same pixel, bit for bit) and, when `d_pixel_d_point` is non-null, the
  /// analytic Jacobian ∂pixel/∂p_camera [px/m] of the pixel [px] w.r.t. the camera-frame point [m]:
  /// K's 2×2 block · ∂distorted/∂(x/z, y/z) · ∂(x/z, y/z)/∂p_camera. Finite on the optical axis
  /// (equidistant: θ_d/r → 1, its derivative → 0). Set to zero when the point is not `in_front`.
  Projection project(const Eigen::Vector3d& p_camera, Eigen::Matrix<double, 2, 3>* d_pixel_d_point) const;
  /// The distorted normalised-plane point of an undistorted one (the model without K).
  Eigen::Vector2d distortNormalized(const Eigen::Vector2d& xy) const;
  /// Pixels (one per column, [px]) → undistorted normalised coordinates (x/z, y/z), via
  /// cv::undistortPoints (radtan) or cv::fisheye::undistortPoints, iterated to 1e-12 rather than
  /// OpenCV's default 5/10 iterations. kInvalidArgument on a non-finite pixel or an invalid camera;
  /// kNumericalError when the inverse does not exist (OpenCV's fisheye solver flips θ or diverges).
  Result<Eigen::Matrix2Xd> undistortToNormalized(const Eigen::Matrix2Xd& pixels) const;

  /// OK, or kInvalidArgument naming the field: fx, fy > 0, K of the form above, 4 or 5 (radtan) /
  /// 4 (equidistant) finite coefficients, width and height > 0, body_T_camera finite and rigid.
  Status validate() const;

  double fx() const { return K(0, 0); }
  double fy() const { return K(1, 1); }
  double cx() const { return K(0, 2); }
  double cy() const { return K(1, 2); }

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// "radtan" or "equidistant".
const char* distortionModelName(CameraModel::Distortion model);

}  // namespace dualgraph
