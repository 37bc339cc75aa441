// SPDX-License-Identifier: MIT
// TemporaryPool: the temporary graph's vertices and edges, reused between keyframes.
#pragma once

#include <Eigen/Geometry>
#include <initializer_list>
#include <memory>
#include <typeindex>
#include <utility>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/dual_graph/gate_edge.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_corner_projection.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {

/// A gate vertex's estimate as an odom_T_gate: a VertexSE3's pose, a VertexPointXYZ's position with the
/// identity rotation; the identity for anything else (null included).
Eigen::Isometry3d gatePoseOf(const VertexBase* vertex);

/// The vertices and edges of one temporary graph (TemporaryGraph::distil), kept between keyframes: `clear`
/// marks every object unused and the `add*` calls hand them out again, so a distillation builds its graph
/// without allocating once the largest interval has been seen (a `Graph` allocates every vertex, edge and
/// map node). Vertices are VertexSE3 (poses in the odometry frame, `odom_T_body`; gates `odom_T_gate`) or
/// VertexPointXYZ (gate centres `p_odom`, m); edges EdgeSE3 (information in g2o units), EdgeSE3PointXYZ
/// (m⁻²) or EdgeSE3CornerProjection (a partial gate's corner), as the dual graph's factories build them (dual_graph/edge_factories.h). Vertex ids must be
/// 0 … numVertices()−1, each added once (TemporaryGraph assigns them so). `copyTo` builds the same graph as a
/// `Graph` for the generic Optimizer (`temp_solver: graph`, the oracle).
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class TemporaryPool {
 public:
  /// Forgets the graph; the objects are kept for the next one.
  void clear();

  /// Adds pose vertex `id` (odom_T_body), fixed or free. kInvalidArgument for a negative or repeated id.
  Status addPose(int id, const Eigen::Isometry3d& odom_T_body, bool fixed);
  /// Adds gate vertex `id`: a VertexSE3 at odom_T_gate (kPose) or a VertexPointXYZ at its translation (kPoint).
  Status addGate(int id, LandmarkModel model, const Eigen::Isometry3d& odom_T_gate);
  /// Adds the EdgeSE3 from → to with measurement from_T_to and information in g2o units.
  Status addPoseEdge(int from, int to, const Eigen::Isometry3d& from_T_to, const Matrix6d& information_g2o);
  /// Adds the edge node → gate of `measurement` (as addGateEdge in gate_edge.h), with `kernel` (may be null).
  Status addGateEdge(int node, int gate, const GateEdgeMeasurement& measurement,
                     const std::shared_ptr<const RobustKernel>& kernel);

  /// Adds the EdgeSE3CornerProjection node → gate (both VertexSE3): the camera at `node_T_camera` sees the gate's
  /// corner `p_gate` at normalised image coordinates `normalized`, information in their units⁻².
  Status addCornerEdge(int node, int gate, const Eigen::Isometry3d& node_T_camera, const Eigen::Vector3d& p_gate,
                       const Eigen::Vector2d& normalized, const Eigen::Matrix2d& information,
                       const std::shared_ptr<const RobustKernel>& kernel);

  /// An edge of a type without a slot above (a new detection type's; dual_graph/README.md, "Add a detection
  /// type"): one of the pool's `Edge` objects (default-constructed at first use, reused after `clear`),
  /// connected to the vertices `ids` in slot order and given `kernel` (may be null); the caller sets its
  /// measurement and information. kNotFound for an id not added, kInvalidArgument for a vertex of the wrong
  /// type. The block solver optimises it like any other; `copyTo` does not copy it (kFailedPrecondition).
  template <typename Edge>
  Result<Edge*> addEdgeOfType(std::initializer_list<int> ids, const std::shared_ptr<const RobustKernel>& kernel);

  /// Per id, the vertex (null for an id not added yet).
  const std::vector<VertexBase*>& vertices() const { return vertices_; }
  /// In the order added.
  const std::vector<EdgeBase*>& edges() const { return edges_; }
  /// A gate's estimate as an odom_T_gate (for a point: its translation, identity rotation). Null-safe:
  /// the identity for an id that is not a gate vertex.
  Eigen::Isometry3d gateEstimate(int id) const;

  /// Adds copies of every vertex (id, estimate, fixed) and edge (measurement, information, kernel) to
  /// `graph`, which must not hold those ids. `kernel` is the one every edge with a kernel was given
  /// (kInvalidArgument otherwise): the copies share it.
  Status copyTo(Graph& graph, const std::shared_ptr<const RobustKernel>& kernel) const;

 private:
  /// Hands out the next unused object of `pool`, creating it when all are in use.
  template <typename T>
  static T* next(std::vector<std::unique_ptr<T>>& pool, size_t& used);
  Status placeVertex(int id, VertexBase* vertex);
  VertexBase* vertexAt(int id) const;
  /// addPoseEdge with `kernel` (may be null), set once: a reused edge that keeps its kernel costs no
  /// reference-count traffic.
  Status addSe3Edge(int from, int to, const Eigen::Isometry3d& from_T_to, const Matrix6d& information_g2o,
                    const std::shared_ptr<const RobustKernel>& kernel);

  /// Connects `edge`'s slots to the vertices `ids`, sets `kernel` and lists the edge (addEdgeOfType).
  Status placeEdge(EdgeBase& edge, std::initializer_list<int> ids, const std::shared_ptr<const RobustKernel>& kernel);

  /// The objects of one edge type without a slot (addEdgeOfType).
  struct OtherEdgesBase {
    virtual ~OtherEdgesBase() = default;
    size_t used = 0;
  };
  template <typename Edge>
  struct OtherEdges final : OtherEdgesBase {
    std::vector<std::unique_ptr<Edge>> objects;
  };

  std::vector<std::unique_ptr<VertexSE3>> poses_;
  std::vector<std::unique_ptr<VertexPointXYZ>> points_;
  std::vector<std::unique_ptr<EdgeSE3>> pose_edges_;
  std::vector<std::unique_ptr<EdgeSE3PointXYZ>> point_edges_;
  std::vector<std::unique_ptr<EdgeSE3CornerProjection>> corner_edges_;
  size_t poses_used_ = 0, points_used_ = 0, pose_edges_used_ = 0, point_edges_used_ = 0, corner_edges_used_ = 0;
  std::vector<std::pair<std::type_index, std::unique_ptr<OtherEdgesBase>>> other_edges_;
  std::vector<VertexBase*> vertices_;
  std::vector<EdgeBase*> edges_;
};

template <typename Edge>
Result<Edge*> TemporaryPool::addEdgeOfType(std::initializer_list<int> ids,
                                           const std::shared_ptr<const RobustKernel>& kernel) {
  OtherEdges<Edge>* pool = nullptr;
  for (auto& [type, objects] : other_edges_) {
    if (type == std::type_index(typeid(Edge))) pool = static_cast<OtherEdges<Edge>*>(objects.get());
  }
  if (pool == nullptr) {
    other_edges_.emplace_back(std::type_index(typeid(Edge)), std::make_unique<OtherEdges<Edge>>());
    pool = static_cast<OtherEdges<Edge>*>(other_edges_.back().second.get());
  }
  if (pool->used == pool->objects.size()) pool->objects.push_back(std::make_unique<Edge>());
  Edge* edge = pool->objects[pool->used++].get();
  DG_RETURN_IF_ERROR(placeEdge(*edge, ids, kernel));
  return edge;
}

}  // namespace dualgraph
