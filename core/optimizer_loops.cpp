// SPDX-License-Identifier: MIT
// The iteration loops of `Optimizer` (Levenberg–Marquardt and Gauss–Newton).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "dualgraph/core/lm_loop.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/core/wall_clock.h"

namespace dualgraph {
namespace {

void pushAll(const std::vector<VertexBase*>& vertices) {
  for (VertexBase* v : vertices) v->push();
}
void popAll(const std::vector<VertexBase*>& vertices) {
  for (VertexBase* v : vertices) v->pop();
}
void discardAll(const std::vector<VertexBase*>& vertices) {
  for (VertexBase* v : vertices) v->discardTop();
}

}  // namespace

// Both loops start with H and b assembled at the current estimate, whose χ² is
// summary.initial_chi2 (optimize() computes both in one pass).

void Optimizer::runLevenbergMarquardt(const OptimizerParams& params, SolverSummary& summary) {
  runLevenbergMarquardtLoop(*this, params, start_time_ms_, summary);
}

void Optimizer::lmSetDamping(bool scaled, double lambda) {
  if (scaled) {
    system_.setScaledDamping(lambda, lm_constants::kMinScaledDiagonal, lm_constants::kMaxScaledDiagonal);
  } else {
    system_.setDamping(lambda);
  }
}
void Optimizer::lmPush() { pushAll(system_.activeVertices()); }
void Optimizer::lmPop() { popAll(system_.activeVertices()); }
void Optimizer::lmDiscardTop() { discardAll(system_.activeVertices()); }
double Optimizer::lmPredictedDecrease() const {
  return system_.dampingEnergy(step_.data()) + step_.dot(system_.rhs());
}

// Gauss–Newton has no step control: it accepts every finite step, even one that raises χ² (on
// sphere2500 it climbs twice before converging, as in g2o). So that an undamped run can never leave
// a worse estimate than it started from (a free gauge whose round-off pivots pass the factorisation
// walks off to χ² ≈ 1e13 on parking-garage), the start is kept on the vertices' stacks and restored
// when the run ends above the initial χ², as kNoDecrease with the reason in the message.
void Optimizer::runGaussNewton(const OptimizerParams& params, SolverSummary& summary) {
  const auto& active = system_.activeVertices();
  pushAll(active);
  runGaussNewtonSteps(params, summary);
  if (!(summary.final_chi2 > summary.initial_chi2)) {
    discardAll(active);
    return;
  }
  popAll(active);
  errors_stale_ = true;
  char values[96];
  std::snprintf(values, sizeof(values), "%.9g above the start's %.9g", summary.final_chi2, summary.initial_chi2);
  summary.message = std::string("Gauss-Newton ended at χ² ") + values + " (" + terminationReasonName(summary.termination) +
                    (summary.message.empty() ? "" : ": " + summary.message) +
                    "); the start estimate is kept (is the gauge fixed? Levenberg-Marquardt controls its steps)";
  summary.termination = TerminationReason::kNoDecrease;
  summary.final_chi2 = summary.initial_chi2;
}

void Optimizer::runGaussNewtonSteps(const OptimizerParams& params, SolverSummary& summary) {
  const auto& active = system_.activeVertices();
  double chi2 = summary.initial_chi2;
  summary.termination = TerminationReason::kMaxIterations;
  for (int iteration = 1; iteration <= params.max_iterations; ++iteration) {
    const double iteration_start = nowMs();
    summary.iterations = iteration;
    if (iteration > 1) linearizeAndAssemble(summary);
    system_.setDamping(0.0);
    const Status solved = solveStep(summary);
    const Status non_finite = solved.ok() ? Status() : findNonFiniteSystem();
    if (!non_finite.ok()) {
      summary.termination = TerminationReason::kNumericalFailure;
      summary.message = non_finite.message();
      return;
    }
    if (!solved.ok()) {
      summary.termination = solved.code() == StatusCode::kNotPositiveDefinite ||
                                    solved.code() == StatusCode::kNumericalError
                                ? TerminationReason::kNotPositiveDefinite
                                : TerminationReason::kLinearSolverFailure;
      summary.message = solved.message();
      return;
    }
    const double update_start = nowMs();
    pushAll(active);
    system_.applyUpdate(step_.data());
    const double new_chi2 = evaluateChi2(nullptr);
    summary.update_ms += nowMs() - update_start;
    if (!std::isfinite(new_chi2)) {
      popAll(active);
      errors_stale_ = true;
      summary.termination = TerminationReason::kNoDecrease;
      summary.message = "Gauss-Newton step produced a non-finite χ²; kept the previous estimate";
      return;
    }
    discardAll(active);
    const double previous = chi2;
    chi2 = new_chi2;
    summary.final_chi2 = chi2;
    IterationSummary progress;
    progress.iteration = iteration;
    progress.chi2 = chi2;
    progress.trials = 1;
    progress.step_accepted = true;
    progress.iteration_ms = nowMs() - iteration_start;
    if (params.callback) params.callback(progress);
    if (std::fabs(previous - chi2) <= params.relative_decrease_stop * previous ||
        step_.lpNorm<Eigen::Infinity>() < params.step_norm_stop) {
      summary.termination = TerminationReason::kConverged;
      return;
    }
    if (params.time_budget_ms > 0.0 && nowMs() - start_time_ms_ >= params.time_budget_ms) {
      summary.termination = TerminationReason::kTimeBudget;
      return;
    }
  }
}

}  // namespace dualgraph
