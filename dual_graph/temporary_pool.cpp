// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/temporary_pool.h"

#include <string>

#include "dualgraph/dual_graph/edge_factories.h"

namespace dualgraph {

void TemporaryPool::clear() {
  poses_used_ = points_used_ = pose_edges_used_ = point_edges_used_ = corner_edges_used_ = 0;
  for (auto& other : other_edges_) other.second->used = 0;
  vertices_.clear();
  edges_.clear();
}

template <typename T>
T* TemporaryPool::next(std::vector<std::unique_ptr<T>>& pool, size_t& used) {
  if (used == pool.size()) pool.push_back(std::make_unique<T>());
  return pool[used++].get();
}

Status TemporaryPool::placeVertex(int id, VertexBase* vertex) {
  if (id < 0) return Status(StatusCode::kInvalidArgument, "temporary problem: negative vertex id");
  if (static_cast<size_t>(id) >= vertices_.size()) vertices_.resize(static_cast<size_t>(id) + 1, nullptr);
  if (vertices_[id] != nullptr) {
    return Status(StatusCode::kInvalidArgument, "temporary problem: vertex " + std::to_string(id) + " added twice");
  }
  vertices_[id] = vertex;
  return Status();
}

VertexBase* TemporaryPool::vertexAt(int id) const {
  return id >= 0 && static_cast<size_t>(id) < vertices_.size() ? vertices_[id] : nullptr;
}

Status TemporaryPool::addPose(int id, const Eigen::Isometry3d& odom_T_body, bool fixed) {
  VertexSE3* vertex = next(poses_, poses_used_);
  vertex->setId(id);
  vertex->reset(odom_T_body);
  vertex->setFixed(fixed);
  return placeVertex(id, vertex);
}

Status TemporaryPool::addGate(int id, LandmarkModel model, const Eigen::Isometry3d& odom_T_gate) {
  if (model == LandmarkModel::kPose) return addPose(id, odom_T_gate, false);
  VertexPointXYZ* vertex = next(points_, points_used_);
  vertex->setId(id);
  vertex->setEstimate(odom_T_gate.translation());
  vertex->setFixed(false);
  return placeVertex(id, vertex);
}

namespace {

/// Connects slot `slot` of `edge` unless it already holds `vertex` (a reused edge often does; setVertex
/// checks the type with a dynamic_cast).
Status connect(EdgeBase& edge, size_t slot, VertexBase* vertex, int id) {
  if (vertex == nullptr) return Status(StatusCode::kNotFound, "no vertex with id " + std::to_string(id));
  return edge.vertex(slot) == vertex ? Status() : edge.setVertex(slot, vertex);
}

void setKernel(EdgeBase& edge, const std::shared_ptr<const RobustKernel>& kernel) {
  if (edge.robustKernel() != kernel.get()) edge.setRobustKernel(kernel);
}

}  // namespace

Status TemporaryPool::addPoseEdge(int from, int to, const Eigen::Isometry3d& from_T_to,
                                     const Matrix6d& information_g2o) {
  return addSe3Edge(from, to, from_T_to, information_g2o, nullptr);
}

Status TemporaryPool::addSe3Edge(int from, int to, const Eigen::Isometry3d& from_T_to, const Matrix6d& information_g2o,
                                    const std::shared_ptr<const RobustKernel>& kernel) {
  if (from == to) return Status(StatusCode::kInvalidArgument, "temporary problem: edge from a vertex to itself");
  EdgeSE3* edge = next(pose_edges_, pose_edges_used_);
  DG_RETURN_IF_ERROR(connect(*edge, 0, vertexAt(from), from));
  DG_RETURN_IF_ERROR(connect(*edge, 1, vertexAt(to), to));
  edge->setMeasurement(from_T_to);
  edge->setInformation(information_g2o);
  setKernel(*edge, kernel);
  edges_.push_back(edge);
  return Status();
}

Status TemporaryPool::addGateEdge(int node, int gate, const GateEdgeMeasurement& measurement,
                                     const std::shared_ptr<const RobustKernel>& kernel) {
  if (measurement.model == LandmarkModel::kPose) {
    return addSe3Edge(node, gate, measurement.node_T_gate, measurement.pose_information, kernel);
  }
  EdgeSE3PointXYZ* edge = next(point_edges_, point_edges_used_);
  DG_RETURN_IF_ERROR(connect(*edge, 0, vertexAt(node), node));
  DG_RETURN_IF_ERROR(connect(*edge, 1, vertexAt(gate), gate));
  edge->setMeasurement(measurement.p_node);
  edge->setInformation(measurement.point_information);
  setKernel(*edge, kernel);
  edges_.push_back(edge);
  return Status();
}

Status TemporaryPool::addCornerEdge(int node, int gate, const Eigen::Isometry3d& node_T_camera,
                                    const Eigen::Vector3d& p_gate, const Eigen::Vector2d& normalized,
                                    const Eigen::Matrix2d& information,
                                    const std::shared_ptr<const RobustKernel>& kernel) {
  if (node == gate) return Status(StatusCode::kInvalidArgument, "temporary problem: edge from a vertex to itself");
  EdgeSE3CornerProjection* edge = next(corner_edges_, corner_edges_used_);
  DG_RETURN_IF_ERROR(connect(*edge, 0, vertexAt(node), node));
  DG_RETURN_IF_ERROR(connect(*edge, 1, vertexAt(gate), gate));
  edge->setCamera(0, node_T_camera);
  edge->setPoint(p_gate);
  edge->setMeasurement(normalized);
  edge->setInformation(information);
  setKernel(*edge, kernel);
  edges_.push_back(edge);
  return Status();
}

Status TemporaryPool::placeEdge(EdgeBase& edge, std::initializer_list<int> ids,
                                const std::shared_ptr<const RobustKernel>& kernel) {
  if (ids.size() != edge.numVertices()) {
    return Status(StatusCode::kInvalidArgument, "temporary problem: an edge with " + std::to_string(edge.numVertices()) +
                                                    " vertices given " + std::to_string(ids.size()) + " ids");
  }
  size_t slot = 0;
  for (int id : ids) DG_RETURN_IF_ERROR(connect(edge, slot++, vertexAt(id), id));
  setKernel(edge, kernel);
  edges_.push_back(&edge);
  return Status();
}

Eigen::Isometry3d gatePoseOf(const VertexBase* vertex) {
  Eigen::Isometry3d odom_T_gate = Eigen::Isometry3d::Identity();
  if (const auto* pose = dynamic_cast<const VertexSE3*>(vertex)) return pose->estimate();
  if (const auto* point = dynamic_cast<const VertexPointXYZ*>(vertex)) odom_T_gate.translation() = point->estimate();
  return odom_T_gate;
}

Eigen::Isometry3d TemporaryPool::gateEstimate(int id) const { return gatePoseOf(vertexAt(id)); }

Status TemporaryPool::copyTo(Graph& graph, const std::shared_ptr<const RobustKernel>& kernel) const {
  for (const VertexBase* vertex : vertices_) {
    if (vertex == nullptr) continue;
    if (const auto* pose = dynamic_cast<const VertexSE3*>(vertex)) {
      auto copy = std::make_unique<VertexSE3>(pose->id());
      copy->setEstimate(pose->estimate());
      copy->setFixed(pose->fixed());
      DG_RETURN_IF_ERROR(graph.addVertex(std::move(copy)));
    } else {
      auto copy = std::make_unique<VertexPointXYZ>(vertex->id());
      copy->setEstimate(static_cast<const VertexPointXYZ*>(vertex)->estimate());
      copy->setFixed(vertex->fixed());
      DG_RETURN_IF_ERROR(graph.addVertex(std::move(copy)));
    }
  }
  for (const EdgeBase* edge : edges_) {
    if (dynamic_cast<const EdgeSE3*>(edge) == nullptr && dynamic_cast<const EdgeSE3PointXYZ*>(edge) == nullptr &&
        dynamic_cast<const EdgeSE3CornerProjection*>(edge) == nullptr) {
      return Status(StatusCode::kFailedPrecondition,
                    "temporary problem: an edge on vertex " + std::to_string(edge->vertex(0)->id()) +
                        " is of a type copyTo does not copy (EdgeSE3, EdgeSE3PointXYZ, EdgeSE3CornerProjection only): "
                        "use temp_solver: block, or add its copy to TemporaryPool::copyTo");
    }
    const int from = edge->vertex(0)->id();
    const int to = edge->vertex(1)->id();
    EdgeBase* copy = nullptr;
    if (const auto* pose_edge = dynamic_cast<const EdgeSE3*>(edge)) {
      Result<EdgeSE3*> added = addRelativePoseEdge(graph, from, to, pose_edge->measurement(), pose_edge->information());
      if (!added.ok()) return added.status();
      copy = *added;
    } else if (const auto* corner_edge = dynamic_cast<const EdgeSE3CornerProjection*>(edge)) {
      auto corner = std::make_unique<EdgeSE3CornerProjection>();
      corner->setCamera(corner_edge->parameterId(), corner_edge->camera());
      corner->setPoint(corner_edge->point());
      corner->setMeasurement(corner_edge->measurement());
      corner->setInformation(corner_edge->information());
      for (size_t slot = 0; slot < 2; ++slot) DG_RETURN_IF_ERROR(corner->setVertex(slot, graph.vertex(slot == 0 ? from : to)));
      Result<EdgeBase*> added = graph.addEdge(std::move(corner));
      if (!added.ok()) return added.status();
      copy = *added;
    } else {
      const auto* point_edge = static_cast<const EdgeSE3PointXYZ*>(edge);
      Result<EdgeSE3PointXYZ*> added =
          addPointObservationEdge(graph, from, to, point_edge->measurement(), point_edge->information());
      if (!added.ok()) return added.status();
      copy = *added;
    }
    if (edge->robustKernel() != nullptr) {
      if (edge->robustKernel() != kernel.get()) {
        return Status(StatusCode::kInvalidArgument, "temporary problem: an edge has a kernel other than the one given");
      }
      copy->setRobustKernel(kernel);
    }
  }
  return Status();
}

}  // namespace dualgraph
