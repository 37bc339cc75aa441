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
/// forming a dense inverse. Two ways to read them:
/// - `blocks(ids)`: each vertex's own block, for any number of vertices at once. With a solver that has a
///   selected inverse (CHOLMOD) the entries of H⁻¹ on the factor's pattern are computed once per `compute`
///   (Takahashi's recursion, about twice the flops of the factorisation) and every block is read from them, at
///   the price of a few factorisations for all vertices (measured in bench/README.md, "Marginals of every
///   vertex"). Other solvers (Eigen) solve each vertex's unit columns as `block(id)` does.
/// - `block(id)` / `jointBlock(ids)`: the unit columns of the requested free vertices are solved in one
///   block with the optimiser's factor and the rows of all requested vertices read from them (cost: one
///   solve with Σ tangentDim right-hand sides; the result is symmetrised); `jointBlock` gives the
///   cross-covariances too.
///
/// Covariances live in each vertex's own tangent space, i.e. the chart of its increment `oplus`, in the
/// units its edges' information matrices imply (for VertexSE3: g2o's [δt; δq] chart, m² and (q.vec)²;
/// convert with `covarianceG2oToMetric` from types/se3_math.h when metric [ρ; θ] is wanted; VertexSE2:
/// [δx δy δθ] in m² and rad²; points: m²). Any vertex type and tangent dimension: only H's pattern matters.
/// A fixed vertex is known exactly: its rows and columns are zero, wherever its id falls.
/// The gauge must be anchored: see `compute`.
/// Never prints, never throws for bad ids or state: every failure is a Status naming the id.
///
/// ```cpp
/// Optimizer optimizer(graph, makeLinearSolver(LinearSolverKind::kCholmod));
/// optimizer.optimize(params);
/// MarginalCovariance marginals;
/// if (Status s = marginals.compute(optimizer, graph); !s.ok()) { /* e.g. gauge not fixed */ }
/// Result<Eigen::MatrixXd> sigma = marginals.jointBlock({3, 7});   // 12×12 for two VertexSE3
/// Result<std::vector<Eigen::MatrixXd>> all = marginals.blocks(ids);  // one 6×6 per VertexSE3
/// ```
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class MarginalCovariance {
 public:
  /// Linearises and factorises through `optimizer.factorizeAtCurrentEstimate()` (reusing the
  /// optimiser's pattern and symbolic analysis). `graph` must be the optimiser's graph (the
  /// Optimizer does not expose it; a different graph is kInvalidArgument). Keeps pointers to both:
  /// the blocks read the optimiser's factor, so they are valid until the optimiser optimises or
  /// factorises again (not detectable here), and the graph's structure must not change in between
  /// (detected: kFailedPrecondition).
  ///
  /// Free gauge → kFailedPrecondition saying how to anchor it. A connected component of the free
  /// vertices (joined by edges between free vertices) is anchored when one of its edges touches a fixed
  /// vertex or is unary (a prior). A component that is not is suspect, since its relative edges leave H
  /// singular along a common motion of its vertices (a rigid motion of a pose graph); it is a free gauge
  /// when the factorisation fails or, when round-off lets it pass (it usually does: covariances of 1e9 m²
  /// result), when inverse iteration with the factor finds a direction v along which vᵀHv is only the
  /// round-off of its terms (vᵀHv ≤ 1e-12 · vᵀ|H|v; solvers/gauge_check.h has the measured margins). So an edge between free vertices that
  /// anchors them absolutely (a marginalisation prior over several vertices, a user's multi-vertex absolute
  /// edge) is recognised by the numbers; a component anchored only in some directions (a position-only
  /// prior on a pose graph leaves the rotation free) is not caught by the structure and gives a huge
  /// covariance or kNotPositiveDefinite. The message names the free components (with a factor and up to 8
  /// suspects, only those singular themselves; when the factorisation failed, every suspect).
  /// Other errors: the factorisation's status (kNotPositiveDefinite for another singularity);
  /// kFailedPrecondition when no free vertex is attached to an edge. After a failure every block call is
  /// kFailedPrecondition.
  Status compute(Optimizer& optimizer, const Graph& graph);

  /// Covariance of each vertex of `ids` in its own tangent space (tangentDim × tangentDim, in the order of
  /// `ids`; zero for a fixed vertex; an id may repeat). The same values as `block(id)` up to round-off
  /// (symmetric), computed from the selected inverse when the solver has one (see the class comment).
  /// Errors as `jointBlock`, except that repeated ids are allowed.
  Result<std::vector<Eigen::MatrixXd>> blocks(const std::vector<int>& ids);

  /// Covariance of one vertex in its own tangent space (tangentDim × tangentDim; zero when fixed), by
  /// solving its unit columns (`jointBlock({id})`). Same errors as `jointBlock`.
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
  /// One requested vertex: where its rows sit in the system (-1 when fixed) and in a joint result.
  struct Requested {
    int id;
    int dim;
    int system_offset;
    int result_offset;
  };
  /// Checks `ids` (known, in the system when free) and lays them out.
  Result<std::vector<Requested>> locate(const std::vector<int>& ids) const;

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
