// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/gate_edge.h"

#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {

Result<GateEdgeMeasurement> attachObservationToNode(const GateObservation& observation,
                                                    const Eigen::Isometry3d& node_T_body,
                                                    const Matrix6d* node_T_body_covariance, LandmarkModel model) {
  const std::string what = "observation of gate " + std::to_string(observation.gate_id);
  GateEdgeMeasurement measurement;
  measurement.gate_id = observation.gate_id;
  measurement.model = model;
  if (observation.kind == ObservationKind::kCorners) {
    return Status(StatusCode::kInvalidArgument,
                  what + ": corner rays are not one gate edge (the temporary graph adds one edge per corner)");
  }
  if (model == LandmarkModel::kPose) {
    if (observation.kind != ObservationKind::kPose) {
      return Status(StatusCode::kInvalidArgument,
                    what + ": a position-only observation cannot constrain an SE(3) gate landmark (landmark: point)");
    }
    measurement.node_T_gate = node_T_body * observation.body_T_gate;
    Matrix6d covariance = observation.pose_covariance;
    if (node_T_body_covariance != nullptr) {
      const Matrix6d adjoint = se3Adjoint(observation.body_T_gate.inverse());
      covariance += adjoint * *node_T_body_covariance * adjoint.transpose();
    }
    Result<Matrix6d> information = poseInformationFromMetricCovariance(covariance, what + ": covariance");
    if (!information.ok()) return information.status();
    measurement.pose_information = *information;
    measurement.p_node = measurement.node_T_gate.translation();
    return measurement;
  }
  const Eigen::Vector3d p_body = observation.centreInBody();
  const Eigen::Matrix3d rotation = node_T_body.linear();
  Eigen::Matrix3d covariance = rotation * observation.centreCovarianceInBody() * rotation.transpose();
  if (node_T_body_covariance != nullptr) {
    Eigen::Matrix<double, 3, 6> J;
    J << rotation, -rotation * skew(p_body);
    covariance += J * *node_T_body_covariance * J.transpose();
  }
  Result<Eigen::Matrix3d> information = pointInformationFromCovariance(covariance, what + ": position covariance");
  if (!information.ok()) return information.status();
  measurement.p_node = node_T_body * p_body;
  measurement.node_T_gate = Eigen::Isometry3d::Identity();
  measurement.node_T_gate.translation() = measurement.p_node;
  measurement.point_information = *information;
  return measurement;
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
