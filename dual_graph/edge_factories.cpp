// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/edge_factories.h"


namespace dualgraph {
namespace {

/// Connects `edge` to the vertices `ids` (slot order) and stores it in the graph.
template <typename EdgeT>
Result<EdgeT*> connectAndAdd(Graph& graph, std::unique_ptr<EdgeT> edge, std::initializer_list<int> ids) {
  size_t slot = 0;
  for (const int id : ids) {
    VertexBase* vertex = graph.vertex(id);
    if (vertex == nullptr) return Status(StatusCode::kNotFound, "no vertex with id " + std::to_string(id));
    DG_RETURN_IF_ERROR(edge->setVertex(slot++, vertex));
  }
  Result<EdgeBase*> stored = graph.addEdge(std::move(edge));
  if (!stored.ok()) return stored.status();
  return static_cast<EdgeT*>(*stored);
}

}  // namespace

Result<EdgeSE3*> addRelativePoseEdge(Graph& graph, int from_id, int to_id, const Eigen::Isometry3d& from_T_to,
                                     const Matrix6d& information_g2o) {
  auto edge = std::make_unique<EdgeSE3>();
  edge->setMeasurement(from_T_to);
  edge->setInformation(information_g2o);
  return connectAndAdd(graph, std::move(edge), {from_id, to_id});
}

Result<EdgeSE3Prior*> addPosePriorEdge(Graph& graph, int id, const Eigen::Isometry3d& world_T_x,
                                       const Matrix6d& information_g2o) {
  auto edge = std::make_unique<EdgeSE3Prior>();
  edge->setMeasurement(world_T_x);
  edge->setInformation(information_g2o);
  return connectAndAdd(graph, std::move(edge), {id});
}

Result<EdgeSE3PointXYZ*> addPointObservationEdge(Graph& graph, int pose_id, int point_id,
                                                 const Eigen::Vector3d& p_pose, const Eigen::Matrix3d& information) {
  auto edge = std::make_unique<EdgeSE3PointXYZ>();
  edge->setMeasurement(p_pose);
  edge->setInformation(information);
  return connectAndAdd(graph, std::move(edge), {pose_id, point_id});
}

Result<EdgePointXYZPrior*> addPointPriorEdge(Graph& graph, int point_id, const Eigen::Vector3d& p_world,
                                             const Eigen::Matrix3d& information) {
  auto edge = std::make_unique<EdgePointXYZPrior>();
  edge->setMeasurement(p_world);
  edge->setInformation(information);
  return connectAndAdd(graph, std::move(edge), {point_id});
}

}  // namespace dualgraph
