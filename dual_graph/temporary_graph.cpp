// SPDX-License-Identifier: MIT
#include "dualgraph/dual_graph/temporary_graph.h"

#include <algorithm>

#include "dualgraph/core/optimizer.h"
#include "dualgraph/core/wall_clock.h"
#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/systematic_floor.h"
#include "dualgraph/types/se3_covariance.h"
#include "dualgraph/solvers/eigen_solver.h"
#include "dualgraph/solvers/marginal_covariance.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {

OdometryNoiseModel TemporaryGraph::noiseModel() const {
  OdometryNoiseModel model = noiseModelOf(params_);
  model.scale = odometry_scale_;
  return model;
}

TemporaryGraph::TemporaryGraph(const LocalizerParams& params, std::shared_ptr<const RobustKernel> kernel)
    : params_(params), kernel_(std::move(kernel)) {}

void TemporaryGraph::clear() {
  nodes_.clear();
  records_.clear();
}

Result<TemporaryGraph::Attachment> TemporaryGraph::attach(double t, const Eigen::Isometry3d& odom_T_body,
                                                          const OdometryHistory& history) const {
  if (!nodes_.empty() && t < nodes_.back().t) {
    return Status(StatusCode::kFailedPrecondition, "temporary graph: observation older than its newest node");
  }
  Attachment attachment;
  attachment.new_node = nodes_.empty();
  if (!attachment.new_node) {
    const Eigen::Isometry3d increment = nodes_.back().odom_T_body.inverse() * odom_T_body;
    attachment.new_node = incrementExceeds(increment, params_.d_temp, params_.theta_temp);
  }
  if (attachment.new_node) return attachment;  // at the node itself: no motion to compensate
  const Node& node = nodes_.back();
  attachment.node_T_body = node.odom_T_body.inverse() * odom_T_body;
  attachment.compensated = t > node.t;
  if (attachment.compensated) {
    Result<Matrix6d> covariance = history.relativeCovariance(node.t, t, noiseModel());
    if (!covariance.ok()) return covariance.status();
    attachment.compensation = *covariance;
  }
  return attachment;
}

void TemporaryGraph::recordNode(const Attachment& attachment, double t, const Eigen::Isometry3d& odom_T_body,
                                const OdometryHistory& history) {
  if (!attachment.new_node) return;
  if (!nodes_.empty()) nodes_.back().information_to_next = odometryInformation(nodes_.back().t, t, history);
  nodes_.push_back(Node{t, odom_T_body, Matrix6d(Matrix6d::Zero())});
}

Status TemporaryGraph::addObservation(const GateObservation& observation, const Eigen::Isometry3d& odom_T_body,
                                      const OdometryHistory& history) {
  Result<Attachment> attachment = attach(observation.t, odom_T_body, history);
  if (!attachment.ok()) return attachment.status();
  NodeAttachment at;
  at.node_T_body = attachment->node_T_body;
  at.compensation = attachment->compensated ? &attachment->compensation : nullptr;
  const ObservationModel& model = observationModel(observation.kind);
  Result<AttachedObservation> attached = model.attach(observation, at, params_.landmark);
  if (!attached.ok()) return attached.status();
  recordNode(*attachment, observation.t, odom_T_body, history);
  attached->node = nodes_.size() - 1;
  records_.push_back(*attached);
  return Status();
}

Result<Matrix6d> TemporaryGraph::odometryInformation(double t_from, double t_to, const OdometryHistory& history) const {
  Result<Matrix6d> covariance = history.relativeCovariance(t_from, t_to, noiseModel());
  if (!covariance.ok()) return covariance.status();
  return poseInformationFromMetricCovariance(*covariance, "temporary odometry covariance");
}

TemporaryGraph::VertexIds TemporaryGraph::assignVertexIds(double t_keyframe) const {
  VertexIds ids;
  std::vector<size_t> last_node;  // per gate entry: the last node observing it
  ids.entry.assign(records_.size(), -1);
  // Gates in order of their first anchoring observation; the other kinds join the entry of their gate, or stay
  // out (unanchored).
  for (const bool anchoring : {true, false}) {
    for (size_t k = 0; k < records_.size(); ++k) {
      const AttachedObservation& record = records_[k];
      if (observationModel(record.kind).anchorsGate() != anchoring) continue;
      const auto found = std::find(ids.gates.begin(), ids.gates.end(), record.gate_id);
      if (found == ids.gates.end() && !anchoring) continue;
      const size_t entry = static_cast<size_t>(found - ids.gates.begin());
      if (found == ids.gates.end()) {
        ids.gates.push_back(record.gate_id);
        ids.gate_observations.push_back(0);
        last_node.push_back(record.node);
      }
      ids.entry[k] = static_cast<int>(entry);
      ++ids.gate_observations[entry];
      last_node[entry] = std::max(last_node[entry], record.node);
    }
  }
  // The gates each node is the last to observe, in increasing gate id: entries by (last node, gate id).
  std::vector<int> closing(ids.gates.size());
  for (size_t e = 0; e < closing.size(); ++e) closing[e] = static_cast<int>(e);
  std::sort(closing.begin(), closing.end(), [&](int a, int b) {
    return last_node[a] != last_node[b] ? last_node[a] < last_node[b] : ids.gates[a] < ids.gates[b];
  });
  ids.node.assign(nodes_.size(), -1);
  ids.gate_vertex.assign(ids.gates.size(), -1);
  int next = 0;
  std::vector<int> at_keyframe;  // gates last seen from the fixed keyframe: after every node
  size_t c = 0;
  for (size_t j = 0; j < nodes_.size(); ++j) {
    const bool free = nodes_[j].t < t_keyframe;
    if (free) ids.node[j] = next++;
    for (; c < closing.size() && last_node[closing[c]] == j; ++c) {
      if (free) {
        ids.gate_vertex[closing[c]] = next++;
      } else {
        at_keyframe.push_back(closing[c]);
      }
    }
  }
  for (int entry : at_keyframe) ids.gate_vertex[entry] = next++;
  // The fixed keyframe after the free vertices, on purpose: block lookup must not assume it comes first.
  ids.keyframe = next;
  for (int& vertex : ids.node) vertex = vertex < 0 ? ids.keyframe : vertex;
  return ids;
}

Status TemporaryGraph::buildProblem(double t_keyframe, const Eigen::Isometry3d& odom_T_keyframe,
                                    const OdometryHistory& history, const VertexIds& ids, DistillationResult& result) {
  problem_.clear();
  const int keyframe_id = ids.keyframe;
  DG_RETURN_IF_ERROR(problem_.addPose(keyframe_id, odom_T_keyframe, true));
  // Node j is its own vertex, or the keyframe itself when it was taken at the keyframe instant.
  const std::vector<int>& node_vertex = ids.node;
  for (size_t j = 0; j < nodes_.size(); ++j) {
    if (node_vertex[j] == keyframe_id) continue;
    DG_RETURN_IF_ERROR(problem_.addPose(node_vertex[j], nodes_[j].odom_T_body, false));
  }
  // The odometry chain node_0 → … → node_last → K (between nodes, the information is computed when the
  // later node is recorded).
  for (size_t j = 0; j < nodes_.size(); ++j) {
    const int from = node_vertex[j];
    const bool last = j + 1 == nodes_.size();
    const int to = last ? keyframe_id : node_vertex[j + 1];
    if (from == to) continue;
    const Eigen::Isometry3d to_pose = last ? odom_T_keyframe : nodes_[j + 1].odom_T_body;
    const Result<Matrix6d> information =
        last ? odometryInformation(nodes_[j].t, t_keyframe, history) : nodes_[j].information_to_next;
    if (!information.ok()) return information.status();
    DG_RETURN_IF_ERROR(problem_.addPoseEdge(from, to, nodes_[j].odom_T_body.inverse() * to_pose, *information));
  }
  // Gates: created at their first anchoring observation (entries come in that order), then each observation's
  // edges; the anchoring kinds' first, the others' after (those of an unanchored gate counted, not added).
  size_t gates_added = 0;
  for (const bool anchoring : {true, false}) {
    for (size_t k = 0; k < records_.size(); ++k) {
      const AttachedObservation& record = records_[k];
      const ObservationModel& model = observationModel(record.kind);
      if (model.anchorsGate() != anchoring) continue;
      if (ids.entry[k] < 0) {
        ++result.partial_unanchored;
        continue;
      }
      const size_t entry = static_cast<size_t>(ids.entry[k]);
      const int gate_vertex = ids.gate_vertex[entry];
      if (anchoring && entry == gates_added) {
        const Eigen::Isometry3d& odom_T_node =
            node_vertex[record.node] == keyframe_id ? odom_T_keyframe : nodes_[record.node].odom_T_body;
        DG_RETURN_IF_ERROR(problem_.addGate(gate_vertex, params_.landmark, model.anchor(record, odom_T_node)));
        ++gates_added;
      }
      DG_RETURN_IF_ERROR(model.addTemporaryEdges(record, problem_, node_vertex[record.node], gate_vertex, kernel_));
      if (!anchoring) ++result.partial_used;
    }
  }
  result.nodes = static_cast<int>(problem_.vertices().size() - ids.gates.size());
  result.edges = static_cast<int>(problem_.edges().size());
  return Status();
}

OptimizerParams TemporaryGraph::lmParams() const {
  OptimizerParams lm;
  lm.max_iterations = params_.temp_max_iterations;
  lm.relative_decrease_stop = params_.temp_relative_decrease_stop;
  lm.model_decrease_stop = params_.temp_model_decrease_stop;
  lm.damping = params_.lm_damping;
  return lm;
}

namespace {

Status optimizationFailure(const SolverSummary& summary) {
  return Status(StatusCode::kNumericalError, std::string("temporary graph optimisation failed (") +
                                                 terminationReasonName(summary.termination) + "): " + summary.message);
}

}  // namespace

Status TemporaryGraph::optimizeWithGraph(const std::vector<int>& gate_vertices,
                                         std::vector<Result<Eigen::MatrixXd>>& covariances,
                                         GatePoses& gate_estimates,
                                         DistillationResult& result) const {
  Graph graph;
  DG_RETURN_IF_ERROR(problem_.copyTo(graph, kernel_));
  // Eigen in the graph's own order unless CHOLMOD is asked for: the ids (assignVertexIds) already make
  // a good elimination order, which saves AMD's analysis, and each gate's marginal solve only touches
  // the factor from that gate's rows on (EigenOrdering::kNatural, solveColumnsAtRows).
  Optimizer optimizer(graph, params_.linear_solver == LinearSolverKind::kCholmod
                                 ? makeLinearSolver(LinearSolverKind::kCholmod)
                                 : std::make_unique<EigenSolver>(EigenOrdering::kNatural));
  const SolverSummary summary = optimizer.optimize(lmParams());
  result.iterations = summary.iterations;
  if (!summary.usable()) return optimizationFailure(summary);
  MarginalCovariance marginals;
  DG_RETURN_IF_ERROR(marginals.compute(optimizer, graph));
  for (int vertex : gate_vertices) {
    covariances.push_back(marginals.block(vertex));
    gate_estimates.push_back(gatePoseOf(graph.vertex(vertex)));
  }
  return Status();
}

Status TemporaryGraph::optimizeWithBlocks(const std::vector<int>& gate_vertices,
                                          std::vector<Result<Eigen::MatrixXd>>& covariances,
                                          GatePoses& gate_estimates,
                                          DistillationResult& result) {
  DG_RETURN_IF_ERROR(solver_.setProblem(problem_.vertices(), problem_.edges()));
  const SolverSummary summary = solver_.optimize(lmParams());
  result.iterations = summary.iterations;
  if (!summary.usable()) return optimizationFailure(summary);
  DG_RETURN_IF_ERROR(solver_.computeMarginals(gate_vertices));
  for (int vertex : gate_vertices) {
    covariances.push_back(solver_.marginal(vertex));
    gate_estimates.push_back(problem_.gateEstimate(vertex));
  }
  return Status();
}

namespace {

/// The distilled edge's information: the marginal must be usable on its own (a floor never hides a broken
/// one), then the systematic floor is added to it; `before_floor` (when given) gets the information without it,
/// or zero when there is no floor.
template <int N, typename What>
Status distilledInformation(const Eigen::MatrixXd& marginal, const Eigen::Matrix<double, N, N>& floor_covariance,
                            const What& what, Eigen::Matrix<double, N, N>& information,
                            Eigen::Matrix<double, N, N>* before_floor = nullptr) {
  const Eigen::Matrix<double, N, N> fixed = marginal;
  DG_RETURN_IF_ERROR(informationFromFixedCovariance<N>(fixed, what, information));
  if (floor_covariance.isZero(0.0)) return Status();
  if (before_floor != nullptr) *before_floor = information;
  return informationFromFixedCovariance<N>(Eigen::Matrix<double, N, N>(fixed + floor_covariance), what, information);
}

}  // namespace

DistillationResult TemporaryGraph::distil(double t_keyframe, const Eigen::Isometry3d& odom_T_keyframe,
                                          const OdometryHistory& history) {
  DistillationResult result;
  if (nodes_.empty()) return result;
  const bool anchored = std::any_of(records_.begin(), records_.end(), [](const AttachedObservation& record) {
    return observationModel(record.kind).anchorsGate();
  });
  if (!anchored) {  // partial gates alone: nothing anchors them
    result.partial_unanchored = static_cast<int>(records_.size());
    clear();
    return result;
  }
  const double start_ms = nowMs();
  const VertexIds ids = assignVertexIds(t_keyframe);
  const std::vector<int>& gate_ids = ids.gates;
  const std::vector<int>& gate_vertices = ids.gate_vertex;
  std::vector<Result<Eigen::MatrixXd>> covariances;
  GatePoses gate_estimates;  // odom_T_gate (a point: its translation)
  covariances.reserve(gate_ids.size());
  gate_estimates.reserve(gate_ids.size());
  Status built = buildProblem(t_keyframe, odom_T_keyframe, history, ids, result);
  const bool blocks =
      params_.temp_solver == TemporarySolverKind::kBlock && params_.linear_solver != LinearSolverKind::kCholmod;
  if (built.ok()) {
    built = blocks ? optimizeWithBlocks(gate_vertices, covariances, gate_estimates, result)
                   : optimizeWithGraph(gate_vertices, covariances, gate_estimates, result);
  }
  if (!built.ok()) {
    result.skipped_gates = static_cast<int>(ids.gates.size());
    result.skip_reason = built.message();
    result.optimize_ms = nowMs() - start_ms;
    clear();
    return result;
  }
  const Eigen::Isometry3d keyframe_T_odom = odom_T_keyframe.inverse();
  const SystematicFloor floor{params_.distilled_floor_range, params_.distilled_floor_lateral,
                              params_.distilled_floor_rotation};  // zero: no floor
  result.gates.reserve(gate_ids.size());
  for (size_t g = 0; g < gate_ids.size(); ++g) {
    GateEdgeMeasurement distilled;
    distilled.gate_id = gate_ids[g];
    distilled.model = params_.landmark;
    distilled.observations = ids.gate_observations[g];
    const Result<Eigen::MatrixXd>& covariance = covariances[g];
    Status usable = covariance.ok() ? Status() : covariance.status();
    const auto what = [&] { return "distilled covariance of gate " + std::to_string(gate_ids[g]); };
    if (usable.ok() && params_.landmark == LandmarkModel::kPose) {
      distilled.node_T_gate = keyframe_T_odom * gate_estimates[g];
      Matrix6d floor_covariance = Matrix6d::Zero();
      addFloorToPoseCovariance(floor, distilled.node_T_gate, floor_covariance);
      // The information before the floor only for the one that reads it, the odometry-noise learner.
      usable = distilledInformation<6>(*covariance, floor_covariance, what, distilled.pose_information,
                                       params_.learn_odometry_noise ? &distilled.statistical_pose_information : nullptr);
    } else if (usable.ok()) {
      distilled.p_node = keyframe_T_odom * gate_estimates[g].translation();
      distilled.node_T_gate.translation() = distilled.p_node;
      // The point's covariance is in odometry axes; the edge's error is in the keyframe's axes.
      const Eigen::Matrix3d rotation = keyframe_T_odom.linear();
      const Eigen::Matrix3d floor_covariance =
          floorTranslationCovariance(floor, distilled.p_node, Eigen::Matrix3d::Identity());
      usable = distilledInformation<3>(rotation * *covariance * rotation.transpose(), floor_covariance, what,
                                       distilled.point_information);
    }
    if (!usable.ok()) {
      if (result.skipped_gates++ == 0) result.skip_reason = usable.message();
      continue;
    }
    result.gates.push_back(distilled);
  }
  result.optimize_ms = nowMs() - start_ms;
  clear();
  return result;
}

}  // namespace dualgraph
