// SPDX-License-Identifier: MIT
// ObservationModel: what the dual graph does with one kind of gate observation, one object per ObservationKind.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>

#include "dualgraph/core/robust_kernel.h"
#include "dualgraph/core/status.h"
#include "dualgraph/dual_graph/gate_edge.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/dual_graph/temporary_pool.h"

namespace dualgraph {

/// The pose node an observation is attached to: `node_T_body`, the VIO increment from the node's instant to the
/// observation's (identity at the node itself), and `compensation`, its covariance (metric [t; θ], m² and rad², a
/// right perturbation of node_T_body), or null when the observation was taken at the node's instant.
struct NodeAttachment {
  Eigen::Isometry3d node_T_body = Eigen::Isometry3d::Identity();
  const Matrix6d* compensation = nullptr;

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// One observation re-expressed at its pose node, as the temporary graph keeps it until the keyframe. A kind that
/// anchors its gate fills `edge` (one constraint node → gate, gate_edge.h); a kind that does not (rays) fills
/// `rays` with body_T_camera replaced by node_T_camera, and `ray_information` per ray (the normalised image
/// coordinates' information [1], the pixel noise and the motion compensation's uncertainty). Plain data.
struct AttachedObservation {
  size_t node = 0;  ///< the temporary graph's node index (set by the temporary graph)
  int gate_id = -1;
  ObservationKind kind = ObservationKind::kPose;
  GateEdgeMeasurement edge;
  GateCornerRays rays;
  std::array<Eigen::Matrix2d, 4> ray_information{Eigen::Matrix2d::Identity(), Eigen::Matrix2d::Identity(),
                                                 Eigen::Matrix2d::Identity(), Eigen::Matrix2d::Identity()};

  /// An empty record of `observation` (its gate and kind), its edge (if any) for a `landmark` gate.
  static AttachedObservation of(const GateObservation& observation, LandmarkModel landmark);

  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Everything kind-specific about a gate observation, in one object per ObservationKind (`observationModel`):
/// its field checks, which Localizer settings can use it, how it is re-expressed at a pose node (motion
/// compensation), which temporary-graph edges it becomes, and whether it anchors its gate there (gives the gate
/// an initial estimate and constrains all its degrees of freedom) or joins a gate another observation anchors.
/// The Localizer, the temporary graph and the single-graph baseline call these and branch on no kind.
/// dual_graph/README.md ("Add a detection type") says how to add one.
/// Frames: `body` (the observation's), the node's, `gate`, the odometry frame of the temporary graph.
/// Threads: stateless and immutable; one object per kind is shared by every thread.
class ObservationModel {
 public:
  virtual ~ObservationModel() = default;

  virtual ObservationKind kind() const = 0;
  /// "pose", "position", "corners": as messages, files and Python name the kind.
  virtual const char* name() const = 0;
  /// The kind's own fields (finite, rigid, covariances symmetric positive definite); kInvalidArgument naming
  /// the field after `where`. The common fields (time, gate id) are checked by validateGateObservation.
  virtual Status validate(const GateObservation& observation, const std::string& where) const = 0;
  /// OK when a Localizer with `params` can use this kind; kInvalidArgument saying which setting it needs.
  virtual Status checkUsable(const LocalizerParams& params, const std::string& what) const = 0;
  /// True when one observation constrains its gate fully in the temporary graph (creates and anchors it);
  /// false when it only joins a gate anchored by another observation of the interval (else left out, counted).
  virtual bool anchorsGate() const = 0;
  /// The observation re-expressed at the node of `at`, for gates modelled as `landmark`; kInvalidArgument when
  /// the kind cannot constrain that landmark, kNotPositiveDefinite when its covariance is unusable.
  virtual Result<AttachedObservation> attach(const GateObservation& observation, const NodeAttachment& at,
                                             LandmarkModel landmark) const = 0;
  /// Adds the edges of `attached` from pose vertex `node` to gate vertex `gate` of the temporary graph, each
  /// with `kernel` (may be null).
  virtual Status addTemporaryEdges(const AttachedObservation& attached, TemporaryPool& pool, int node, int gate,
                                   const std::shared_ptr<const RobustKernel>& kernel) const = 0;
  /// The gate's initial estimate in the temporary graph (odom_T_gate; a point: its translation) from an anchoring
  /// observation at the node with `odom_T_node`. Kinds that do not anchor are never asked.
  virtual Eigen::Isometry3d anchor(const AttachedObservation& attached, const Eigen::Isometry3d& odom_T_node) const {
    return gateFromNode(odom_T_node, attached.edge);
  }
  /// The gate centre in body axes [m] (a pose's translation; rays: the pose the frontend predicted).
  virtual Eigen::Vector3d centreInBody(const GateObservation& observation) const = 0;
  /// Its covariance [m²], body axes.
  virtual Eigen::Matrix3d centreCovarianceInBody(const GateObservation& observation) const = 0;

 protected:
  /// The observation's centre and covariance as a point constraint at the node (landmark: point):
  /// p_node = node_T_body · p_body, Σ = R Σ_body Rᵀ + J Σ_c Jᵀ with J = R_node_body [I, −[p_body]×].
  Result<AttachedObservation> attachCentre(const GateObservation& observation, const NodeAttachment& at) const;
};

/// The model of `kind` (a static object per kind), or null for a value that names no kind (the one place that
/// lists the kinds).
const ObservationModel* findObservationModel(ObservationKind kind);
/// The model of a valid observation's kind (validateGateObservation refuses unknown kinds; the pose model for
/// one that slipped through).
const ObservationModel& observationModel(ObservationKind kind);

}  // namespace dualgraph
