// SPDX-License-Identifier: MIT
#include "dualgraph/core/optimizer.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "dualgraph/core/wall_clock.h"

namespace dualgraph {
namespace {

/// Edges go through the linearisation in runs this long: a run's errors, Jacobians and
/// information matrices are still in L2 (128 SE(3) edges are ~180 KB) when the run is added to
/// H, instead of one pass over all edges writing them and another reading them back from memory.
/// On parking-garage 128 and 512 measured alike, 32 slightly and 8 clearly slower.
constexpr size_t kEdgeRun = 128;

/// Software prefetch in loops over edges (memory bound on large graphs, whose edges do not fit in
/// the caches): at edge k, the first cache line of edge k + 2·kAhead (its vtable pointer, so that
/// the next call does not wait for it) and the fields of edge k + kAhead.
constexpr size_t kPrefetchAhead = 4;
template <typename EdgePointer>
void prefetchAhead(const std::vector<EdgePointer>& edges, size_t k) {
#if defined(__GNUC__)
  if (k + 2 * kPrefetchAhead < edges.size()) __builtin_prefetch(&*edges[k + 2 * kPrefetchAhead]);
#endif
  if (k + kPrefetchAhead < edges.size()) edges[k + kPrefetchAhead]->prefetch();
}

/// Adds the active edges [begin, end) to H and b after computing their Jacobians (their errors
/// are current), each part on its phase clock; `clock` is the time the run started and is
/// advanced to the time it ended.
void linearizeRun(SparseSystem& system, size_t begin, size_t end, double& clock, SolverSummary& summary) {
  const std::vector<EdgeBase*>& active = system.activeEdges();
  for (size_t e = begin; e < end; ++e) {
    prefetchAhead(active, e);
    active[e]->computeJacobians();
  }
  const double jacobians_done = nowMs();
  summary.linearize_ms += jacobians_done - clock;
  system.assembleEdges(begin, end);
  clock = nowMs();
  summary.assemble_ms += clock - jacobians_done;
}

/// Optimizer::evaluateChi2 and Optimizer::linearizeAndAssemble in one pass over the edges: each
/// run's errors are computed (the χ² summed in graph order, exactly as evaluateChi2) and the run's
/// active edges, a contiguous stretch of activeEdges() since both lists keep graph order, are
/// linearised and added while they are in cache. The errors are on no phase clock, as before.
double evaluateChi2AndLinearize(const std::vector<std::unique_ptr<EdgeBase>>& edges, SparseSystem& system,
                                SolverSummary& summary, std::string* first_bad) {
  const std::vector<EdgeBase*>& active = system.activeEdges();
  double clock = nowMs();
  system.beginAssembly();
  summary.assemble_ms += nowMs() - clock;
  double sum = 0.0;
  size_t next_active = 0;
  for (size_t begin = 0; begin < edges.size(); begin += kEdgeRun) {
    const size_t end = std::min(edges.size(), begin + kEdgeRun);
    const size_t run_begin = next_active;
    for (size_t k = begin; k < end; ++k) {
      prefetchAhead(edges, k);
      EdgeBase* edge = edges[k].get();
      edge->computeError();
      sum += optimizerChi2(*edge, first_bad);
      if (next_active < active.size() && active[next_active] == edge) ++next_active;
    }
    clock = nowMs();
    linearizeRun(system, run_begin, next_active, clock, summary);
  }
  system.finishAssembly();
  summary.assemble_ms += nowMs() - clock;
  return sum;
}

}  // namespace

const char* terminationReasonName(TerminationReason reason) {
  switch (reason) {
    case TerminationReason::kConverged: return "converged";
    case TerminationReason::kMaxIterations: return "max_iterations";
    case TerminationReason::kNoDecrease: return "no_decrease";
    case TerminationReason::kTimeBudget: return "time_budget";
    case TerminationReason::kNotPositiveDefinite: return "not_positive_definite";
    case TerminationReason::kInvalidInput: return "invalid_input";
    case TerminationReason::kNothingToOptimize: return "nothing_to_optimize";
    case TerminationReason::kLinearSolverFailure: return "linear_solver_failure";
    case TerminationReason::kNumericalFailure: return "numerical_failure";
  }
  return "unknown";
}

const char* lmDampingName(LmDamping damping) {
  switch (damping) {
    case LmDamping::kIdentity: return "identity";
    case LmDamping::kDiagonal: return "diagonal";
  }
  return "unknown";
}

bool SolverSummary::usable() const {
  return termination == TerminationReason::kConverged ||
         termination == TerminationReason::kMaxIterations ||
         termination == TerminationReason::kNoDecrease ||
         termination == TerminationReason::kTimeBudget;
}

Optimizer::Optimizer(Graph& graph, std::unique_ptr<LinearSolver> solver)
    : graph_(graph), solver_(std::move(solver)) {
  if (!solver_) throw ContractViolation("Optimizer needs a linear solver");
}

bool Optimizer::structureIsCurrent() const {
  if (built_version_ != graph_.structureVersion()) return false;
  // Fixed flags can be flipped on a vertex directly, bypassing the graph's version counter.
  for (const auto& [vertex, fixed] : fixed_snapshot_) {
    if (vertex->fixed() != fixed) return false;
  }
  return true;
}

Status Optimizer::ensureStructure(SolverSummary& summary) {
  if (structureIsCurrent()) return Status();
  PhaseTimer timer(summary.structure_ms);
  summary.structure_rebuilt = true;
  built_version_ = ~uint64_t{0};
  DG_RETURN_IF_ERROR(system_.build(graph_));
  if (system_.dim() > 0) DG_RETURN_IF_ERROR(solver_->analyze(system_.matrix()));
  fixed_snapshot_.clear();
  for (const auto& [id, vertex] : graph_.vertices()) fixed_snapshot_.emplace_back(vertex.get(), vertex->fixed());
  built_version_ = graph_.structureVersion();
  step_.resize(system_.dim());
  return Status();
}

double Optimizer::evaluateChi2(std::string* first_bad) {
  errors_stale_ = false;
  double sum = 0.0;
  const auto& edges = graph_.edges();
  for (size_t k = 0; k < edges.size(); ++k) {
    prefetchAhead(edges, k);
    edges[k]->computeError();
    sum += optimizerChi2(*edges[k], first_bad);
  }
  return sum;
}

void Optimizer::linearizeAndAssemble(SolverSummary& summary) {
  // Every caller evaluated χ² (hence every error) at the current estimate just before, so only
  // Jacobians are computed.
  double clock = nowMs();
  system_.beginAssembly();
  const size_t num_active = system_.activeEdges().size();
  for (size_t begin = 0; begin < num_active; begin += kEdgeRun) {
    linearizeRun(system_, begin, std::min(num_active, begin + kEdgeRun), clock, summary);
  }
  system_.finishAssembly();
  summary.assemble_ms += nowMs() - clock;
}

Status Optimizer::solveStep(SolverSummary& summary) {
  ++summary.factorizations;
  {
    PhaseTimer timer(summary.factorize_ms);
    DG_RETURN_IF_ERROR(solver_->factorize(system_.matrix()));
  }
  PhaseTimer timer(summary.solve_ms);
  DG_RETURN_IF_ERROR(solver_->solve(system_.rhs().data(), step_.data()));
  if (!step_.allFinite()) return Status(StatusCode::kNumericalError, "non-finite step");
  return Status();
}

Status Optimizer::findNonFiniteSystem() const {
  DG_RETURN_IF_ERROR(findNonFiniteJacobian(system_.activeEdges()));
  const SparseMatrixView h = system_.matrix();
  for (int column = 0; column < h.n; ++column) {
    bool finite = std::isfinite(system_.rhs()[column]);
    for (int k = h.col_ptr[column]; finite && k < h.col_ptr[column + 1]; ++k) finite = std::isfinite(h.values[k]);
    if (finite) continue;
    for (const VertexBase* v : system_.activeVertices()) {
      const int offset = system_.offsetOf(v);
      if (column >= offset && column < offset + v->tangentDim()) {
        return Status(StatusCode::kNumericalError, "H or b is not finite in the rows of vertex " + std::to_string(v->id()));
      }
    }
    return Status(StatusCode::kNumericalError, "H or b is not finite at row " + std::to_string(column));
  }
  return Status();
}

Status Optimizer::factorizeAtCurrentEstimate() {
  SolverSummary summary;
  DG_RETURN_IF_ERROR(ensureStructure(summary));
  if (system_.dim() == 0) return Status(StatusCode::kFailedPrecondition, "no free vertex in the system");
  evaluateChi2(nullptr);
  linearizeAndAssemble(summary);
  system_.setDamping(0.0);
  return solver_->factorize(system_.matrix());
}

SolverSummary Optimizer::optimize(const OptimizerParams& params) {
  SolverSummary summary;
  start_time_ms_ = nowMs();
  summary.linear_solver = solver_->name();
  const Status structure = ensureStructure(summary);
  summary.vertices = static_cast<int>(system_.activeVertices().size());
  summary.edges = static_cast<int>(system_.activeEdges().size());
  summary.dimension = system_.dim();
  summary.nonzeros = system_.dim() > 0 ? system_.matrix().nnz() : 0;

  std::string first_bad;
  // Both algorithms start from H and b at the initial estimate, so when one will run, the initial
  // χ² and that linearisation share one pass over the edges (the system is simply unused if the
  // χ² turns out non-finite).
  if (structure.ok() && system_.dim() > 0 && params.max_iterations > 0) {
    errors_stale_ = false;
    summary.initial_chi2 = evaluateChi2AndLinearize(graph_.edges(), system_, summary, &first_bad);
  } else {
    summary.initial_chi2 = evaluateChi2(&first_bad);
  }
  summary.final_chi2 = summary.initial_chi2;
  if (!structure.ok()) {
    summary.termination = TerminationReason::kLinearSolverFailure;
    summary.message = structure.message();
  } else if (!first_bad.empty()) {
    summary.termination = TerminationReason::kInvalidInput;
    summary.message = first_bad;
  } else if (system_.dim() == 0) {
    summary.termination = TerminationReason::kNothingToOptimize;
    summary.message = "no free vertex is attached to an edge";
  } else if (params.max_iterations <= 0) {
    summary.termination = TerminationReason::kMaxIterations;
  } else if (params.algorithm == Algorithm::kGaussNewton) {
    runGaussNewton(params, summary);
  } else {
    runLevenbergMarquardt(params, summary);
  }
  // Leaves every edge's stored error consistent with the final estimate (a rejected trial may
  // have been the last evaluation).
  if (errors_stale_) summary.final_chi2 = evaluateChi2(nullptr);
  summary.total_ms = nowMs() - start_time_ms_;
  return summary;
}

}  // namespace dualgraph
