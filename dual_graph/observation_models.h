// SPDX-License-Identifier: MIT
// The built-in observation models: a gate's pose, its centre, the rays to the corners of a partial gate.
#pragma once

#include "dualgraph/dual_graph/observation_model.h"

namespace dualgraph {

/// kPose: `body_T_gate` with a 6×6 metric covariance (a right perturbation in the gate frame). Anchors its gate:
/// an EdgeSE3 node → gate (pose landmarks; the covariance plus Ad(gate_T_body) Σ_c Ad(gate_T_body)ᵀ of the
/// motion compensation, in g2o units) or, for point landmarks, its centre as an EdgeSE3PointXYZ. A pose that
/// carries the four corner rays it was solved from (`corner_rays.count` 4, in its gate frame) becomes those four
/// EdgeSE3CornerProjection in the temporary graph instead (pose landmarks; its pose then only the gate's first
/// estimate): the graph fits the gate to every image's corners at once, so a PnP's per-image bias (a far gate's
/// range, short by ∝ σ²) is not averaged in. The single-graph baseline and point landmarks use the pose.
/// Threads: stateless; shared by every thread.
class PoseObservationModel final : public ObservationModel {
 public:
  ObservationKind kind() const override { return ObservationKind::kPose; }
  const char* name() const override { return "pose"; }
  Status validate(const GateObservation& observation, const std::string& where) const override;
  Status checkUsable(const LocalizerParams& params, const std::string& what) const override;
  bool anchorsGate() const override { return true; }
  Result<AttachedObservation> attach(const GateObservation& observation, const NodeAttachment& at,
                                     LandmarkModel landmark) const override;
  Status addTemporaryEdges(const AttachedObservation& attached, TemporaryPool& pool, int node, int gate,
                           const std::shared_ptr<const RobustKernel>& kernel) const override;
  Eigen::Vector3d centreInBody(const GateObservation& observation) const override;
  Eigen::Matrix3d centreCovarianceInBody(const GateObservation& observation) const override;
};

/// kPosition: the gate centre `p_body` [m] with a 3×3 covariance [m²] in body axes. Anchors a point landmark
/// (EdgeSE3PointXYZ node → gate); pose landmarks refuse it (three of their six degrees of freedom unobserved).
/// Threads: stateless; shared by every thread.
class PositionObservationModel final : public ObservationModel {
 public:
  ObservationKind kind() const override { return ObservationKind::kPosition; }
  const char* name() const override { return "position"; }
  Status validate(const GateObservation& observation, const std::string& where) const override;
  Status checkUsable(const LocalizerParams& params, const std::string& what) const override;
  bool anchorsGate() const override { return true; }
  Result<AttachedObservation> attach(const GateObservation& observation, const NodeAttachment& at,
                                     LandmarkModel landmark) const override;
  Status addTemporaryEdges(const AttachedObservation& attached, TemporaryPool& pool, int node, int gate,
                           const std::shared_ptr<const RobustKernel>& kernel) const override;
  Eigen::Vector3d centreInBody(const GateObservation& observation) const override;
  Eigen::Matrix3d centreCovarianceInBody(const GateObservation& observation) const override;
};

/// kCorners: a partial gate as rays to the 2–4 corners seen (GateCornerRays: normalised image coordinates with
/// their 2×2 covariance, the camera on the body). One EdgeSE3CornerProjection per corner from the node to a pose
/// landmark; does not anchor (a few corners leave the gate's pose unobservable): joins a gate a pose observation
/// of the same interval anchors. The motion compensation adds J Σ_c Jᵀ per ray, J = ∂(x/z, y/z)/∂ε at the
/// corner the frontend predicted. Dual mode with pose landmarks only. Threads: stateless; shared by every thread.
class CornerRaysObservationModel final : public ObservationModel {
 public:
  ObservationKind kind() const override { return ObservationKind::kCorners; }
  const char* name() const override { return "corners"; }
  Status validate(const GateObservation& observation, const std::string& where) const override;
  Status checkUsable(const LocalizerParams& params, const std::string& what) const override;
  bool anchorsGate() const override { return false; }
  Result<AttachedObservation> attach(const GateObservation& observation, const NodeAttachment& at,
                                     LandmarkModel landmark) const override;
  Status addTemporaryEdges(const AttachedObservation& attached, TemporaryPool& pool, int node, int gate,
                           const std::shared_ptr<const RobustKernel>& kernel) const override;
  Eigen::Vector3d centreInBody(const GateObservation& observation) const override;
  Eigen::Matrix3d centreCovarianceInBody(const GateObservation& observation) const override;
};

/// The checks of a GateCornerRays (count 2 … 4, finite corners and rays, covariances SPD, a rigid
/// body_T_camera); kInvalidArgument naming the field after `where`.
Status validateCornerRays(const GateCornerRays& rays, const std::string& where);
/// Fills `attached.rays` and `attached.ray_information` from `rays` at the node of `at`: body_T_camera becomes
/// node_T_camera, and each ray's covariance gains J Σ_c Jᵀ of the motion compensation at the corner that
/// `body_T_gate` places.
void attachCornerRays(const GateCornerRays& rays, const Eigen::Isometry3d& body_T_gate, const NodeAttachment& at,
                      AttachedObservation& attached);
/// One EdgeSE3CornerProjection per ray of `attached` from pose vertex `node` to gate vertex `gate`.
Status addCornerRayEdges(const AttachedObservation& attached, TemporaryPool& pool, int node, int gate,
                         const std::shared_ptr<const RobustKernel>& kernel);

}  // namespace dualgraph
