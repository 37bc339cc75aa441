// SPDX-License-Identifier: MIT
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

#include "dual_graph/measurements.h"
#include "frontend/camera_model.h"
#include "types/se3_math.h"

namespace dualgraph {

/// The four inner corners of a gate as they appear in the image [px], columns in the order of
/// DESIGN.md §6: top-left, top-right, bottom-right, bottom-left (a clockwise cycle in the image).
using GateCornerPixels = Eigen::Matrix<double, 2, 4>;

/// Which face of the gate the camera sees; the association stage decides.
/// Gate frame: origin at the centre of the inner square, x along the gate normal (the direction of
/// flight through it), z up, y = z × x (left when flying through). Seen from the front (camera on
/// the −x side) the image corners tl, tr, br, bl are (0, +s/2, +s/2), (0, −s/2, +s/2), (0, −s/2, −s/2),
/// (0, +s/2, −s/2). Seen from behind they are the same points of the frame turned 180° about z, i.e.
/// y negated: left and right swap.
enum class GateSide { kFront, kBack };

/// Why solveGatePnp refused a detection.
enum class GatePnpRejection {
  kNone = 0,
  kNonFiniteInput,     ///< a corner pixel is NaN or infinite
  kInvalidInput,       ///< the camera fails CameraModel::validate or the parameters are out of range
  kNotConvex,          ///< the undistorted corners are not a convex clockwise quadrilateral (self-intersecting, or wrong order)
  kDegenerate,         ///< an interior angle within min_corner_angle_deg of 0° or 180°, or JᵀJ ill-conditioned
  kSolverFailed,       ///< undistortion or OpenCV's solver failed, or the pose puts a corner behind the camera
  kReprojectionError,  ///< reprojection RMS above max_reprojection_rms
  kRangeOutOfBounds,   ///< distance camera → gate centre outside [min_range, max_range]
};
/// "NonFiniteInput", ...
const char* gatePnpRejectionName(GatePnpRejection rejection);

struct GatePnpParams {
  double gate_size = 1.5;               ///< side of the inner square [m]
  double pixel_sigma = 1.0;             ///< corner noise, standard deviation per pixel coordinate [px]
  double max_reprojection_rms = 2.0;    ///< [px], sqrt of the mean squared corner distance
  double min_range = 0.3;               ///< [m], |camera_T_gate.translation()|
  double max_range = 50.0;              ///< [m]
  double min_corner_angle_deg = 5.0;    ///< [deg], in the undistorted normalised plane
  double max_condition_number = 1e10;   ///< of JᵀJ (J in px per m and px per rad)
  int max_refinement_iterations = 20;   ///< Gauss–Newton steps in pixel space after IPPE
  /// When IPPE's and SQPnP's candidates end in one basin, take the mirrored tilt (translation re-fitted)
  /// as the alternative mode anyway (see below): a consistent covariance for near-frontal far views
  /// (mean NEES 6.3 instead of 7.2 on the simulated RATM views) at the price of the localizer's
  /// accuracy on the ellipse (ATE 0.034 → 0.041 m over seeds 1–3), so off by default.
  bool mirrored_tilt_alternative = false;
};

/// The pose of one gate from its corners, or the reason it was rejected.
///
/// Method: the corner pixels are undistorted to normalised coordinates (one path for both lens
/// models; cv::solvePnP has no equidistant model) and cv::solvePnPGeneric(SOLVEPNP_IPPE_SQUARE) gives
/// IPPE's two candidate poses (plus SQPnP's, a safeguard: OpenCV's IPPE degrades at an exactly
/// fronto-parallel view). Each is refined by Gauss–Newton on the *pixel* reprojection error
/// through CameraModel::project, so the estimate is the maximum-likelihood pose under isotropic pixel
/// noise (the normalised-plane error that IPPE minimises weights pixels unequally: fx ≠ fy, distortion),
/// and the lower-RMS candidate is returned.
///
/// Covariance: metric [t; θ] (m², rad²), a right perturbation in the gate frame in the chart the
/// graph's SE(3) edges measure errors in, camera_T_gate_true = se3BoxPlus(camera_T_gate, ε) (translation
/// and rotation apart, types/se3_math.h), Σ = σ² (JᵀJ)⁻¹ with J = ∂pixels/∂ε (8×6, central differences
/// through project). Because body_T_gate = body_T_camera · camera_T_gate shares that perturbation, the
/// same Σ is the covariance of body_T_gate, as GateObservation expects.
///
/// Ambiguity: near-frontal views of a small square have two poses (mirrored tilts) explaining the
/// pixels almost equally. The alternative is the best other refined candidate that differs by more
/// than 1° in rotation or, when IPPE's and SQPnP's candidates all end in one basin and
/// `mirrored_tilt_alternative` is set, the returned pose with its normal reflected about the line of
/// sight and its translation re-fitted (the error's profile at the mirrored tilt). It is kept in
/// `alternative_*`, and `ambiguous` is set when it is also within max_reprojection_rms. The returned
/// pose is still the lower-RMS one. Σ is the second moment of the two-mode posterior about the
/// returned pose, w₁Σ₁ + w₂(Σ₂ + δδᵀ), δ the alternative's offset, weights ∝ exp(−SSR/2σ²)·√det Σ
/// (each mode's Laplace mass), so it says how little the tilt is known.
/// Consistency on the simulated RATM ellipse (σ = 1 px, first 1000 views, test/frontend/
/// simulator_sensors_test.cpp; band 5.79–6.22): mean NEES 7.18 by default (6.29 below 6 m, 7.8 beyond
/// 10 m); 6.33 with `mirrored_tilt_alternative` (6.21 beyond 10 m, 6.68 at 6–10 m, where the tilt is
/// neither determined nor clearly two-fold).
struct GatePnpSolution {
  GatePnpRejection rejection = GatePnpRejection::kNone;
  std::string message;  ///< why it was rejected (empty when accepted)
  Eigen::Isometry3d camera_T_gate = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d body_T_gate = Eigen::Isometry3d::Identity();
  Matrix6d covariance = Matrix6d::Identity();  ///< see above; valid only when accepted
  double reprojection_rms = 0.0;                ///< [px]
  double condition_number = 0.0;                ///< of JᵀJ
  bool ambiguous = false;
  Eigen::Isometry3d alternative_camera_T_gate = Eigen::Isometry3d::Identity();
  double alternative_reprojection_rms = 0.0;  ///< [px]; 0 when no candidate differs by > 1°

  bool ok() const { return rejection == GatePnpRejection::kNone; }
  /// The kPose GateObservation of an accepted solution (body_T_gate, covariance).
  GateObservation observation(double t, int gate_id) const {
    return GateObservation::pose(t, gate_id, body_T_gate, covariance);
  }

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// The corners tl, tr, br, bl in the gate frame [m] (columns) for a gate of inner side `gate_size`.
Eigen::Matrix<double, 3, 4> gateCornersInGateFrame(double gate_size, GateSide side = GateSide::kFront);

/// Pose of the gate from its four corner pixels (order above), seen from `side`. Never throws.
GatePnpSolution solveGatePnp(const GateCornerPixels& corners, const CameraModel& camera,
                             GateSide side = GateSide::kFront, const GatePnpParams& params = GatePnpParams{});

}  // namespace dualgraph
