// SPDX-License-Identifier: MIT
// MarginalCovariance: marginal covariances of chosen vertices from the optimiser's factor.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/core/status.h"
#include "dualgraph/solvers/linear_solver_factory.h"

namespace dualgraph {

/// Marginal covariances of vertex blocks at the graph's current estimate, from the sparse Cholesky
/// factor of H = Σ Jᵀ W J (W = ρ'(eᵀΩe)·Ω with a robust kernel, Ω without; no damping), without
/// forming a dense inverse: the unit columns of every requested free vertex are solved in one block
/// with the optimiser's factor, and the rows of all requested vertices are read from them (cost: one
/// solve with Σ tangentDim right-hand sides; the result is symmetrised).
///
/// Covariances live in each vertex's own tangent space, in the units its edges' information
/// matrices imply (for VertexSE3: g2o's [δt; δq] chart, m² and (q.vec)²; convert with
/// `covarianceG2oToMetric` from types/se3_math.h when metric [ρ; θ] is wanted).
/// A fixed vertex is known exactly: its rows and columns are zero, wherever its id falls.
/// Never prints, never throws for bad ids or state: every failure is a Status naming the id.
///
/// ```cpp
/// Optimizer optimizer(graph, makeLinearSolver(LinearSolverKind::kCholmod));
/// optimizer.optimize(params);
/// MarginalCovariance marginals;
/// if (Status s = marginals.compute(optimizer, graph); !s.ok()) { /* e.g. gauge not fixed */ }
/// Result<Eigen::MatrixXd> sigma = marginals.jointBlock({3, 7});   // 12×12 for two VertexSE3
/// ```
class MarginalCovariance {
 public:
  /// Linearises and factorises through `optimizer.factorizeAtCurrentEstimate()` (reusing the
  /// optimiser's pattern and symbolic analysis). `graph` must be the optimiser's graph (the
  /// Optimizer does not expose it; a different graph is kInvalidArgument). Keeps pointers to both:
  /// the blocks read the optimiser's factor, so they are valid until the optimiser optimises or
  /// factorises again (not detectable here), and the graph's structure must not change in between
  /// (detected: kFailedPrecondition). Errors: the factorisation's status, e.g. kNotPositiveDefinite
  /// when H is singular (gauge freedom: nothing fixed); kFailedPrecondition when no free vertex is
  /// attached to an edge. After a failure every block call is kFailedPrecondition.
  Status compute(Optimizer& optimizer, const Graph& graph);

  /// Covariance of one vertex in its own tangent space (tangentDim × tangentDim; zero when fixed).
  /// Same errors as `jointBlock`.
  Result<Eigen::MatrixXd> block(int id);

  /// Joint covariance of several vertices (Σ tangentDim square), blocks in the order of `ids`;
  /// rows and columns of fixed vertices are zero. Empty `ids` → 0×0. Errors: kFailedPrecondition
  /// when `compute` was not called or failed, or the graph's structure (vertices, edges, fixed
  /// flags) changed since; kNotFound for an unknown id; kFailedPrecondition for a free vertex not
  /// attached to any edge (not in the system: its covariance is unbounded); kInvalidArgument for a
  /// duplicate id; a failing solve's status. Every message names the id at fault.
  Result<Eigen::MatrixXd> jointBlock(const std::vector<int>& ids);

 private:
  Status checkCurrent() const;

  Optimizer* optimizer_ = nullptr;  ///< null until a successful compute
  const Graph* graph_ = nullptr;
  uint64_t structure_version_ = 0;
  /// Fixed flags at compute time: they can be flipped on a vertex without bumping the version.
  std::vector<std::pair<const VertexBase*, bool>> fixed_snapshot_;
  int dim_ = 0;              ///< rows of H at compute()
  Eigen::MatrixXd units_;    ///< the requested unit columns
  Eigen::MatrixXd solved_;   ///< H⁻¹ times them (only the requested rows are meaningful)
  std::vector<int> rows_;    ///< the requested rows of the system
};

/// Convenience: builds an Optimizer with a solver of `kind` over `graph`, computes at the current
/// estimate and returns `jointBlock(ids)` (errors as `compute` and `jointBlock`).
Result<Eigen::MatrixXd> computeMarginalCovariance(Graph& graph, const std::vector<int>& ids,
                                                  LinearSolverKind kind = LinearSolverKind::kCholmod);

}  // namespace dualgraph
