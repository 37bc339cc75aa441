// SPDX-License-Identifier: MIT
// SparseSystem: a graph's normal equations H Δ = b in upper CSC, built once per structure.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/linear_solver.h"

namespace dualgraph {

/// The normal equations H Δ = b of a graph, H = Σ Jᵀ W J and b = −Σ Jᵀ W e over the edges
/// (W = ρ'(eᵀΩe)·Ω), in the block-sparse upper-triangular CSC layout of `SparseMatrixView`.
///
/// `build()` fixes the structure once per graph structure: the active vertices (not fixed and
/// attached to at least one edge) get consecutive scalar offsets in increasing id order, the block
/// pattern is laid out column by column, and every edge records where each of its blocks lands in
/// the value array. `assemble()` then only refills values; `setDamping(λ)` adds λ to the diagonal
/// without re-assembling.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class SparseSystem {
 public:
  /// Builds the structure for the current graph. Fails when an edge's vertices are missing.
  Status build(const Graph& graph);

  /// Fills H and b from the edges' current errors and Jacobians (call `EdgeBase::linearize` first).
  /// Same as `beginAssembly(); assembleEdges(0, activeEdges().size()); finishAssembly();`.
  void assemble();
  /// The same in pieces, so a caller can linearise a run of edges and add it while its Jacobians
  /// are still in cache: clears b, ...
  void beginAssembly();
  /// ... adds active edges [begin, end) (their errors and Jacobians must be current; every active
  /// edge once, in increasing order), clearing the columns of H they reach first, ...
  void assembleEdges(size_t begin, size_t end);
  /// ... and records the undamped diagonal once every edge is in.
  void finishAssembly();
  /// H ← H_undamped + λ I (the value array keeps the undamped diagonal aside).
  void setDamping(double lambda);
  /// H ← H_undamped + λ D, D = diag(H_undamped) clamped to [min_diagonal, max_diagonal]
  /// (Marquardt's scale-invariant damping; the clamp keeps a zero or huge pivot from making the
  /// damped system singular or frozen).
  void setScaledDamping(double lambda, double min_diagonal, double max_diagonal);
  /// Σ_k (H_kk − H_undamped_kk) Δ_k²: the damping term ΔᵀΛΔ of the current damping, for LM's
  /// predicted decrease Δᵀ(ΛΔ + b). `delta` has `dim()` entries.
  double dampingEnergy(const double* delta) const;

  /// x ← x ⊞ Δ for every active vertex; `delta` has `dim()` entries.
  void applyUpdate(const double* delta) const;

  int dim() const { return dim_; }
  SparseMatrixView matrix() const;
  /// b = −Σ Jᵀ W e
  const Eigen::VectorXd& rhs() const { return rhs_; }
  /// Largest diagonal entry of the undamped H (LM's initial damping scale).
  double maxDiagonal() const;
  const std::vector<VertexBase*>& activeVertices() const { return active_; }
  /// Scalar offset of an active vertex in Δ, or -1 when the vertex is not active.
  int offsetOf(const VertexBase* vertex) const;
  /// Edges with at least one active vertex, in graph order.
  const std::vector<EdgeBase*>& activeEdges() const { return active_edges_; }

 private:
  struct BlockSlot {
    int first_column;  ///< scalar column of the block's first column
    int row_offset;    ///< offset of the block's first row within each of those columns
    bool transposed;   ///< the edge pair (a,b) lands as (b,a) in the upper triangle
    bool diagonal;
  };
  enum class EdgeKernel : unsigned char { kDynamic, kFixed6, kFixed3 };
  using BlockOf = std::unordered_map<const VertexBase*, int>;
  /// The block pattern: for each block column j, the sorted block rows i ≤ j.
  using BlockRows = std::vector<std::vector<int>>;
  // The steps of build():
  /// Active vertices (not fixed, touched by an edge) in increasing id: offsets and `block_of` (vertex → block).
  Status orderActiveVertices(const Graph& graph, BlockOf& block_of);
  /// The scalar CSC layout of the upper triangle from the block pattern; per column j, the row offset of
  /// each block of `rows_of_column[j]` within the column (returned).
  BlockRows layOutColumns(const BlockRows& rows_of_column);
  /// Per active edge: its assembly kernel, its vertices' offsets, its blocks' scatter slots, its reach.
  void recordEdges(const Graph& graph, const BlockOf& block_of, const BlockRows& rows_of_column,
                   const BlockRows& block_row_offset);
  /// The scratch and per-edge buffers, sized to the largest edge (`max_edge_dim` rows).
  void sizeBuffers(size_t max_edge_dim);
  /// Adds an edge whose error and free vertices all have dimension N straight into H and b.
  template <int N>
  void assembleEdgeFixed(size_t edge_index);
  /// Writes any other edge's Jᵀ W e parts and Jᵀ W J blocks (slot order) to `out`.
  void computeEdgeDynamic(size_t edge_index, double* out);
  /// The same for an edge that supplies its constant JᵀΩJ (`hessian`, EdgeBase::constantHessianData):
  /// the blocks are copied from it, b from the Jacobians and `weighted_error` = Ω e.
  void computeEdgeFromConstantHessian(const EdgeBase& edge, const double* hessian, const double* weighted_error,
                                      int v_begin, int num_slots, double* out) const;
  /// Adds what `computeEdge*` wrote into H and b.
  void scatterEdge(size_t edge_index, const double* in);
  void scatter(const BlockSlot& slot, const double* block, int rows, int cols);

  int dim_ = 0;
  std::vector<VertexBase*> active_;
  std::vector<int> active_offset_;           ///< scalar offset per active vertex
  std::unordered_map<const VertexBase*, int> offset_by_vertex_;
  std::vector<EdgeBase*> active_edges_;
  std::vector<EdgeKernel> edge_kernel_;      ///< per active edge: which assembly kernel fits it
  std::vector<int> edge_vertex_offset_;      ///< per edge slot: scalar offset or -1 (fixed)
  std::vector<int> edge_vertex_begin_;       ///< per edge: index into edge_vertex_offset_
  std::vector<BlockSlot> slots_;             ///< per edge, pairs a ≤ b of active slots
  std::vector<int> edge_slot_begin_;
  std::vector<int> col_ptr_;
  std::vector<int> row_index_;
  std::vector<double> values_;
  /// Per active edge: end (in values_) of the last column its blocks reach. H is cleared up to a
  /// watermark just before the edges that reach further, so each part is zeroed right before it
  /// is added to (still in cache) rather than all 2 MB up front.
  std::vector<int> edge_values_end_;
  size_t values_cleared_ = 0;
  std::vector<int> diagonal_index_;          ///< position of H(k,k) in values_
  std::vector<double> undamped_diagonal_;
  Eigen::VectorXd rhs_;
  std::vector<double> edge_buffer_;          ///< one edge's Jᵀ W e and Jᵀ W J blocks before scattering
  std::vector<double> scratch_;              ///< [J_aᵀW | block | We], sized to the largest edge
  size_t scratch_stride_ = 0;
};

}  // namespace dualgraph
