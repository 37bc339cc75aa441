// SPDX-License-Identifier: MIT
// BlockLmSolver: the temporary graph's Levenberg–Marquardt and marginals on 6×6 blocks.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/solvers/block/block_cholesky.h"

namespace dualgraph {

/// Levenberg–Marquardt with marginal covariances for the temporary graph, on 6×6 blocks (BlockCholesky)
/// instead of the generic Optimizer's scalar CSC system, which is its oracle (`temp_solver: graph`).
///
/// The graph's edges are evaluated through their own `computeError`/`computeJacobians` (the residuals and
/// Jacobians are those of the edge types: nothing is written twice). Each free vertex attached to an edge
/// is one block, in increasing id, so the graph's ids are the elimination order (natural order, no
/// permutation); a vertex of tangent dimension < 6 (a VertexPointXYZ) is padded with an identity diagonal.
/// H = Σ Jᵀ W J and b = −Σ Jᵀ W e with W = ρ'(eᵀΩe)·Ω (the robust kernel's IRLS weight, exactly as
/// SparseSystem weights), in the units of the edges' information matrices. The iteration is the
/// generic Optimizer's LM (core/optimizer_loops.cpp): the same damping (`params.damping`: H + λI with
/// λ₀ = τ·max diag H, or H + λ·diag H clamped to [1e-6, 1e32] with λ₀ = 1e-4), gain ratio from the
/// damping actually applied, Nielsen's λ update, the same acceptance (including steps below χ²'s
/// round-off) and stopping rules (`relative_decrease_stop`, `model_decrease_stop`, `step_norm_stop`,
/// `max_iterations`, `max_trials`, `time_budget_ms`) and the same terminations. Only Levenberg–Marquardt (`params.algorithm`
/// is not read). Covariances are Σ = H⁻¹ of the undamped H at the current estimate, in each vertex's own
/// tangent space (VertexSE3: g2o's [δt; δq]), from the selected inverse of the block factor.
///
/// The object keeps its buffers between graphs (one per TemporaryGraph): `setGraph` rebuilds the
/// structure into them, and the numeric phases allocate nothing of their own once the sizes have been
/// seen (the graph's vertices keep their own undo stacks). Never prints.
class BlockLmSolver {
 public:
  /// Builds the block structure of `graph` (kept by pointer until the next call; its structure must not
  /// change meanwhile). kFailedPrecondition for an edge with an empty slot or a negative vertex id.
  Status setGraph(Graph& graph);
  /// The same for a graph given as its vertices in strictly increasing id order (null entries are
  /// skipped; every vertex an edge refers to must be among them) and its edges: the vertices and edges
  /// are kept by pointer until the next call (TemporaryPool reuses them between keyframes).
  /// kFailedPrecondition also for ids out of order; kInvalidArgument for an edge that uses one free vertex
  /// in two slots (its Jᵀ W J would need two cross terms in one block).
  Status setProblem(const std::vector<VertexBase*>& vertices, const std::vector<EdgeBase*>& edges);
  /// LM from the current estimate; the estimate is left at the last accepted state.
  SolverSummary optimize(const OptimizerParams& params);
  /// Linearises at the current estimate and computes the selected inverse of the undamped H; then
  /// `marginal`. Right after `optimize` it reuses the errors optimize left (the estimate must not be
  /// changed in between; anything else recomputes them), and when optimize stopped on the model check
  /// (`model_decrease_stop`) also the factor of that H it left. Errors: the factorisation's status (kNotPositiveDefinite, kNumericalError),
  /// kFailedPrecondition when no free vertex is attached to an edge.
  Status computeMarginals();
  /// The same for the free vertices `ids` only (BlockCholesky::selectedInverse of their blocks: the columns
  /// on their elimination-tree paths to the root, which for the temporary graph's order skips every column
  /// before the first gate's). Their covariances equal computeMarginals()'s bit for bit. kFailedPrecondition
  /// also for an id that is not a free vertex of the system (nothing computed then).
  Status computeMarginals(const std::vector<int>& ids);
  /// Covariance of free vertex `id` (tangentDim square) from the last successful `computeMarginals`;
  /// kFailedPrecondition when there is none, `id` is not in the system or its marginal was not computed.
  Result<Eigen::MatrixXd> marginal(int id) const;

 private:
  static constexpr int kMaxSlots = 4;                     ///< vertices per edge (the assembly's stack arrays)
  static constexpr int kB = BlockCholesky::kBlockDim;     ///< every block is kB × kB (smaller ones padded)
  /// Σ ρ(eᵀΩe) over every edge after computing its error (keeping each eᵀΩe in plain_chi2_); names the
  /// first non-finite edge in `first_bad`.
  double evaluateChi2(std::string* first_bad);
  /// H and b from the active edges' Jacobians (their errors must be current).
  void linearizeAndAssemble();
  /// One edge into H and b, with the AVX2 + FMA products when `avx2` (block_lm_assembly.cpp).
  void assembleEdge(size_t active_index, bool avx2);
  /// Factorises H + diag(damping_) and solves for the step.
  Status solveStep(SolverSummary& summary);
  /// After a failed solve: kNumericalError naming the first non-finite Jacobian, H or b entry.
  Status findNonFinite() const;
  void setDamping(bool scaled, double lambda);
  double dampingEnergy() const;
  void applyStep();
  /// computeMarginals for every block (`ids` null) or the blocks of `ids`.
  Status computeMarginalsOf(const std::vector<int>* ids);
  void runLevenbergMarquardt(const OptimizerParams& params, double start_ms, SolverSummary& summary);
  // The steps of runLevenbergMarquardtLoop (core/lm_loop.h, shared with Optimizer): block_lm_steps.cpp.
  template <typename System>
  friend void runLevenbergMarquardtLoop(System&, const OptimizerParams&, double, SolverSummary&);
  double lmMaxDiagonal() const;
  void lmSetDamping(bool scaled, double lambda) { setDamping(scaled, lambda); }
  Status lmSolveStep(SolverSummary& summary) { return solveStep(summary); }
  Status lmFindNonFinite() const { return findNonFinite(); }
  void lmPush();
  void lmPop();
  void lmDiscardTop();
  void lmApplyStep() { applyStep(); }
  double lmEvaluateChi2() { return evaluateChi2(nullptr); }
  double lmPredictedDecrease() const;
  double lmStepInfNorm() const;
  void lmMarkErrorsStale() { errors_stale_ = true; }
  void lmRelinearize(SolverSummary& /*summary*/) { linearizeAndAssemble(); }

  bool has_problem_ = false;
  std::vector<EdgeBase*> edges_;        ///< every edge, in the order given (χ² sums over all)
  std::vector<VertexBase*> active_;     ///< per block
  std::vector<int> block_dim_;          ///< per block: tangent dimension (≤ 6)
  std::vector<int> block_by_id_;        ///< vertex id → block, -1 when not in the system
  std::vector<EdgeBase*> active_edges_; ///< edges with at least one free vertex, graph order
  std::vector<int> active_source_;      ///< per active edge: its index in edges_
  std::vector<double> plain_chi2_;      ///< per edge of edges_: eᵀΩe from the last evaluateChi2 (the robust weight's argument)
  std::vector<int> edge_begin_;         ///< per active edge: first entry of edge_block_ (+ one past the end)
  std::vector<int> edge_block_;         ///< per edge slot: block or -1 (fixed)
  std::vector<int> pair_begin_;         ///< per active edge: first entry of pair_index_
  std::vector<int> pair_index_;         ///< per active slot pair (a ≤ b): stored block of (max, min)
  /// Per entry of pair_index_: 1 when it is the first contribution to its block in an assembly, which
  /// then assigns instead of adding (so H is not cleared first; blocks no edge touches, the fill, stay zero).
  std::vector<unsigned char> pair_first_;
  std::vector<std::pair<int, int>> pattern_;
  std::vector<unsigned char> touched_work_;  ///< setProblem: per stored block, whether an edge assembles it
  std::vector<int> marginal_blocks_;          ///< computeMarginals(ids): the blocks of ids
  BlockCholesky cholesky_;
  BlockCholesky::BlockVector h_;        ///< undamped H in BlockCholesky's storage
  Eigen::VectorXd rhs_;                 ///< b, 6 per block (padded entries zero)
  Eigen::VectorXd damping_;             ///< what is added to H's diagonal
  Eigen::VectorXd step_;
  bool marginals_ready_ = false;
  bool errors_stale_ = false;
  bool errors_current_ = false;  ///< every edge's error is at the current estimate (set by optimize only)
  bool undamped_factor_current_ = false;  ///< cholesky_ holds the factor of the undamped H at the current estimate
};

}  // namespace dualgraph
