// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/block/block_lm_solver.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "dualgraph/core/wall_clock.h"
#include "dualgraph/solvers/block/block_kernels_avx2.h"

namespace dualgraph {
Status BlockLmSolver::setGraph(Graph& graph) {
  std::vector<VertexBase*> vertices;
  std::vector<EdgeBase*> edges;
  vertices.reserve(graph.numVertices());
  edges.reserve(graph.numEdges());
  for (const auto& [id, vertex] : graph.vertices()) vertices.push_back(vertex.get());
  for (const auto& edge : graph.edges()) edges.push_back(edge.get());
  return setProblem(vertices, edges);
}

Status BlockLmSolver::setProblem(const std::vector<VertexBase*>& vertices, const std::vector<EdgeBase*>& edges) {
  has_problem_ = false;
  marginals_ready_ = false;
  errors_current_ = false;
  undamped_factor_current_ = false;
  active_.clear();
  block_dim_.clear();
  active_edges_.clear();
  active_source_.clear();
  edge_begin_.assign(1, 0);
  edge_block_.clear();
  pair_begin_.assign(1, 0);
  pair_index_.clear();
  pair_first_.clear();
  pattern_.clear();
  int max_id = -1;
  for (const VertexBase* v : vertices) {
    if (v == nullptr) continue;
    if (v->id() < 0) return Status(StatusCode::kFailedPrecondition, "temporary solver: negative vertex id");
    if (v->id() <= max_id) return Status(StatusCode::kFailedPrecondition, "temporary solver: vertex ids out of order");
    max_id = v->id();
  }
  block_by_id_.assign(max_id + 1, -1);
  for (const EdgeBase* edge : edges) {
    if (edge->errorDim() > kB || edge->numVertices() > static_cast<size_t>(kMaxSlots)) {
      return Status(StatusCode::kInvalidArgument, "temporary solver: " + describeEdge(*edge) + " is larger than 6×6 blocks");
    }
    for (const VertexBase* v : edge->vertices()) {
      if (v == nullptr) return Status(StatusCode::kFailedPrecondition, "temporary solver: edge with an empty vertex slot");
      if (v->id() < 0 || v->id() > max_id) {
        return Status(StatusCode::kFailedPrecondition, "temporary solver: " + describeEdge(*edge) + " refers to a vertex not given");
      }
      if (!v->fixed()) block_by_id_[v->id()] = 0;  // attached and free
    }
    const std::vector<VertexBase*>& slots = edge->vertices();
    for (size_t a = 0; a < slots.size(); ++a) {
      for (size_t b = a + 1; b < slots.size(); ++b) {
        if (slots[a] == slots[b] && !slots[a]->fixed()) {  // the assembly has one H block per pair of blocks
          return Status(StatusCode::kInvalidArgument, "temporary solver: " + describeEdge(*edge) + " uses free vertex " +
                                                          std::to_string(slots[a]->id()) + " in two slots");
        }
      }
    }
  }
  for (VertexBase* vertex : vertices) {
    if (vertex == nullptr || block_by_id_[vertex->id()] < 0) continue;
    if (vertex->tangentDim() > kB) {
      return Status(StatusCode::kInvalidArgument, "temporary solver: vertex " + std::to_string(vertex->id()) + " has more than 6 dimensions");
    }
    block_by_id_[vertex->id()] = static_cast<int>(active_.size());
    active_.push_back(vertex);
    block_dim_.push_back(vertex->tangentDim());
  }
  for (size_t source = 0; source < edges.size(); ++source) {
    EdgeBase* edge = edges[source];
    const size_t first = edge_block_.size();
    for (const VertexBase* v : edge->vertices()) {
      const int block = v->fixed() ? -1 : block_by_id_[v->id()];
      if (block >= 0 && (block >= static_cast<int>(active_.size()) || active_[block] != v)) {  // an id in range whose vertex was not given (or another object)
        return Status(StatusCode::kFailedPrecondition, "temporary solver: " + describeEdge(*edge) + " refers to a vertex not given");
      }
      edge_block_.push_back(block);
    }
    if (std::all_of(edge_block_.begin() + first, edge_block_.end(), [](int b) { return b < 0; })) {
      edge_block_.resize(first);
      continue;
    }
    active_edges_.push_back(edge);
    active_source_.push_back(static_cast<int>(source));
    edge_begin_.push_back(static_cast<int>(edge_block_.size()));
    for (size_t a = first; a < edge_block_.size(); ++a) {
      for (size_t b = a + 1; b < edge_block_.size(); ++b) {
        if (edge_block_[a] >= 0 && edge_block_[b] >= 0 && edge_block_[a] != edge_block_[b]) {
          pattern_.emplace_back(edge_block_[a], edge_block_[b]);
        }
      }
    }
  }
  const int num_blocks = static_cast<int>(active_.size());
  DG_RETURN_IF_ERROR(cholesky_.analyse(num_blocks, pattern_));
  for (size_t e = 0; e < active_edges_.size(); ++e) {
    for (int a = edge_begin_[e]; a < edge_begin_[e + 1]; ++a) {
      if (edge_block_[a] < 0) continue;
      for (int b = a; b < edge_begin_[e + 1]; ++b) {
        if (edge_block_[b] < 0) continue;
        pair_index_.push_back(cholesky_.blockIndex(std::max(edge_block_[a], edge_block_[b]),
                                                   std::min(edge_block_[a], edge_block_[b])));
      }
    }
    pair_begin_.push_back(static_cast<int>(pair_index_.size()));
  }
  h_.resize(cholesky_.numStoredBlocks());
  std::vector<unsigned char>& touched = touched_work_;
  touched.assign(h_.size(), 0);
  pair_first_.resize(pair_index_.size());
  for (size_t k = 0; k < pair_index_.size(); ++k) {
    pair_first_[k] = touched[pair_index_[k]] == 0 ? 1 : 0;
    touched[pair_index_[k]] = 1;
  }
  for (size_t p = 0; p < h_.size(); ++p) {
    if (touched[p] == 0) h_[p].setZero();  // fill: L's pattern only, never assembled
  }
  rhs_.setZero(kB * num_blocks);
  damping_.setZero(kB * num_blocks);
  step_.setZero(kB * num_blocks);
  edges_.assign(edges.begin(), edges.end());
  plain_chi2_.assign(edges_.size(), 0.0);
  has_problem_ = true;
  return Status();
}

double BlockLmSolver::evaluateChi2(std::string* first_bad) {
  const bool avx2 = block_kernels_avx2::enabled();
  double sum = 0.0;
  for (size_t k = 0; k < edges_.size(); ++k) {
    EdgeBase& edge = *edges_[k];
    edge.computeError();
    plain_chi2_[k] = avx2 && edge.errorDim() == kB ? block_kernels_avx2::quadraticForm(edge.informationData(), edge.errorData())
                                                   : edge.chi2();
    sum += optimizerChi2(edge, plain_chi2_[k], first_bad);
  }
  return sum;
}

void BlockLmSolver::linearizeAndAssemble() {
  undamped_factor_current_ = false;
  rhs_.setZero();  // H needs no clearing: each block's first contribution assigns (pair_first_)
  const bool avx2 = block_kernels_avx2::enabled();  // once per linearisation, not per edge
  for (size_t k = 0; k < active_edges_.size(); ++k) {
    active_edges_[k]->computeJacobians();
    assembleEdge(k, avx2);
  }
  // Padding of smaller vertices: identity diagonal, no coupling, zero right-hand side.
  for (size_t j = 0; j < active_.size(); ++j) {
    for (int c = block_dim_[j]; c < kB; ++c) h_[cholesky_.diagonalIndex(static_cast<int>(j))](c, c) = 1.0;
  }
}

void BlockLmSolver::setDamping(bool scaled, double lambda) {
  for (size_t j = 0; j < active_.size(); ++j) {
    const BlockCholesky::Block& diagonal = h_[cholesky_.diagonalIndex(static_cast<int>(j))];
    for (int c = 0; c < kB; ++c) {
      const bool real = c < block_dim_[j];
      damping_[kB * j + c] = !real ? 0.0 : scaled ? lambda * std::clamp(diagonal(c, c), lm_constants::kMinScaledDiagonal, lm_constants::kMaxScaledDiagonal)
                                                  : lambda;
    }
  }
}

double BlockLmSolver::dampingEnergy() const { return (damping_.array() * step_.array().square()).sum(); }

void BlockLmSolver::applyStep() {
  undamped_factor_current_ = false;
  for (size_t j = 0; j < active_.size(); ++j) active_[j]->plus(step_.data() + kB * j);
}

Status BlockLmSolver::solveStep(SolverSummary& summary) {
  ++summary.factorizations;
  undamped_factor_current_ = false;
  DG_RETURN_IF_ERROR(cholesky_.factorize(h_.data(), damping_.data()));
  undamped_factor_current_ = damping_.isZero(0.0);  // the factor of H itself, at the current estimate
  DG_RETURN_IF_ERROR(cholesky_.solve(rhs_.data(), step_.data()));
  if (!step_.allFinite()) return Status(StatusCode::kNumericalError, "non-finite step");
  return Status();
}

Status BlockLmSolver::findNonFinite() const {
  DG_RETURN_IF_ERROR(findNonFiniteJacobian(active_edges_));
  const int num_blocks = static_cast<int>(active_.size());
  for (int j = 0; j < num_blocks; ++j) {  // column j's stored blocks are contiguous
    bool finite = rhs_.segment<kB>(kB * j).allFinite();
    const int end = j + 1 < num_blocks ? cholesky_.diagonalIndex(j + 1) : cholesky_.numStoredBlocks();
    for (int p = cholesky_.diagonalIndex(j); finite && p < end; ++p) finite = h_[p].allFinite();
    if (!finite) {
      return Status(StatusCode::kNumericalError, "H or b is not finite in the block column of vertex " +
                                                     std::to_string(active_[j]->id()));
    }
  }
  return Status();
}

SolverSummary BlockLmSolver::optimize(const OptimizerParams& params) {
  SolverSummary summary;
  const double start_ms = nowMs();
  summary.linear_solver = "block Cholesky (6x6)";
  if (!has_problem_) {
    summary.termination = TerminationReason::kLinearSolverFailure;
    summary.message = "temporary solver: setGraph was not called";
    return summary;
  }
  summary.vertices = static_cast<int>(active_.size());
  summary.edges = static_cast<int>(active_edges_.size());
  for (int d : block_dim_) summary.dimension += d;
  std::string first_bad;
  errors_stale_ = false;
  summary.initial_chi2 = evaluateChi2(&first_bad);
  summary.final_chi2 = summary.initial_chi2;
  if (!first_bad.empty()) {
    summary.termination = TerminationReason::kInvalidInput;
    summary.message = first_bad;
  } else if (active_.empty()) {
    summary.termination = TerminationReason::kNothingToOptimize;
    summary.message = "no free vertex is attached to an edge";
  } else if (params.max_iterations <= 0) {
    summary.termination = TerminationReason::kMaxIterations;
  } else {
    linearizeAndAssemble();
    runLevenbergMarquardt(params, start_ms, summary);
  }
  if (errors_stale_) summary.final_chi2 = evaluateChi2(nullptr);
  errors_current_ = true;
  summary.total_ms = nowMs() - start_ms;
  return summary;
}

Status BlockLmSolver::computeMarginals() { return computeMarginalsOf(nullptr); }

Status BlockLmSolver::computeMarginals(const std::vector<int>& ids) { return computeMarginalsOf(&ids); }

Status BlockLmSolver::computeMarginalsOf(const std::vector<int>* ids) {
  marginals_ready_ = false;
  if (!has_problem_) return Status(StatusCode::kFailedPrecondition, "temporary solver: setGraph was not called");
  if (active_.empty()) return Status(StatusCode::kFailedPrecondition, "no free vertex in the system");
  if (ids != nullptr) {
    marginal_blocks_.clear();
    for (int id : *ids) {
      if (id < 0 || id >= static_cast<int>(block_by_id_.size()) || block_by_id_[id] < 0) {
        return Status(StatusCode::kFailedPrecondition,
                      "marginal covariance: vertex " + std::to_string(id) + " is not free in the system");
      }
      marginal_blocks_.push_back(block_by_id_[id]);
    }
  }
  // optimize ended on the model check (OptimizerParams::model_decrease_stop): the factor of the undamped
  // H at this estimate is in cholesky_ already.
  const bool reuse = errors_current_ && undamped_factor_current_;
  if (!errors_current_) evaluateChi2(nullptr);
  errors_current_ = false;
  if (!reuse) {
    linearizeAndAssemble();
    DG_RETURN_IF_ERROR(cholesky_.factorize(h_.data()));
  }
  undamped_factor_current_ = false;
  DG_RETURN_IF_ERROR(ids == nullptr ? cholesky_.selectedInverse() : cholesky_.selectedInverse(marginal_blocks_));
  marginals_ready_ = true;
  return Status();
}

Result<Eigen::MatrixXd> BlockLmSolver::marginal(int id) const {
  if (!marginals_ready_) return Status(StatusCode::kFailedPrecondition, "marginal covariance: computeMarginals did not succeed");
  if (id < 0 || id >= static_cast<int>(block_by_id_.size()) || block_by_id_[id] < 0) {
    return Status(StatusCode::kFailedPrecondition, "marginal covariance: vertex " + std::to_string(id) + " is not free in the system");
  }
  const int block = block_by_id_[id];
  if (!cholesky_.inverseComputed(block)) {
    return Status(StatusCode::kFailedPrecondition,
                  "marginal covariance: vertex " + std::to_string(id) + " was not asked of computeMarginals");
  }
  const int d = block_dim_[block];
  return Eigen::MatrixXd(cholesky_.inverseDiagonal(block).topLeftCorner(d, d));
}

}  // namespace dualgraph
