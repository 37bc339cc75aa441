// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/main_graph.h"

#include <Eigen/Cholesky>
#include <algorithm>

#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/marginal_prior.h"
#include "dualgraph/types/se3_covariance.h"
#include "dualgraph/solvers/marginal_covariance.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

Matrix6d diagonalPoseCovariance(double sigma_t, double sigma_r) {
  Vector6d variances;
  variances << Eigen::Vector3d::Constant(sigma_t * sigma_t), Eigen::Vector3d::Constant(sigma_r * sigma_r);
  return variances.asDiagonal();
}

}  // namespace

MainGraph::MainGraph(const LocalizerParams& params, const GateMap& map, std::shared_ptr<const RobustKernel> kernel)
    : params_(params), map_(map), kernel_(std::move(kernel)), optimizer_(graph_, makeLinearSolver(params.linear_solver)) {}

const Eigen::Isometry3d& MainGraph::keyframePose(size_t index) const {
  const Keyframe& keyframe = keyframes_.at(index);
  if (keyframe.marginalized) return keyframe.frozen_pose;
  return graph_.vertexAs<VertexSE3>(keyframe.vertex_id)->estimate();
}

int MainGraph::landmarkVertex(int gate_id) const {
  const auto found = landmark_vertex_.find(gate_id);
  return found == landmark_vertex_.end() ? -1 : found->second;
}

Status MainGraph::addFirstKeyframe(double t, const Eigen::Isometry3d& odom_T_body) {
  if (!keyframes_.empty()) return Status(StatusCode::kFailedPrecondition, "main graph: first keyframe added twice");
  const bool fixed = params_.mapping || params_.initial_sigma_t <= 0.0;
  // Nothing changes on an error: the prior's information is checked before the vertex goes in, and the vertex
  // leaves again when its prior cannot join it.
  Result<Matrix6d> information = Matrix6d(Matrix6d::Zero());
  if (!fixed) {
    information = poseInformationFromMetricCovariance(
        diagonalPoseCovariance(params_.initial_sigma_t, params_.initial_sigma_r), "initial pose prior");
    if (!information.ok()) return information.status();
  }
  const int id = next_vertex_id_;
  auto vertex = std::make_unique<VertexSE3>(id);
  const Eigen::Isometry3d world_T_body = params_.initial_world_T_odom * odom_T_body;
  vertex->setEstimate(world_T_body);
  vertex->setFixed(fixed);
  DG_RETURN_IF_ERROR(graph_.addVertex(std::move(vertex)));
  if (!fixed) {
    Result<EdgeSE3Prior*> prior = addPosePriorEdge(graph_, id, world_T_body, *information);
    if (!prior.ok()) {
      (void)graph_.removeVertex(id);
      return prior.status();
    }
  }
  ++next_vertex_id_;
  keyframes_.push_back(Keyframe{id, t, odom_T_body});
  return Status();
}

Status MainGraph::addKeyframe(double t, const Eigen::Isometry3d& odom_T_body, const Matrix6d& increment_covariance) {
  if (keyframes_.empty()) return Status(StatusCode::kFailedPrecondition, "main graph: no first keyframe");
  const Keyframe& previous = keyframes_.back();
  const Eigen::Isometry3d increment = previous.odom_T_body.inverse() * odom_T_body;
  Result<Matrix6d> information = poseInformationFromMetricCovariance(
      scaledOdometryCovariance(increment_covariance, odometry_scale_), "odometry covariance");
  if (!information.ok()) return information.status();
  const int id = next_vertex_id_++;
  auto vertex = std::make_unique<VertexSE3>(id);
  vertex->setEstimate(keyframePose(keyframes_.size() - 1) * increment);
  DG_RETURN_IF_ERROR(graph_.addVertex(std::move(vertex)));
  Result<EdgeSE3*> edge = addRelativePoseEdge(graph_, previous.vertex_id, id, increment, *information);
  if (!edge.ok()) {
    (void)graph_.removeVertex(id);
    return edge.status();
  }
  keyframes_.push_back(Keyframe{id, t, odom_T_body});
  odometry_edges_.push_back(OdometryEdge{keyframes_.size() - 1, *edge, increment_covariance});
  return Status();
}

Status MainGraph::setOdometryScale(const OdometryNoiseScale& scale) {
  odometry_scale_ = scale;
  // An edge leaves the graph (folded into a prior) when either keyframe it joins is marginalised, oldest first.
  const auto gone = std::find_if(odometry_edges_.begin(), odometry_edges_.end(), [this](const OdometryEdge& entry) {
    return !keyframes_[entry.keyframe].marginalized && !keyframes_[entry.keyframe - 1].marginalized;
  });
  odometry_edges_.erase(odometry_edges_.begin(), gone);
  for (const OdometryEdge& entry : odometry_edges_) {
    Result<Matrix6d> information = poseInformationFromMetricCovariance(
        scaledOdometryCovariance(entry.base_covariance, scale), "odometry covariance");
    if (!information.ok()) return information.status();
    entry.edge->setInformation(*information);
  }
  return Status();
}

Result<int> MainGraph::findOrCreateLandmark(int gate_id, size_t keyframe_index, const GateEdgeMeasurement& measurement,
                                            bool& constrained) {
  constrained = true;
  const int existing = landmarkVertex(gate_id);
  if (existing >= 0) return existing;
  const int id = next_vertex_id_;
  if (params_.mapping) {
    constrained = false;  // nothing to disagree with yet
    DG_RETURN_IF_ERROR(
        addGateVertex(graph_, id, params_.landmark, gateFromNode(keyframePose(keyframe_index), measurement)));
  } else {
    const auto in_map = map_.world_T_gate.find(gate_id);
    if (in_map == map_.world_T_gate.end()) {
      return Status(StatusCode::kNotFound, "gate " + std::to_string(gate_id) + " is not in the map");
    }
    // Nothing changes on an error: the prior's information is checked first, and the gate's vertex leaves again
    // when its prior cannot join it (a later sighting then meets the same error, not a duplicate vertex id).
    Result<Matrix6d> pose_information = Matrix6d(Matrix6d::Zero());
    Result<Eigen::Matrix3d> point_information = Eigen::Matrix3d(Eigen::Matrix3d::Zero());
    if (!params_.fix_map_gates && params_.landmark == LandmarkModel::kPose) {
      pose_information = poseInformationFromMetricCovariance(
          diagonalPoseCovariance(params_.map_sigma_t, params_.map_sigma_r), "gate map prior");
      if (!pose_information.ok()) return pose_information.status();
    } else if (!params_.fix_map_gates) {
      point_information = pointInformationFromCovariance(
          Eigen::Matrix3d::Identity() * (params_.map_sigma_t * params_.map_sigma_t), "gate map prior");
      if (!point_information.ok()) return point_information.status();
    }
    DG_RETURN_IF_ERROR(addGateVertex(graph_, id, params_.landmark, in_map->second));
    Status held;
    if (params_.fix_map_gates) {
      held = graph_.setFixed(id, true);
    } else if (params_.landmark == LandmarkModel::kPose) {
      held = addPosePriorEdge(graph_, id, in_map->second, *pose_information).status();
    } else {
      held = addPointPriorEdge(graph_, id, in_map->second.translation(), *point_information).status();
    }
    if (!held.ok()) {
      (void)graph_.removeVertex(id);
      return held;
    }
  }
  ++next_vertex_id_;
  landmark_vertex_.emplace(gate_id, id);
  return id;
}

double MainGraph::gateThreshold() const {
  return params_.landmark == LandmarkModel::kPose ? params_.chi2_gate_pose : params_.chi2_gate_point;
}

double MainGraph::innovationChi2(EdgeBase& edge, const Eigen::MatrixXd& joint_covariance) {
  edge.linearize();
  const int rows = edge.errorDim();
  const int d0 = edge.vertex(0)->tangentDim();
  const int d1 = edge.vertex(1)->tangentDim();
  Eigen::MatrixXd J(rows, d0 + d1);
  J.leftCols(d0) = Eigen::Map<const Eigen::MatrixXd>(edge.jacobianData(0), rows, d0);
  J.rightCols(d1) = Eigen::Map<const Eigen::MatrixXd>(edge.jacobianData(1), rows, d1);
  const Eigen::Map<const Eigen::MatrixXd> information(edge.informationData(), rows, rows);
  const Eigen::MatrixXd S = J * joint_covariance * J.transpose() +
                            information.llt().solve(Eigen::MatrixXd::Identity(rows, rows));
  const Eigen::Map<const Eigen::VectorXd> error(edge.errorData(), rows);
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (S + S.transpose()));
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return error.dot(llt.solve(error));
}

Status MainGraph::predictJointCovariances(int keyframe_id, const std::vector<int>& landmark,
                                          const std::vector<EdgeBase*>& edges, std::vector<Eigen::MatrixXd>& joint) {
  // The new edges are already in (one structure, one symbolic analysis per keyframe); their
  // information is zeroed for this one factorisation, so H is the graph's without them.
  std::vector<Eigen::MatrixXd> saved(edges.size());
  for (size_t k = 0; k < edges.size(); ++k) {
    if (edges[k] == nullptr) continue;
    Eigen::Map<Eigen::MatrixXd> information(edges[k]->mutableInformationData(), edges[k]->errorDim(),
                                            edges[k]->errorDim());
    saved[k] = information;
    information.setZero();
  }
  // One block solve for the keyframe and every gated landmark; offsets of each in the result.
  std::vector<int> ids = {keyframe_id};
  std::vector<int> offsets = {0};
  int total = graph_.vertex(keyframe_id)->tangentDim();
  for (size_t k = 0; k < edges.size(); ++k) {
    if (edges[k] == nullptr || std::find(ids.begin(), ids.end(), landmark[k]) != ids.end()) continue;
    ids.push_back(landmark[k]);
    offsets.push_back(total);
    total += graph_.vertex(landmark[k])->tangentDim();
  }
  MarginalCovariance marginals;
  Status status = marginals.compute(optimizer_, graph_);
  Result<Eigen::MatrixXd> all = status.ok() ? marginals.jointBlock(ids) : Result<Eigen::MatrixXd>(status);
  if (!all.ok()) status = all.status();
  joint.assign(edges.size(), Eigen::MatrixXd());
  for (size_t k = 0; k < edges.size(); ++k) {
    if (edges[k] == nullptr) continue;
    Eigen::Map<Eigen::MatrixXd>(edges[k]->mutableInformationData(), saved[k].rows(), saved[k].cols()) = saved[k];
    if (!status.ok()) continue;
    const size_t slot = static_cast<size_t>(std::find(ids.begin(), ids.end(), landmark[k]) - ids.begin());
    std::vector<int> rows;
    for (int r = 0; r < graph_.vertex(keyframe_id)->tangentDim(); ++r) rows.push_back(r);
    for (int r = 0; r < graph_.vertex(landmark[k])->tangentDim(); ++r) rows.push_back(offsets[slot] + r);
    joint[k] = (*all)(rows, rows);
  }
  return status;
}

GateEdgeOutcome MainGraph::addGateEdges(size_t keyframe_index, const GateEdgeMeasurements& measurements) {
  GateEdgeOutcome outcome;
  auto fail = [&outcome](const Status& status) {
    if (outcome.failed++ == 0) outcome.message = status.message();
  };
  if (measurements.empty()) return outcome;
  const int keyframe_id = keyframes_.at(keyframe_index).vertex_id;
  // 1. Landmarks first, so the marginals below see every vertex the new edges attach to.
  std::vector<int> landmark(measurements.size(), -1);
  std::vector<bool> gated(measurements.size(), false);
  bool any_gated = false;
  for (size_t k = 0; k < measurements.size(); ++k) {
    bool constrained = false;
    Result<int> id = findOrCreateLandmark(measurements[k].gate_id, keyframe_index, measurements[k], constrained);
    if (!id.ok()) {
      fail(id.status());
      continue;
    }
    landmark[k] = *id;
    gated[k] = constrained && gateThreshold() > 0.0;
    any_gated = any_gated || gated[k];
  }
  // 2. All edges in at once, so the structure (and CHOLMOD's symbolic analysis) is rebuilt once.
  std::vector<EdgeBase*> edges(measurements.size(), nullptr);
  for (size_t k = 0; k < measurements.size(); ++k) {
    if (landmark[k] < 0) continue;
    Result<EdgeBase*> edge = addGateEdge(graph_, keyframe_id, landmark[k], measurements[k], kernel_);
    if (!edge.ok()) {
      fail(edge.status());
      continue;
    }
    edges[k] = *edge;
  }
  // 3. The χ² gate against the graph without the gated edges.
  std::vector<EdgeBase*> to_gate(measurements.size(), nullptr);
  for (size_t k = 0; k < measurements.size(); ++k) to_gate[k] = gated[k] ? edges[k] : nullptr;
  std::vector<Eigen::MatrixXd> joint;
  if (any_gated) {
    const Status predicted = predictJointCovariances(keyframe_id, landmark, to_gate, joint);
    if (!predicted.ok()) {  // cannot judge: keep the edges ungated, say so
      std::fill(to_gate.begin(), to_gate.end(), nullptr);
      if (outcome.message.empty()) outcome.message = "chi2 gate not applied: " + predicted.message();
    }
  }
  for (size_t k = 0; k < measurements.size(); ++k) {
    if (edges[k] == nullptr) continue;
    if (to_gate[k] != nullptr && !(innovationChi2(*edges[k], joint[k]) <= gateThreshold())) {
      (void)graph_.removeEdge(edges[k]);
      ++outcome.rejected;
      outcome.rejected_observations += measurements[k].observations;
      continue;
    }
    ++outcome.added;
  }
  return outcome;
}

Status MainGraph::slideWindow() {
  if (params_.main_window <= 0) return Status();
  const size_t window = static_cast<size_t>(params_.main_window);
  while (keyframes_.size() - first_free_keyframe_ > window) {
    const int id = keyframes_[first_free_keyframe_].vertex_id;
    if (!graph_.vertex(id)->fixed()) {
      Result<MarginalizationOutcome> outcome = marginalize_(graph_, id);
      if (!outcome.ok()) {  // condition on it instead: fixed where it is, the window moves on
        Keyframe& keyframe = keyframes_[first_free_keyframe_];
        keyframe.frozen_pose = graph_.vertexAs<VertexSE3>(id)->estimate();
        DG_RETURN_IF_ERROR(graph_.setFixed(id, true));
        ++conditioned_keyframes_;
        last_fallback_ = "main graph: keyframe " + std::to_string(first_free_keyframe_) +
                         " could not be marginalised (" + outcome.status().message() + "): conditioned on instead";
        ++first_free_keyframe_;
        continue;
      }
      folded_edges_ += static_cast<size_t>(outcome->edges_folded - outcome->priors_folded);
      prior_edges_ += (outcome->prior != nullptr ? 1u : 0u);
      prior_edges_ -= static_cast<size_t>(outcome->priors_folded);
      // Out of the graph altogether (it has no edges left), so nothing per update visits it again.
      Keyframe& keyframe = keyframes_[first_free_keyframe_];
      keyframe.frozen_pose = graph_.vertexAs<VertexSE3>(id)->estimate();
      DG_RETURN_IF_ERROR(graph_.removeVertex(id));
      keyframe.marginalized = true;
      ++marginalized_keyframes_;
    }
    ++first_free_keyframe_;
  }
  return Status();
}

Result<Matrix6d> MainGraph::keyframeCovariance(size_t index) {
  if (index >= keyframes_.size() || keyframes_[index].marginalized) {
    return Status(StatusCode::kFailedPrecondition, "keyframe " + std::to_string(index) + " is not in the graph");
  }
  MarginalCovariance marginals;
  DG_RETURN_IF_ERROR(marginals.compute(optimizer_, graph_));
  Result<Eigen::MatrixXd> block = marginals.block(keyframes_[index].vertex_id);
  if (!block.ok()) return block.status();
  return covarianceG2oToMetric(Matrix6d(*block));  // VertexSE3's [δt; δq] chart, right perturbation
}

SolverSummary MainGraph::optimize() {
  OptimizerParams lm;
  lm.max_iterations = params_.main_max_iterations;
  lm.time_budget_ms = params_.main_time_budget_ms;
  lm.relative_decrease_stop = params_.main_relative_decrease_stop;
  lm.damping = params_.lm_damping;
  return optimizer_.optimize(lm);
}

}  // namespace dualgraph
