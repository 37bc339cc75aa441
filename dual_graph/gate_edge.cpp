// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/gate_edge.h"

#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/observation_model.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

Result<GateEdgeMeasurement> attachObservationToNode(const GateObservation& observation,
                                                    const Eigen::Isometry3d& node_T_body,
                                                    const Matrix6d* node_T_body_covariance, LandmarkModel model) {
  const ObservationModel& kind = observationModel(observation.kind);
  if (!kind.anchorsGate()) {
    return Status(StatusCode::kInvalidArgument,
                  "observation of gate " + std::to_string(observation.gate_id) + ": " + kind.name() +
                      " observations make no gate edge on their own (they join a gate the temporary graph anchors)");
  }
  NodeAttachment at;
  at.node_T_body = node_T_body;
  at.compensation = node_T_body_covariance;
  Result<AttachedObservation> attached = kind.attach(observation, at, model);
  if (!attached.ok()) return attached.status();
  return attached->edge;
}

Result<EdgeBase*> addGateEdge(Graph& graph, int node_id, int gate_vertex_id, const GateEdgeMeasurement& measurement,
                              std::shared_ptr<const RobustKernel> kernel) {
  EdgeBase* edge = nullptr;
  if (measurement.model == LandmarkModel::kPose) {
    Result<EdgeSE3*> added =
        addRelativePoseEdge(graph, node_id, gate_vertex_id, measurement.node_T_gate, measurement.pose_information);
    if (!added.ok()) return added.status();
    edge = *added;
  } else {
    Result<EdgeSE3PointXYZ*> added =
        addPointObservationEdge(graph, node_id, gate_vertex_id, measurement.p_node, measurement.point_information);
    if (!added.ok()) return added.status();
    edge = *added;
  }
  if (kernel) edge->setRobustKernel(std::move(kernel));
  return edge;
}

Status addGateVertex(Graph& graph, int id, LandmarkModel model, const Eigen::Isometry3d& world_T_gate) {
  if (model == LandmarkModel::kPose) {
    auto vertex = std::make_unique<VertexSE3>(id);
    vertex->setEstimate(world_T_gate);
    return graph.addVertex(std::move(vertex));
  }
  auto vertex = std::make_unique<VertexPointXYZ>(id);
  vertex->setEstimate(world_T_gate.translation());
  return graph.addVertex(std::move(vertex));
}

Eigen::Isometry3d gateFromNode(const Eigen::Isometry3d& world_T_node, const GateEdgeMeasurement& measurement) {
  if (measurement.model == LandmarkModel::kPose) return world_T_node * measurement.node_T_gate;
  Eigen::Isometry3d world_T_gate = Eigen::Isometry3d::Identity();
  world_T_gate.translation() = world_T_node * measurement.p_node;
  return world_T_gate;
}

}  // namespace dualgraph
