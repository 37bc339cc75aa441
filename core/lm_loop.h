// SPDX-License-Identifier: MIT
// The Levenberg–Marquardt loop, one template for Optimizer and the temporary graph's block solver.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "dualgraph/core/optimizer.h"
#include "dualgraph/core/wall_clock.h"

namespace dualgraph {

/// The Levenberg–Marquardt loop, written once for every system it runs on: `Optimizer` (the scalar
/// sparse system) and the temporary graph's 6×6 block solver (solvers/block/block_lm_solver.h), so both
/// take exactly the same steps. It starts with H and b assembled at the current estimate, whose χ² is
/// `summary.initial_chi2`, and leaves the estimate at the last accepted state.
///
/// `System` provides (typically as private members, befriending this function):
///   double lmMaxDiagonal() const;                  max diag(H) (g2o's λ₀ = tau · it)
///   void   lmSetDamping(bool scaled, double λ);    H + λ·clamp(diag H) (scaled) or H + λI for the next solve
///   Status lmSolveStep(SolverSummary&);            factorise the damped H, solve for the step
///   Status lmFindNonFinite() const;                after a failed solve: a status naming a NaN in H/b, else OK
///   void   lmPush(); lmPop(); lmDiscardTop();      the free vertices' estimate stacks
///   void   lmApplyStep();                          x ⊞ step
///   double lmEvaluateChi2();                       Σ ρ(eᵀΩe) at the current estimate
///   double lmPredictedDecrease() const;            stepᵀ D step + stepᵀ b (the damped model's decrease)
///   double lmStepInfNorm() const;
///   void   lmMarkErrorsStale();                    the edges hold a rejected trial's errors
///   void   lmRelinearize(SolverSummary&);          H and b at the current estimate
/// With `params.model_decrease_stop` > 0 the loop may end right after an undamped lmSolveStep at the
/// final estimate (see OptimizerParams).
template <typename System>
void runLevenbergMarquardtLoop(System& system, const OptimizerParams& params, double start_ms, SolverSummary& summary) {
  using namespace lm_constants;
  const auto out_of_time = [&] { return params.time_budget_ms > 0.0 && nowMs() - start_ms >= params.time_budget_ms; };
  double chi2 = summary.initial_chi2;
  const bool scaled = params.damping == LmDamping::kDiagonal;
  double lambda = params.initial_lambda > 0.0 ? params.initial_lambda
                  : scaled                    ? kInitialScaledLambda
                                              : params.tau * std::max(system.lmMaxDiagonal(), 1e-12);
  double nu = 2.0;
  summary.termination = TerminationReason::kMaxIterations;

  for (int iteration = 1; iteration <= params.max_iterations; ++iteration) {
    const double iteration_start = nowMs();
    summary.iterations = iteration;
    IterationSummary progress;
    progress.iteration = iteration;
    Status last_failure;
    double new_chi2 = chi2;
    double accepted_rho = 0.0;
    bool at_minimum = false;
    for (int trial = 0; trial < params.max_trials && !progress.step_accepted; ++trial) {
      if (out_of_time()) break;
      ++progress.trials;
      progress.lambda = lambda;
      system.lmSetDamping(scaled, lambda);
      last_failure = system.lmSolveStep(summary);
      if (!last_failure.ok()) {
        if (last_failure.code() != StatusCode::kNotPositiveDefinite &&
            last_failure.code() != StatusCode::kNumericalError) {
          summary.termination = TerminationReason::kLinearSolverFailure;
          summary.message = last_failure.message();
          return;
        }
        // Damping cannot repair a NaN in H or b (a non-finite Jacobian): stop instead of retrying.
        const Status non_finite = system.lmFindNonFinite();
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
      system.lmPush();
      system.lmApplyStep();
      new_chi2 = system.lmEvaluateChi2();
      // Gain ratio: actual decrease over the decrease predicted by the damped model.
      const double predicted = system.lmPredictedDecrease();
      const double rho = (chi2 - new_chi2) / std::max(predicted, 1e-300);
      // A step whose predicted decrease and actual change are both below χ²'s evaluation round-off
      // (and below the relative threshold) cannot be judged by χ²: it is taken on the model's word,
      // ending the run converged, rather than discarded (which left a linear problem ~1e-9 short of
      // its closed-form optimum once λ·diag(H) damping made the first step stop 1e-4 short).
      const double round_off = kChi2RoundOff * chi2;
      const bool unresolvable = predicted <= std::min(round_off, params.relative_decrease_stop * chi2) &&
                                std::fabs(new_chi2 - chi2) <= round_off;
      if (std::isfinite(new_chi2) && (rho > 0.0 || unresolvable)) {
        system.lmDiscardTop();
        // Nielsen's update with g2o's bounds: a good step shrinks λ by a factor in [1/3, 2/3].
        const double a = 2.0 * rho - 1.0;
        lambda *= std::clamp(1.0 - a * a * a, 1.0 / 3.0, 2.0 / 3.0);
        nu = 2.0;
        accepted_rho = rho;
        progress.step_accepted = true;
      } else {
        system.lmPop();
        system.lmMarkErrorsStale();
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
    progress.chi2 = progress.step_accepted ? new_chi2 : chi2;
    progress.iteration_ms = nowMs() - iteration_start;
    if (progress.step_accepted) {
      const double previous = chi2;
      chi2 = new_chi2;
      summary.final_chi2 = chi2;
      if (params.callback) params.callback(progress);
      if (previous - chi2 <= params.relative_decrease_stop * previous || system.lmStepInfNorm() < params.step_norm_stop) {
        summary.termination = TerminationReason::kConverged;
        return;
      }
      if (out_of_time()) {
        summary.termination = TerminationReason::kTimeBudget;
        return;
      }
      if (iteration < params.max_iterations) {
        system.lmRelinearize(summary);
        if (params.model_decrease_stop > 0.0 && accepted_rho > 0.75) {
          // The model was trusted by the last step: ask its undamped Gauss–Newton step whether another
          // iteration could still lower χ² by the relative threshold.
          system.lmSetDamping(scaled, 0.0);
          if (system.lmSolveStep(summary).ok()) {
            const double predicted = system.lmPredictedDecrease();
            if (std::isfinite(predicted) && predicted <= params.model_decrease_stop * chi2) {
              summary.termination = TerminationReason::kConverged;
              return;
            }
          }
        }
      }
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
