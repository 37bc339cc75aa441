// SPDX-License-Identifier: MIT
// TemporaryGraph: one keyframe interval's detections, distilled into one edge per gate.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "dualgraph/dual_graph/gate_edge.h"
#include "dualgraph/dual_graph/localizer_params.h"
#include "dualgraph/dual_graph/observation_model.h"
#include "dualgraph/dual_graph/odometry_history.h"
#include "dualgraph/dual_graph/temporary_pool.h"
#include "dualgraph/solvers/block/block_lm_solver.h"

namespace dualgraph {

/// What one distillation did (statistics and the edges for the main graph).
struct DistillationResult {
  GateEdgeMeasurements gates;  ///< one per gate seen in the interval, relative to the new keyframe
  int skipped_gates = 0;       ///< gates whose marginal covariance was not usable (not positive definite, …)
  int partial_used = 0;        ///< partial gates (corner rays) whose corners became edges
  /// Partial gates left out: their gate had no pose observation in the interval to anchor it (a few corners
  /// alone leave the gate's pose unobservable).
  int partial_unanchored = 0;
  std::string skip_reason;     ///< why the first one was skipped
  int nodes = 0;               ///< pose nodes of the temporary graph, the fixed keyframe included
  int edges = 0;
  int iterations = 0;
  double optimize_ms = 0.0;    ///< LM + marginals
};

/// The short-lived graph of one keyframe interval (dual_graph/README.md). Between keyframes it only records:
/// pose nodes at detection instants (a new one when the VIO increment since the last node exceeds
/// `d_temp`/`theta_temp`), each detection re-expressed in its node's frame (motion-compensated).
/// `distil` builds the graph in the odometry frame — nodes chained by VIO-increment edges ending at the
/// new keyframe K, which is fixed (the gauge); gates free, one edge per detection — optimises it, and
/// turns each gate L into one edge K → L with measurement K⁻¹·L and information Σ_L⁻¹, Σ_L the
/// marginal covariance of L (its own tangent space, which is exactly the tangent of that edge's error;
/// for a point the world-axes covariance is rotated into K's axes). A detection at the keyframe instant
/// attaches to K itself. Each kind's edges are its ObservationModel's: a kind that does not anchor its gate (a
/// partial gate's corner rays: one EdgeSE3CornerProjection per corner seen) joins the gate when another
/// observation of the interval anchors it (else it is counted unanchored).
/// The graph is optimised by `BlockLmSolver` (6×6 blocks, the default) or the generic
/// Optimizer (`temp_solver: graph` or `linear_solver: cholmod`); both give the same edges to round-off.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class TemporaryGraph {
 public:
  TemporaryGraph(const LocalizerParams& params, std::shared_ptr<const RobustKernel> kernel);

  /// Records a valid observation taken at `odom_T_body` (the VIO pose at its instant); `history` must
  /// cover [last node, observation]. Observations must come in non-decreasing time.
  Status addObservation(const GateObservation& observation, const Eigen::Isometry3d& odom_T_body,
                        const OdometryHistory& history);

  /// Distils into edges relative to the keyframe at (t_keyframe, odom_T_keyframe) and clears the record.
  /// `history` must cover [first node, t_keyframe]. Never fails: unusable gates are counted.
  DistillationResult distil(double t_keyframe, const Eigen::Isometry3d& odom_T_keyframe,
                            const OdometryHistory& history);
  /// The odometry scale for the motion compensation and the chain's increments (OdometryNoiseLearner).
  void setOdometryScale(const OdometryNoiseScale& scale) { odometry_scale_ = scale; }

  bool empty() const { return nodes_.empty(); }
  size_t numObservations() const { return records_.size(); }
  void clear();

 private:
  struct Node {
    double t;
    Eigen::Isometry3d odom_T_body;
    /// Information (g2o units) of the odometry edge to the next node, computed when that node is created
    /// (off the keyframe's critical path), or why it is unusable (reported by `distil`).
    Result<Matrix6d> information_to_next = Matrix6d(Matrix6d::Zero());
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  /// The information of the odometry edge (t_from, t_to]; kNotPositiveDefinite etc. when unusable.
  Result<Matrix6d> odometryInformation(double t_from, double t_to, const OdometryHistory& history) const;
  /// The node an observation at (t, odom_T_body) attaches to: the newest, or a new one when the VIO moved
  /// d_temp/theta_temp since (`new_node`). Fills node_T_body and the compensation covariance (null: none).
  struct Attachment {
    bool new_node = false;
    Eigen::Isometry3d node_T_body = Eigen::Isometry3d::Identity();
    bool compensated = false;
    Matrix6d compensation = Matrix6d::Zero();
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  Result<Attachment> attach(double t, const Eigen::Isometry3d& odom_T_body, const OdometryHistory& history) const;
  /// Records the new node of `attachment` (after the observation was found usable).
  void recordNode(const Attachment& attachment, double t, const Eigen::Isometry3d& odom_T_body,
                  const OdometryHistory& history);
  /// Vertex ids, chosen so that increasing id (the linear system's order) is a good elimination order.
  struct VertexIds {
    std::vector<int> node;               ///< per node: its vertex, or `keyframe` for a node at the keyframe instant
    std::vector<int> gates;              ///< the gate ids, in order of first observation
    std::vector<int> gate_vertex;        ///< per entry of `gates`: its vertex
    std::vector<int> gate_observations;  ///< per entry of `gates`: its number of observations
    std::vector<int> entry;              ///< per record: its gate's entry in `gates`, or −1 when unanchored
    int keyframe = 0;                    ///< the fixed keyframe, after every free vertex
  };
  /// Nodes in time order, each gate right after the last node that observes it (so at most the gates
  /// still in view are coupled to a node while the chain is eliminated), then the keyframe.
  VertexIds assignVertexIds(double t_keyframe) const;
  /// Builds the graph into `problem_` (nodes, fixed keyframe, gates, odometry and detection edges) with the
  /// vertex ids `ids` (assignVertexIds); fills `result`'s sizes.
  Status buildProblem(double t_keyframe, const Eigen::Isometry3d& odom_T_keyframe, const OdometryHistory& history,
                      const VertexIds& ids, DistillationResult& result);
  OptimizerParams lmParams() const;
  using GatePoses = std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>>;
  /// Optimises `problem_` and appends each gate vertex's marginal covariance (or why it has none) to
  /// `covariances` and its optimised estimate (odom_T_gate; a point's translation) to `gate_estimates`:
  /// with the generic Optimizer and MarginalCovariance on a copy as a Graph (temp_solver: graph, or CHOLMOD) …
  Status optimizeWithGraph(const std::vector<int>& gate_vertices, std::vector<Result<Eigen::MatrixXd>>& covariances,
                           GatePoses& gate_estimates, DistillationResult& result) const;
  /// … or with the block solver (temp_solver: block) on `problem_` itself.
  Status optimizeWithBlocks(const std::vector<int>& gate_vertices, std::vector<Result<Eigen::MatrixXd>>& covariances,
                            GatePoses& gate_estimates, DistillationResult& result);

  /// The per-metre model of params_ under odometry_scale_.
  OdometryNoiseModel noiseModel() const;

  const LocalizerParams params_;
  OdometryNoiseScale odometry_scale_;
  std::shared_ptr<const RobustKernel> kernel_;
  std::vector<Node, Eigen::aligned_allocator<Node>> nodes_;
  /// The interval's observations at their nodes, in time order (ObservationModel::attach).
  std::vector<AttachedObservation, Eigen::aligned_allocator<AttachedObservation>> records_;
  TemporaryPool problem_;  ///< the vertices and edges of the graph being distilled, reused between keyframes
  BlockLmSolver solver_;    ///< work buffers of the block solver, reused between keyframes
};

}  // namespace dualgraph
