// SPDX-License-Identifier: MIT
// The Ceres peer: the very problem of a dualgraph Graph (same vertices, edges, information matrices,
// robust kernels and fixed vertices) as a ceres::Problem with the residuals of bench/ceres_residuals.h,
// solved with Levenberg–Marquardt and SPARSE_NORMAL_CHOLESKY on SuiteSparse (CHOLMOD, as ours).
#pragma once

#include <memory>
#include <string>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/status.h"

namespace dualgraph::bench {

/// The stopping rules, set to the ones our OptimizerParams use.
struct CeresSolveOptions {
  int max_iterations = 100;           ///< = OptimizerParams::max_iterations
  double function_tolerance = 1e-9;   ///< = relative_decrease_stop (|Δcost| < tol · cost)
  double parameter_tolerance = 1e-12; ///< ≈ step_norm_stop (Ceres' is relative to |x|)
  double gradient_tolerance = 0.0;    ///< we have no gradient test: off
  int num_threads = 1;                ///< Jacobian evaluation threads (ours is single-threaded)
};

/// Ceres' summary in our terms. χ² = 2 × Ceres' cost = Σ ρ(eᵀΩe), g2o's convention.
struct CeresSolveOutcome {
  bool usable = false;       ///< CONVERGENCE or NO_CONVERGENCE (the iteration cap)
  std::string termination;   ///< Ceres' TerminationType name and message
  double initial_chi2 = 0.0;
  double final_chi2 = 0.0;
  int iterations = 0;        ///< successful + unsuccessful steps (as our `iterations`)
  int linear_solves = 0;     ///< factorisations (our `factorizations`)
  double total_ms = 0.0;     ///< Ceres' total time (preprocessing included)
  double minimizer_ms = 0.0;
  double jacobian_ms = 0.0;
  double residual_ms = 0.0;
  double linear_solver_ms = 0.0;
};

/// Owns the ceres::Problem and its parameter blocks.
class CeresPoseGraph {
 public:
  /// Mirrors `graph`; kInvalidArgument naming the first vertex, edge or robust kernel without a
  /// counterpart here (types: VertexSE3, VertexSE2, VertexPointXYZ, EdgeSE3, EdgeSE3Prior,
  /// EdgeSE3PointXYZ, EdgePointXYZPrior, EdgeSE2; kernels: Huber, Cauchy).
  static Result<std::unique_ptr<CeresPoseGraph>> create(const Graph& graph);
  ~CeresPoseGraph();
  CeresPoseGraph(const CeresPoseGraph&) = delete;
  CeresPoseGraph& operator=(const CeresPoseGraph&) = delete;

  /// Parameter blocks ← the graph's current estimates (same vertex ids as at create).
  void copyEstimatesFrom(const Graph& graph);
  /// The graph's estimates ← the parameter blocks (to evaluate χ² with our own edges).
  void copyEstimatesTo(Graph& graph) const;
  CeresSolveOutcome solve(const CeresSolveOptions& options);
  int numResidualBlocks() const;

 private:
  CeresPoseGraph();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dualgraph::bench
