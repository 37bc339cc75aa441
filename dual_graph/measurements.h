// SPDX-License-Identifier: MIT
// The Localizer's inputs, OdometrySample and GateObservation, and their validation.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>

#include "dualgraph/core/status.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {

/// One VIO sample at time `t` [s]: `odom_T_body` maps points from the body frame to the odometry's
/// own frame. `relative_covariance`, when given, is the covariance of the motion since the previous
/// sample: 6×6, metric [t; θ] (m², rad²), a right perturbation in the current body frame,
/// i.e. prev_T_cur_true = prev_T_cur · exp(ε), ε ~ N(0, Σ).
struct OdometrySample {
  double t = 0.0;
  Eigen::Isometry3d odom_T_body = Eigen::Isometry3d::Identity();
  std::optional<Matrix6d> relative_covariance;

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// What a gate observation measures. Everything kind-specific is in the kind's ObservationModel
/// (observation_model.h); dual_graph/README.md says how to add a kind.
enum class ObservationKind {
  kPose,      ///< `body_T_gate` with a 6×6 covariance
  kPosition,  ///< the gate centre `p_body` with a 3×3 covariance
  kCorners,   ///< a gate partly out of the image: rays to the corners seen (`corner_rays`)
};

/// A partial gate (2–3 corners in the image; 4 allowed) as the rays the camera saw: for corner k < count, its
/// position `p_gate` in the gate's own frame [m] (the map gate's, after association) and the undistorted
/// normalised image coordinates (x/z, y/z, camera frame z forward) it was seen at, with the 2×2 covariance
/// `covariance[k]` of those coordinates (the pixel noise through the lens: σ_px² J⁻¹J⁻ᵀ, J = ∂pixel/∂(x/z, y/z)
/// there; near a fisheye's border one pixel spans several times 1/fx). The temporary graph turns each corner
/// into an EdgeSE3CornerProjection.
struct GateCornerRays {
  int count = 0;                                                      ///< 2 … 4 (the first `count` columns)
  Eigen::Matrix<double, 3, 4> p_gate = Eigen::Matrix<double, 3, 4>::Zero();
  Eigen::Matrix<double, 2, 4> normalized = Eigen::Matrix<double, 2, 4>::Zero();
  /// Per corner (the first `count`): covariance of its normalised coordinates [1], symmetric positive definite.
  std::array<Eigen::Matrix2d, 4> covariance{Eigen::Matrix2d::Identity() * 1e-6, Eigen::Matrix2d::Identity() * 1e-6,
                                            Eigen::Matrix2d::Identity() * 1e-6, Eigen::Matrix2d::Identity() * 1e-6};
  Eigen::Isometry3d body_T_camera = Eigen::Isometry3d::Identity();    ///< the camera on the body

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// One gate observation at time `t` [s] of the gate `gate_id` (≥ 0; association happens before).
/// kPose: `body_T_gate` maps points from the gate frame to the body frame; `pose_covariance` is metric
/// [t; θ] (m², rad²), a right perturbation in the gate frame (body_T_gate_true = body_T_gate · exp(ε)).
/// kPosition: `p_body` is the gate centre in body axes [m], `position_covariance` in m², body axes.
/// A kPose solved from corners may carry them (`corner_rays`, count 4, gate points in its gate frame): the dual
/// graph's temporary graph then uses the rays (observation_models.h); count 0 otherwise.
/// kCorners: `corner_rays` are the measurement; `body_T_gate` / `p_body` hold the pose the frontend predicted
/// when it associated them (not a measurement: used for statistics only). Used by the dual graph with
/// landmark pose only.
struct GateObservation {
  double t = 0.0;
  int gate_id = -1;
  ObservationKind kind = ObservationKind::kPose;
  Eigen::Isometry3d body_T_gate = Eigen::Isometry3d::Identity();
  Matrix6d pose_covariance = Matrix6d::Identity();
  Eigen::Vector3d p_body = Eigen::Vector3d::Zero();
  Eigen::Matrix3d position_covariance = Eigen::Matrix3d::Identity();
  GateCornerRays corner_rays;
  /// kPose only: a second pose that explains the same image about as well (a PnP's mirrored tilt, ambiguous near
  /// frontal views; GatePnpSolution::ambiguous) and its covariance about it, in the same chart as
  /// `pose_covariance`. The frontend's association keeps whichever of the two agrees with the map gate's
  /// orientation (frontend/gates/gate_association.h); the dual graph reads `body_T_gate` only.
  bool has_alternative = false;
  Eigen::Isometry3d alternative_body_T_gate = Eigen::Isometry3d::Identity();
  Matrix6d alternative_covariance = Matrix6d::Identity();

  static GateObservation pose(double t, int gate_id, const Eigen::Isometry3d& body_T_gate,
                              const Matrix6d& covariance);
  static GateObservation position(double t, int gate_id, const Eigen::Vector3d& p_body,
                                  const Eigen::Matrix3d& covariance);
  /// kCorners at `predicted_body_T_gate` (see above).
  static GateObservation corners(double t, int gate_id, const GateCornerRays& rays,
                                 const Eigen::Isometry3d& predicted_body_T_gate);
  /// The gate centre in body axes whatever the kind (a pose's translation; kCorners: the prediction): its
  /// ObservationModel's (observation_model.h).
  Eigen::Vector3d centreInBody() const;
  /// Its covariance (the translation block of a pose covariance, rotated into body axes).
  Eigen::Matrix3d centreCovarianceInBody() const;

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// The same observation in the gate frame turned by `turn` (a rotation about the gate centre: gate_T_turned):
/// body_T_gate · turn, the right-perturbation covariance Ad(turn⁻¹) Σ Ad(turn⁻¹)ᵀ, the corner rays' gate points
/// turn⁻¹ · p_gate. How a detection is put on its map gate's side or quarter turn.
GateObservation inTurnedGateFrame(GateObservation observation, const Eigen::Matrix3d& turn);

/// The observation with its alternative pose (and covariance) taken as the pose, the pose kept as the alternative;
/// unchanged without one.
GateObservation withAlternativeTaken(GateObservation observation);

/// kInvalidArgument naming the field when `t` or the pose is not finite, the rotation is not
/// orthonormal (|RᵀR − I| > 1e-6 or det ≤ 0), or the covariance is not finite, symmetric and positive definite.
Status validateOdometrySample(const OdometrySample& sample);
/// The same checks for an observation, plus gate_id ≥ 0 and a known kind, then its ObservationModel's (kCorners:
/// count 2 … 4, finite corners and rays, σ > 0, a rigid body_T_camera).
Status validateGateObservation(const GateObservation& observation);

}  // namespace dualgraph
