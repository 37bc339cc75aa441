// SPDX-License-Identifier: MIT
// The iteration loops of `Optimizer` (Levenberg–Marquardt and Gauss–Newton).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/optimizer.h"
#include "core/wall_clock.h"

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

using namespace lm_constants;  // NOLINT: the loop's constants (core/optimizer.h)

}  // namespace

// Both loops start with H and b assembled at the current estimate, whose χ² is
// summary.initial_chi2 (optimize() computes both in one pass).

void Optimizer::runLevenbergMarquardt(const OptimizerParams& params, SolverSummary& summary) {
  const auto& active = system_.activeVertices();
  const auto out_of_time = [&] {
    return params.time_budget_ms > 0.0 && nowMs() - start_time_ms_ >= params.time_budget_ms;
  };
  double chi2 = summary.initial_chi2;
  const bool scaled = params.damping == LmDamping::kDiagonal;
  double lambda = params.initial_lambda > 0.0 ? params.initial_lambda
                  : scaled                    ? kInitialScaledLambda
                                              : params.tau * std::max(system_.maxDiagonal(), 1e-12);
  double nu = 2.0;
  summary.termination = TerminationReason::kMaxIterations;

  for (int iteration = 1; iteration <= params.max_iterations; ++iteration) {
    const double iteration_start = nowMs();
    summary.iterations = iteration;
    IterationSummary progress;
    progress.iteration = iteration;
    Status last_failure;
    double new_chi2 = chi2;
    bool at_minimum = false;
    for (int trial = 0; trial < params.max_trials && !progress.step_accepted; ++trial) {
      if (out_of_time()) break;
      ++progress.trials;
      progress.lambda = lambda;
      if (scaled) {
        system_.setScaledDamping(lambda, kMinScaledDiagonal, kMaxScaledDiagonal);
      } else {
        system_.setDamping(lambda);
      }
      last_failure = solveStep(summary);
      if (!last_failure.ok()) {
        if (last_failure.code() != StatusCode::kNotPositiveDefinite &&
            last_failure.code() != StatusCode::kNumericalError) {
          summary.termination = TerminationReason::kLinearSolverFailure;
          summary.message = last_failure.message();
          return;
        }
        // Damping cannot repair a NaN in H or b (a non-finite Jacobian): stop instead of retrying.
        const Status non_finite = findNonFiniteSystem();
        if (!non_finite.ok()) {
          summary.termination = TerminationReason::kNumericalFailure;
          summary.message = non_finite.message();
          return;
        }
        lambda *= nu;
        nu *= 2.0;
        continue;
      }
      const double update_start = nowMs();
      pushAll(active);
      system_.applyUpdate(step_.data());
      new_chi2 = evaluateChi2(nullptr);
      // Gain ratio: actual decrease over the decrease predicted by the damped model.
      const double predicted = system_.dampingEnergy(step_.data()) + step_.dot(system_.rhs());
      const double rho = (chi2 - new_chi2) / std::max(predicted, 1e-300);
      // A step whose predicted decrease and actual change are both below χ²'s evaluation round-off
      // (and below the relative threshold) cannot be judged by χ²: it is taken on the model's word,
      // ending the run converged, rather than discarded (which left a linear problem ~1e-9 short of
      // its closed-form optimum once λ·diag(H) damping made the first step stop 1e-4 short).
      const double round_off = kChi2RoundOff * chi2;
      const bool unresolvable = predicted <= std::min(round_off, params.relative_decrease_stop * chi2) &&
                                std::fabs(new_chi2 - chi2) <= round_off;
      if (std::isfinite(new_chi2) && (rho > 0.0 || unresolvable)) {
        discardAll(active);
        // Nielsen's update with g2o's bounds: a good step shrinks λ by a factor in [1/3, 2/3].
        const double a = 2.0 * rho - 1.0;
        lambda *= std::clamp(1.0 - a * a * a, 1.0 / 3.0, 2.0 / 3.0);
        nu = 2.0;
        progress.step_accepted = true;
      } else {
        popAll(active);
        errors_stale_ = true;
        last_failure = Status();
        // The model itself predicts less than the relative threshold and the step did not realise
        // even that: χ² is at its round-off floor (e.g. a linear problem solved by the previous
        // step), which is convergence, not a failure to find a decreasing step.
        at_minimum = std::isfinite(new_chi2) && predicted <= params.relative_decrease_stop * chi2;
        lambda *= nu;
        nu *= 2.0;
      }
      summary.update_ms += nowMs() - update_start;
      if (at_minimum) break;
    }
    if (progress.step_accepted) {
      const double previous = chi2;
      chi2 = new_chi2;
      summary.final_chi2 = chi2;
      progress.chi2 = chi2;
      progress.iteration_ms = nowMs() - iteration_start;
      if (params.callback) params.callback(progress);
      if (previous - chi2 <= params.relative_decrease_stop * previous ||
          step_.lpNorm<Eigen::Infinity>() < params.step_norm_stop) {
        summary.termination = TerminationReason::kConverged;
        return;
      }
      if (out_of_time()) {
        summary.termination = TerminationReason::kTimeBudget;
        return;
      }
      if (iteration < params.max_iterations) linearizeAndAssemble(summary);
      continue;
    }
    progress.chi2 = chi2;
    progress.iteration_ms = nowMs() - iteration_start;
    if (params.callback) params.callback(progress);
    if (at_minimum) {
      summary.termination = TerminationReason::kConverged;
    } else if (out_of_time()) {
      summary.termination = TerminationReason::kTimeBudget;
    } else if (!last_failure.ok()) {
      summary.termination = TerminationReason::kNotPositiveDefinite;
      summary.message = last_failure.message();
    } else {
      summary.termination = TerminationReason::kNoDecrease;
      summary.message = "no decreasing step after " + std::to_string(progress.trials) + " damping increases";
    }
    return;
  }
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
