// SPDX-License-Identifier: MIT
// solveGatePnp: a gate's pose and covariance from its four corner pixels, or why it was refused.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "dualgraph/frontend/gates/corner_detection.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

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

/// How solveGatePnp turns the pixel noise into the pose covariance (see GatePnpSolution).
enum class PnpCovarianceModel {
  kLaplace,        ///< σ² (JᵀJ)⁻¹ at the returned pose, mixed with IPPE's other basin when it found one
  kTiltPosterior,  ///< the posterior's second moment, the tilt integrated on a lattice (consistent; not the
                   ///< default: the localizer's ATE is not lower with it, see frontend/gates/README.md)
};

struct GatePnpParams {
  double gate_size = 1.5;               ///< side of the inner square [m]
  double pixel_sigma = 1.0;             ///< corner noise, standard deviation per pixel coordinate [px]
  double max_reprojection_rms = 2.0;    ///< [px], sqrt of the mean squared corner distance
  double min_range = 0.3;               ///< [m], |camera_T_gate.translation()|
  double max_range = 50.0;              ///< [m]
  double min_corner_angle_deg = 5.0;    ///< [deg], in the undistorted normalised plane
  double max_condition_number = 1e10;   ///< of JᵀJ (J in px per m and px per rad)
  int max_refinement_iterations = 20;   ///< Gauss–Newton steps in pixel space after IPPE
  PnpCovarianceModel covariance_model = PnpCovarianceModel::kLaplace;
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
/// and rotation apart, types/se3_math.h), Σ = σ² (JᵀJ)⁻¹ with J = ∂pixels/∂ε (8×6, analytic
/// through project). Because body_T_gate = body_T_camera · camera_T_gate shares that perturbation, the
/// same Σ is the covariance of body_T_gate, as GateObservation expects.
///
/// Ambiguity: near-frontal views of a small square have two poses (mirrored tilts) explaining the
/// pixels almost equally. The alternative is the best other refined candidate that differs by more
/// than 1° in rotation or, when IPPE's and SQPnP's candidates all end in one basin (and the model is
/// kTiltPosterior), the returned pose with its normal reflected about the line of sight and its
/// translation re-fitted. It is kept in `alternative_*`, and `ambiguous` is set when it is also within
/// max_reprojection_rms. The returned pose is always the lower-RMS one.
///
/// kTiltPosterior: Σ is the second moment of the posterior about the returned pose (flat
/// prior, isotropic pixel noise), the two tilt angles across the line of sight integrated on a lattice
/// that reaches the alternative, the other four coordinates Gaussian given the tilt
/// (frontend/gates/gate_pnp_posterior.h). kLaplace (default): σ² (JᵀJ)⁻¹, mixed with IPPE's other basin when it found
/// one, w₁Σ₁ + w₂(Σ₂ + δδᵀ) (weights: each mode's Laplace mass).
/// kTiltPosterior is consistent on the simulated RATM ellipse (test/frontend/simulator_sensors_test.cpp), kLaplace
/// optimistic beyond 6 m, where the tilt's likelihood is flat-topped or two-peaked; kTiltPosterior costs about
/// twice as much per view (NEES and cost: bench/README.md, "Gate PnP per detection").
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
  /// When `ambiguous` (and no upright prior): the two-mode covariance about the alternative, as `covariance` is about
  /// the returned pose (the Laplace mixture below, whichever covariance_model), in the alternative's gate frame.
  Matrix6d alternative_covariance = Matrix6d::Identity();
  bool has_alternative_covariance = false;  ///< alternative_covariance was computed (`ambiguous`, no upright prior)

  bool ok() const { return rejection == GatePnpRejection::kNone; }
  /// The kPose GateObservation of an accepted solution (body_T_gate, covariance; when `ambiguous`, the alternative
  /// as the observation's alternative, for the association to choose against the map).
  GateObservation observation(double t, int gate_id) const;

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// The corners tl, tr, br, bl in the gate frame [m] (columns) for a gate of inner side `gate_size`.
Eigen::Matrix<double, 3, 4> gateCornersInGateFrame(double gate_size, GateSide side = GateSide::kFront);

/// A prior that the gate stands upright: its z axis along `up_in_camera` (unit; the direction opposite gravity in
/// the camera frame, from the VIO's attitude), with `sigma` [rad] on each of the two tilts across it.
struct UprightGatePrior {
  Eigen::Vector3d up_in_camera = Eigen::Vector3d::UnitZ();
  double sigma = 0.0;  ///< [rad], > 0
};

/// Pose of the gate from its four corner pixels (order above), seen from `side`. Never throws. With `upright`,
/// the pose is the posterior's mode under that prior (every candidate refined with it, the most probable kept)
/// and the covariance its Laplace one, (JᵀJ/σ² + the prior's information)⁻¹: a far gate's tilt, which its image
/// hardly fixes, then comes from gravity, and its range is no longer pulled short by a tilt the noise suggests.
GatePnpSolution solveGatePnp(const GateCornerPixels& corners, const CameraModel& camera,
                             GateSide side = GateSide::kFront, const GatePnpParams& params = GatePnpParams{},
                             const UprightGatePrior* upright = nullptr);

}  // namespace dualgraph
