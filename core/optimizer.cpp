// SPDX-License-Identifier: MIT
#include "core/optimizer.h"

#include <algorithm>
#include <cmath>

#include "core/wall_clock.h"

namespace dualgraph {

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
  const auto& edges = graph_.edges();
  double sum = 0.0;
  for (size_t k = 0; k < edges.size(); ++k) {
    edges[k]->computeError();
    // A kernel can map an infinite eᵀΩe to a finite ρ (Tukey's plateau); the error is still
    // unusable (its weight 0 times ∞ poisons b), so the plain χ² decides finiteness.
    double chi2 = edges[k]->chi2();
    const RobustKernel* kernel = edges[k]->robustKernel();
    if (kernel != nullptr && std::isfinite(chi2)) chi2 = kernel->robustify(chi2)[0];
    if (!std::isfinite(chi2) && first_bad != nullptr && first_bad->empty()) {
      *first_bad = "edge between vertices";
      for (const VertexBase* v : edges[k]->vertices()) *first_bad += " " + std::to_string(v->id());
      if (edges[k]->sourceLine() > 0) *first_bad += " (line " + std::to_string(edges[k]->sourceLine()) + ")";
      *first_bad += " has a non-finite χ²";
    }
    sum += chi2;
  }
  return sum;
}

void Optimizer::linearizeAndAssemble(SolverSummary& summary) {
  // Every caller evaluated χ² (hence every error) at the current estimate just before, so only
  // Jacobians are computed. Edges go in runs small enough that the Jacobians just written are
  // still in L1/L2 when the run is added to H, instead of one pass writing every Jacobian and a
  // second reading them all back from memory; each phase keeps its own clock.
  constexpr size_t kRun = 32;
  const std::vector<EdgeBase*>& edges = system_.activeEdges();
  {
    PhaseTimer timer(summary.assemble_ms);
    system_.beginAssembly();
  }
  for (size_t begin = 0; begin < edges.size(); begin += kRun) {
    const size_t end = std::min(edges.size(), begin + kRun);
    {
      PhaseTimer timer(summary.linearize_ms);
      for (size_t e = begin; e < end; ++e) edges[e]->computeJacobians();
    }
    PhaseTimer timer(summary.assemble_ms);
    system_.assembleEdges(begin, end);
  }
  PhaseTimer timer(summary.assemble_ms);
  system_.finishAssembly();
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
  summary.initial_chi2 = summary.final_chi2 = evaluateChi2(&first_bad);
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
