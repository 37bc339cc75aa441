// SPDX-License-Identifier: MIT
// Optimizer: Levenberg–Marquardt and Gauss–Newton over a Graph, with its parameters and summaries.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/linear_solver.h"
#include "dualgraph/core/sparse_system.h"

namespace dualgraph {

enum class Algorithm { kLevenbergMarquardt, kGaussNewton };

/// Levenberg–Marquardt's damping matrix.
enum class LmDamping {
  /// H + λI, λ₀ = tau · max diag(H): g2o's choice, the engine's default. One λ for every unknown,
  /// so on a graph whose diagonal spans orders of magnitude (priors and detections beside weakly
  /// constrained poses) the first steps are damped hard where H is small.
  kIdentity,
  /// H + λ·diag(H) (diagonal clamped to [1e-6, 1e32]), λ₀ = 1e-4: Marquardt's scale-invariant
  /// form, what Ceres' Levenberg–Marquardt does with its default Jacobi scaling (λ₀ = 1 / its
  /// initial trust-region radius 1e4). Each unknown is damped relative to its own curvature.
  kDiagonal,
};
const char* lmDampingName(LmDamping damping);

/// The constants of the LM loop, shared by `Optimizer` and the temporary graph's block solver
/// (solvers/block/block_lm_solver.h), so both take the same steps.
namespace lm_constants {
/// LmDamping::kDiagonal: Ceres' defaults (1 / initial_trust_region_radius, min/max_lm_diagonal).
inline constexpr double kInitialScaledLambda = 1e-4;
inline constexpr double kMinScaledDiagonal = 1e-6;
inline constexpr double kMaxScaledDiagonal = 1e32;
/// Relative round-off of an evaluated χ² (a sum of up to millions of positive terms: ≈ 4500 ε).
inline constexpr double kChi2RoundOff = 1e-12;
}  // namespace lm_constants

/// Why `Optimizer::optimize` stopped. The estimate is always left at the last accepted state
/// (bit for bit: rejected trials are undone from a saved copy, never by a reverse step); when
/// nothing was accepted, at the start.
///
/// Faults and what each gives (test/core/optimizer_faults_test.cpp, both solvers):
/// - gauge freedom (nothing fixed, no prior) or an unanchored component: LM's damping λI makes
///   every trial system positive definite and its steps have no component along the free gauge
///   beyond round-off, so LM converges (kConverged) to the optimum of the anchored problem. GN
///   either meets a non-positive pivot (kNotPositiveDefinite, start kept) or, when round-off
///   pivots pass, walks off along the gauge and ends above the initial χ² (kNoDecrease, start kept).
/// - all vertices fixed: kNothingToOptimize; a NaN/Inf error at the start: kInvalidInput naming
///   the edge and its line; a NaN/Inf Jacobian: kNumericalFailure naming the edge and vertex
///   (no damping retries: λ cannot repair a NaN).
/// - a system that is not positive definite at every damping level (e.g. an indefinite
///   information matrix set through the API): kNotPositiveDefinite after `max_trials` factorisations.
/// - a divergent step (χ² non-finite or, for LM, not lower): LM rejects it and retries with more
///   damping, then kNoDecrease; GN stops with kNoDecrease at the previous estimate.
enum class TerminationReason {
  kConverged,            ///< an accepted step decreased χ² (relatively) or moved less than the thresholds
  kMaxIterations,        ///< the iteration cap was reached
  /// LM found no decreasing step within `max_trials` damping increases; GN took a step to a
  /// non-finite χ², or ended above the initial χ² and restored the start (GN has no step control)
  kNoDecrease,
  kTimeBudget,           ///< the wall-time budget was used up
  kNotPositiveDefinite,  ///< the system could not be factorised (GN, or LM at every damping level)
  kInvalidInput,         ///< non-finite χ² at the start (an edge's error or information is NaN/Inf)
  kNothingToOptimize,    ///< no free vertex is attached to an edge
  kLinearSolverFailure,  ///< the linear solver failed for another reason (message says why)
  kNumericalFailure,     ///< H or b became non-finite (an edge's Jacobian is NaN/Inf; message names the vertex)
};
const char* terminationReasonName(TerminationReason reason);

/// One line of the optimiser's progress, passed to the verbosity callback after each iteration.
struct IterationSummary {
  int iteration = 0;          ///< 1-based
  double chi2 = 0.0;          ///< robust χ² after the iteration
  double lambda = 0.0;        ///< LM damping used by the accepted (or last) trial
  int trials = 0;             ///< factorisations this iteration
  bool step_accepted = false;
  double iteration_ms = 0.0;
};

/// Parameters of `Optimizer::optimize`, with g2o-like defaults.
struct OptimizerParams {
  Algorithm algorithm = Algorithm::kLevenbergMarquardt;
  int max_iterations = 100;
  /// Stop when an accepted step lowers χ² by less than this fraction of the previous χ².
  double relative_decrease_stop = 1e-9;
  /// LM: after an accepted step with gain ratio above 0.75, factorise the undamped H at the new estimate
  /// and stop there (kConverged) when its Gauss–Newton step predicts a χ² decrease below this fraction
  /// of χ²: the confirming iteration (a damped factorisation, a trial step, a χ² evaluation) is saved,
  /// and the system is left holding that undamped factorisation (the temporary graph's marginals reuse
  /// it). 0 = off (the default). When the check does not stop, its factorisation is spent.
  double model_decrease_stop = 0.0;
  /// Also stop when the largest entry of an accepted step is below this (tangent units); this ends
  /// zero-residual problems, whose χ² keeps falling by large fractions down to round-off.
  double step_norm_stop = 1e-12;
  /// Wall-time budget in milliseconds; 0 = none. Checked between trials.
  double time_budget_ms = 0.0;
  LmDamping damping = LmDamping::kIdentity;
  /// LM, kIdentity: initial λ = tau · max diag(H) (g2o's default 1e-5). Both kinds: `initial_lambda`
  /// > 0 overrides the initial λ (kDiagonal's default is 1e-4).
  double tau = 1e-5;
  double initial_lambda = 0.0;
  /// LM: damping increases allowed per iteration before giving up (g2o: 10).
  int max_trials = 10;
  /// Called after every iteration; must not modify the graph.
  std::function<void(const IterationSummary&)> callback;
};

/// Outcome of `optimize`: termination, χ² (robust, g2o's convention Σ ρ(eᵀΩe)) and time per phase.
struct SolverSummary {
  TerminationReason termination = TerminationReason::kMaxIterations;
  std::string message;  ///< human-readable detail (which edge was NaN, solver error, ...)
  int iterations = 0;   ///< iterations performed (accepted or not)
  double initial_chi2 = 0.0;
  double final_chi2 = 0.0;
  int vertices = 0;          ///< free vertices in the system
  int edges = 0;             ///< edges in the system
  int dimension = 0;         ///< rows of H
  long nonzeros = 0;         ///< stored entries of H's upper triangle
  int factorizations = 0;
  bool structure_rebuilt = false;
  double structure_ms = 0.0;  ///< pattern build + symbolic analysis (only when rebuilt)
  double linearize_ms = 0.0;
  double assemble_ms = 0.0;
  double factorize_ms = 0.0;
  double solve_ms = 0.0;
  double update_ms = 0.0;     ///< applying steps and re-evaluating χ²
  double total_ms = 0.0;
  std::string linear_solver;
  /// True for the reasons that mean "a usable optimum or the budget was reached".
  bool usable() const;
};

/// Levenberg–Marquardt (Nielsen's damping update, as g2o) and Gauss–Newton over a `Graph`, with a
/// pluggable linear solver. LM accepts a step when χ² decreases, and also, ending the run as converged,
/// a step whose predicted decrease is below both the relative threshold and χ²'s round-off (1e-12 χ²)
/// and whose χ² change is within that round-off: χ² cannot judge it, so χ² is monotone up to 1e-12
/// relative and a linear problem ends at its optimum to round-off. The sparsity pattern and the solver's symbolic analysis are cached and
/// rebuilt only when the graph's structure (vertices, edges, fixed flags) changed, so repeated
/// calls on a growing graph pay only for numeric work. The optimiser never prints.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class Optimizer {
 public:
  /// `solver` must not be null.
  Optimizer(Graph& graph, std::unique_ptr<LinearSolver> solver);

  SolverSummary optimize(const OptimizerParams& params);

  /// The system as of the last optimize (structure and values at the last linearisation).
  const SparseSystem& system() const { return system_; }
  LinearSolver& linearSolver() { return *solver_; }
  /// Rebuilds the structure if stale; then linearises, assembles and factorises H at the current
  /// estimate without damping (for marginal covariances).
  Status factorizeAtCurrentEstimate();

 private:
  Status ensureStructure(SolverSummary& summary);
  bool structureIsCurrent() const;
  /// Recomputes every edge's error; Σ ρ(eᵀΩe). Names the first non-finite edge in `first_bad`.
  double evaluateChi2(std::string* first_bad);
  void linearizeAndAssemble(SolverSummary& summary);
  void runLevenbergMarquardt(const OptimizerParams& params, SolverSummary& summary);
  // The steps of runLevenbergMarquardtLoop (core/lm_loop.h), which runLevenbergMarquardt calls.
  template <typename System>
  friend void runLevenbergMarquardtLoop(System&, const OptimizerParams&, double, SolverSummary&);
  double lmMaxDiagonal() const { return system_.maxDiagonal(); }
  void lmSetDamping(bool scaled, double lambda);
  Status lmSolveStep(SolverSummary& summary) { return solveStep(summary); }
  Status lmFindNonFinite() const { return findNonFiniteSystem(); }
  void lmPush();
  void lmPop();
  void lmDiscardTop();
  void lmApplyStep() { system_.applyUpdate(step_.data()); }
  double lmEvaluateChi2() { return evaluateChi2(nullptr); }
  double lmPredictedDecrease() const;
  double lmStepInfNorm() const { return step_.lpNorm<Eigen::Infinity>(); }
  void lmMarkErrorsStale() { errors_stale_ = true; }
  void lmRelinearize(SolverSummary& summary) { linearizeAndAssemble(summary); }
  void runGaussNewton(const OptimizerParams& params, SolverSummary& summary);
  /// Factorises the current values and solves for Δ into step_.
  Status solveStep(SolverSummary& summary);
  /// After a failed solve only (O(edges)): a kNumericalError naming the first edge whose Jacobian
  /// (or, failing that, the row of H or b) is not finite; OK when H and b are finite.
  Status findNonFiniteSystem() const;
  /// Gauss–Newton's iterations proper; runGaussNewton wraps them with the start-state rule.
  void runGaussNewtonSteps(const OptimizerParams& params, SolverSummary& summary);

  Graph& graph_;
  std::unique_ptr<LinearSolver> solver_;
  SparseSystem system_;
  uint64_t built_version_ = ~uint64_t{0};
  std::vector<std::pair<const VertexBase*, bool>> fixed_snapshot_;
  Eigen::VectorXd step_;
  double start_time_ms_ = 0.0;
  bool errors_stale_ = false;  ///< edges hold errors of a rejected trial
};

}  // namespace dualgraph
