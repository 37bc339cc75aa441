// SPDX-License-Identifier: MIT
// TemporarySolver's Levenberg–Marquardt loop: Optimizer::runLevenbergMarquardt (core/optimizer_loops.cpp)
// step for step, on the block system. Keep the two in step when either changes.
#include <algorithm>
#include <cmath>
#include <string>

#include "core/wall_clock.h"
#include "dual_graph/temporary_solver.h"

namespace dualgraph {

void TemporarySolver::runLevenbergMarquardt(const OptimizerParams& params, double start_ms, SolverSummary& summary) {
  const auto out_of_time = [&] { return params.time_budget_ms > 0.0 && nowMs() - start_ms >= params.time_budget_ms; };
  double chi2 = summary.initial_chi2;
  const bool scaled = params.damping == LmDamping::kDiagonal;
  double max_diagonal = 0.0;
  for (size_t j = 0; j < active_.size(); ++j) {
    const BlockCholesky::Block& diagonal = h_[cholesky_.diagonalIndex(static_cast<int>(j))];
    for (int c = 0; c < block_dim_[j]; ++c) max_diagonal = std::max(max_diagonal, diagonal(c, c));
  }
  double lambda = params.initial_lambda > 0.0 ? params.initial_lambda
                  : scaled                    ? lm_constants::kInitialScaledLambda
                                              : params.tau * std::max(max_diagonal, 1e-12);
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
      setDamping(scaled, lambda);
      last_failure = solveStep(summary);
      if (!last_failure.ok()) {
        if (last_failure.code() != StatusCode::kNotPositiveDefinite && last_failure.code() != StatusCode::kNumericalError) {
          summary.termination = TerminationReason::kLinearSolverFailure;
          summary.message = last_failure.message();
          return;
        }
        const Status non_finite = findNonFinite();  // damping cannot repair a NaN
        if (!non_finite.ok()) {
          summary.termination = TerminationReason::kNumericalFailure;
          summary.message = non_finite.message();
          return;
        }
        lambda *= nu;
        nu *= 2.0;
        continue;
      }
      for (VertexBase* v : active_) v->push();
      applyStep();
      new_chi2 = evaluateChi2(nullptr);
      const double predicted = dampingEnergy() + step_.dot(rhs_);
      const double rho = (chi2 - new_chi2) / std::max(predicted, 1e-300);
      const double round_off = lm_constants::kChi2RoundOff * chi2;
      const bool unresolvable = predicted <= std::min(round_off, params.relative_decrease_stop * chi2) &&
                                std::fabs(new_chi2 - chi2) <= round_off;
      if (std::isfinite(new_chi2) && (rho > 0.0 || unresolvable)) {
        for (VertexBase* v : active_) v->discardTop();
        const double a = 2.0 * rho - 1.0;
        lambda *= std::clamp(1.0 - a * a * a, 1.0 / 3.0, 2.0 / 3.0);
        nu = 2.0;
        progress.step_accepted = true;
      } else {
        for (VertexBase* v : active_) v->pop();
        errors_stale_ = true;
        last_failure = Status();
        at_minimum = std::isfinite(new_chi2) && predicted <= params.relative_decrease_stop * chi2;
        lambda *= nu;
        nu *= 2.0;
      }
      if (at_minimum) break;
    }
    progress.chi2 = progress.step_accepted ? new_chi2 : chi2;
    progress.iteration_ms = nowMs() - iteration_start;
    if (progress.step_accepted) {
      const double previous = chi2;
      chi2 = new_chi2;
      summary.final_chi2 = chi2;
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
      if (iteration < params.max_iterations) linearizeAndAssemble();
      continue;
    }
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

}  // namespace dualgraph
