// SPDX-License-Identifier: MIT
// MainGraph: the long-lived keyframe and gate graph, with χ² gating and the fixed-lag window.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dualgraph/core/optimizer.h"
#include "dualgraph/dual_graph/gate_edge.h"
#include "dualgraph/dual_graph/gate_map.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/marginal_prior.h"
#include "dualgraph/dual_graph/odometry_history.h"

namespace dualgraph {

class EdgeSE3;

/// A keyframe (dual mode) or node (single mode) of the main graph.
struct Keyframe {
  int vertex_id = -1;
  double t = 0.0;                                                ///< [s]
  Eigen::Isometry3d odom_T_body = Eigen::Isometry3d::Identity();  ///< the VIO pose at t
  /// Fixed-lag mode: true once marginalised; the vertex is then gone from the graph and `frozen_pose`
  /// (world_T_body) holds its estimate when it left the window.
  bool marginalized = false;
  Eigen::Isometry3d frozen_pose = Eigen::Isometry3d::Identity();
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// What happened to a batch of gate edges.
struct GateEdgeOutcome {
  int added = 0;
  int rejected = 0;  ///< failed the χ² gate
  int rejected_observations = 0;  ///< detections the rejected edges stood for
  int failed = 0;    ///< could not be added (message says why)
  std::string message;
};

/// The long-lived graph (dual_graph/README.md), in the world frame: keyframe poses `world_T_body` (VertexSE3),
/// odometry edges between consecutive keyframes (VIO increment, metric covariance converted to g2o
/// units), gate landmarks (VertexSE3 `world_T_gate` or VertexPointXYZ `p_world`) with the known map as
/// priors (or fixed), and gate edges from keyframes. A persistent optimiser keeps warm starts.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class MainGraph {
 public:
  /// `map` must outlive the graph (may be empty in mapping mode); `kernel` may be null.
  MainGraph(const LocalizerParams& params, const GateMap& map, std::shared_ptr<const RobustKernel> kernel);

  /// The first keyframe: initial_world_T_odom · odom_T_body, held by the initial prior, or fixed
  /// (mapping mode, or initial_sigma_t ≤ 0).
  Status addFirstKeyframe(double t, const Eigen::Isometry3d& odom_T_body);
  /// A keyframe after the newest: initial guess newest · (VIO increment), and the odometry edge with the
  /// increment's metric [t; θ] base covariance under the graph's odometry scale.
  Status addKeyframe(double t, const Eigen::Isometry3d& odom_T_body, const Matrix6d& increment_covariance);
  /// The odometry scale (OdometryNoiseLearner) for the odometry edges to come and those still in the graph
  /// (their information recomputed from their base covariances; the marginalised ones keep theirs).
  Status setOdometryScale(const OdometryNoiseScale& scale);
  /// Adds one edge per measurement from keyframe `keyframe_index`, creating landmarks on first sight
  /// (at the map pose with its prior in localization mode; where seen in mapping mode). With the χ² gate
  /// on, each edge whose residual is implausible given the edge's and the graph's covariance is rejected.
  GateEdgeOutcome addGateEdges(size_t keyframe_index, const GateEdgeMeasurements& measurements);
  /// Warm-started LM with the configured iteration cap and time budget.
  SolverSummary optimize();
  /// Fixed-lag mode (`main_window` > 0): marginalises the oldest free keyframes until `main_window` remain
  /// (call after `optimize`, so they leave at an optimised estimate). A keyframe that cannot be
  /// marginalised (its marginal not positive definite, a non-finite linearisation) is conditioned on
  /// instead: fixed at its current estimate, its edges kept as they are, so the window of free keyframes
  /// stays bounded and the graph consistent; counted (conditionedKeyframes) and said in lastFallback().
  /// Errors only when even that fails.
  Status slideWindow();
  /// Keyframes conditioned on because their marginalisation failed, and the last such failure's message.
  size_t conditionedKeyframes() const { return conditioned_keyframes_; }
  const std::string& lastFallback() const { return last_fallback_; }
  /// Fault injection for tests: the marginalisation slideWindow uses (marginalizeVertex by default).
  using Marginalizer = std::function<Result<MarginalizationOutcome>(Graph&, int)>;
  void setMarginalizerForTesting(Marginalizer marginalizer) { marginalize_ = std::move(marginalizer); }
  /// Edges the main graph stands for: those in the optimisation plus those folded into marginal priors
  /// (the priors themselves not counted). Equals graph().numEdges() in full-batch mode.
  size_t totalEdges() const { return graph_.numEdges() - prior_edges_ + folded_edges_; }
  /// Keyframes marginalised so far (removed from the graph, estimates frozen in `keyframes()`).
  size_t marginalizedKeyframes() const { return marginalized_keyframes_; }
  /// Vertices the main graph stands for: those in the graph plus the marginalised keyframes.
  size_t totalVertices() const { return graph_.numVertices() + marginalized_keyframes_; }

  const std::vector<Keyframe, Eigen::aligned_allocator<Keyframe>>& keyframes() const { return keyframes_; }
  /// Marginal covariance of keyframe `index` (free, in the graph), metric [t; θ], a right perturbation of
  /// world_T_body in the body frame; zero when it is fixed. The factorisation's errors (a free gauge, say).
  Result<Matrix6d> keyframeCovariance(size_t index);
  /// Current estimate of keyframe `index` (the frozen one once marginalised).
  const Eigen::Isometry3d& keyframePose(size_t index) const;
  const Graph& graph() const { return graph_; }
  /// Vertex id of a gate landmark, -1 when it has none yet.
  int landmarkVertex(int gate_id) const;

 private:
  Result<int> findOrCreateLandmark(int gate_id, size_t keyframe_index, const GateEdgeMeasurement& measurement,
                                   bool& constrained);
  /// The joint marginal of (keyframe, landmark[k]) for every non-null edges[k], from the graph without
  /// those edges (their information zeroed for one factorisation, then restored).
  Status predictJointCovariances(int keyframe_id, const std::vector<int>& landmark, const std::vector<EdgeBase*>& edges,
                                 std::vector<Eigen::MatrixXd>& joint);
  /// eᵀS⁻¹e of `edge` with S = J Σ Jᵀ + Ω⁻¹, Σ the joint marginal of its two vertices.
  static double innovationChi2(EdgeBase& edge, const Eigen::MatrixXd& joint_covariance);
  double gateThreshold() const;

  const LocalizerParams params_;
  const GateMap& map_;
  std::shared_ptr<const RobustKernel> kernel_;
  Graph graph_;
  Optimizer optimizer_;
  std::vector<Keyframe, Eigen::aligned_allocator<Keyframe>> keyframes_;
  /// The odometry edge into keyframe `keyframe` and its base covariance (metric), for setOdometryScale.
  struct OdometryEdge {
    size_t keyframe;
    EdgeSE3* edge;
    Matrix6d base_covariance;
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  std::vector<OdometryEdge, Eigen::aligned_allocator<OdometryEdge>> odometry_edges_;
  OdometryNoiseScale odometry_scale_;
  std::map<int, int> landmark_vertex_;  ///< gate id → vertex id
  int next_vertex_id_ = 0;
  size_t first_free_keyframe_ = 0;   ///< keyframes before it are marginalised (or were fixed)
  size_t marginalized_keyframes_ = 0;
  size_t prior_edges_ = 0;           ///< EdgeMarginalPriors in graph_
  size_t folded_edges_ = 0;          ///< original edges folded into priors
  size_t conditioned_keyframes_ = 0;
  std::string last_fallback_;
  Marginalizer marginalize_ = marginalizeVertex;
};

}  // namespace dualgraph
