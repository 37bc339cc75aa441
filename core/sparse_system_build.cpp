// SPDX-License-Identifier: MIT
// SparseSystem::build: the structure of H (active vertices, block pattern, CSC layout, per-edge scatter slots).
#include "dualgraph/core/sparse_system.h"

#include <algorithm>

namespace dualgraph {

namespace {

/// The block pattern of the graph's edges over `block_of` (block rows i ≤ j per column j, sorted, each
/// diagonal block included) and the largest edge dimension (error or vertex tangent) in `max_edge_dim`.
std::vector<std::vector<int>> blockPattern(const Graph& graph, const std::unordered_map<const VertexBase*, int>& block_of,
                                           int num_blocks, size_t& max_edge_dim) {
  std::vector<std::vector<int>> rows_of_column(num_blocks);
  for (int k = 0; k < num_blocks; ++k) rows_of_column[k].push_back(k);
  max_edge_dim = 0;
  for (const auto& edge : graph.edges()) {
    std::vector<int> blocks;
    size_t edge_dim = edge->errorDim();
    for (VertexBase* v : edge->vertices()) {
      if (!v->fixed()) blocks.push_back(block_of.at(v));
      edge_dim = std::max<size_t>(edge_dim, v->tangentDim());
    }
    if (blocks.empty()) continue;
    max_edge_dim = std::max(max_edge_dim, edge_dim);
    for (size_t a = 0; a < blocks.size(); ++a) {
      for (size_t b = a + 1; b < blocks.size(); ++b) {
        const int i = std::min(blocks[a], blocks[b]);
        const int j = std::max(blocks[a], blocks[b]);
        rows_of_column[j].push_back(i);
      }
    }
  }
  for (auto& rows : rows_of_column) {
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  }
  return rows_of_column;
}

}  // namespace

Status SparseSystem::build(const Graph& graph) {
  *this = SparseSystem();
  BlockOf block_of;
  DG_RETURN_IF_ERROR(orderActiveVertices(graph, block_of));
  size_t max_edge_dim = 0;
  const BlockRows rows_of_column = blockPattern(graph, block_of, static_cast<int>(active_.size()), max_edge_dim);
  const BlockRows block_row_offset = layOutColumns(rows_of_column);
  recordEdges(graph, block_of, rows_of_column, block_row_offset);
  sizeBuffers(max_edge_dim);
  return Status();
}

Status SparseSystem::orderActiveVertices(const Graph& graph, BlockOf& block_of) {
  for (const auto& edge : graph.edges()) {
    for (VertexBase* v : edge->vertices()) {
      if (v == nullptr) return Status(StatusCode::kFailedPrecondition, "edge with an empty vertex slot");
      if (!v->fixed()) block_of.emplace(v, -1);
    }
  }
  for (const auto& [id, vertex] : graph.vertices()) {
    auto it = block_of.find(vertex.get());
    if (it == block_of.end()) continue;
    it->second = static_cast<int>(active_.size());
    active_.push_back(vertex.get());
    active_offset_.push_back(dim_);
    offset_by_vertex_.emplace(vertex.get(), dim_);
    dim_ += vertex->tangentDim();
  }
  return Status();
}

SparseSystem::BlockRows SparseSystem::layOutColumns(const BlockRows& rows_of_column) {
  const int num_blocks = static_cast<int>(active_.size());
  BlockRows block_row_offset(num_blocks);
  col_ptr_.assign(dim_ + 1, 0);
  for (int j = 0; j < num_blocks; ++j) {
    const int dj = active_[j]->tangentDim();
    int above = 0;
    for (int i : rows_of_column[j]) {
      block_row_offset[j].push_back(above);
      if (i != j) above += active_[i]->tangentDim();
    }
    for (int c = 0; c < dj; ++c) {
      const int col = active_offset_[j] + c;
      col_ptr_[col + 1] = col_ptr_[col] + above + c + 1;
    }
  }
  row_index_.resize(col_ptr_[dim_]);
  diagonal_index_.resize(dim_);
  for (int j = 0; j < num_blocks; ++j) {
    for (int c = 0; c < active_[j]->tangentDim(); ++c) {
      const int col = active_offset_[j] + c;
      int pos = col_ptr_[col];
      for (int i : rows_of_column[j]) {
        const int rows = i == j ? c + 1 : active_[i]->tangentDim();
        for (int r = 0; r < rows; ++r) row_index_[pos++] = active_offset_[i] + r;
      }
      diagonal_index_[col] = pos - 1;
    }
  }
  values_.assign(row_index_.size(), 0.0);
  undamped_diagonal_.assign(dim_, 0.0);
  rhs_ = Eigen::VectorXd::Zero(dim_);
  return block_row_offset;
}

void SparseSystem::recordEdges(const Graph& graph, const BlockOf& block_of, const BlockRows& rows_of_column,
                               const BlockRows& block_row_offset) {
  auto slot_for = [&](int bi, int bj) {
    const bool transposed = bi > bj;
    const int i = std::min(bi, bj);
    const int j = std::max(bi, bj);
    const auto& rows = rows_of_column[j];
    const size_t r = std::lower_bound(rows.begin(), rows.end(), i) - rows.begin();
    return BlockSlot{active_offset_[j], block_row_offset[j][r], transposed, i == j};
  };
  for (const auto& edge : graph.edges()) {
    const auto& vs = edge->vertices();
    if (std::all_of(vs.begin(), vs.end(), [](const VertexBase* v) { return v->fixed(); })) continue;
    active_edges_.push_back(edge.get());
    const int m = edge->errorDim();
    const bool uniform = std::all_of(vs.begin(), vs.end(), [m](const VertexBase* v) {
      return v->fixed() || v->tangentDim() == m;
    });
    edge_kernel_.push_back(!uniform ? EdgeKernel::kDynamic
                           : m == 6 ? EdgeKernel::kFixed6
                           : m == 3 ? EdgeKernel::kFixed3
                                    : EdgeKernel::kDynamic);
    edge_vertex_begin_.push_back(static_cast<int>(edge_vertex_offset_.size()));
    edge_slot_begin_.push_back(static_cast<int>(slots_.size()));
    for (size_t a = 0; a < vs.size(); ++a) {
      edge_vertex_offset_.push_back(vs[a]->fixed() ? -1 : offset_by_vertex_.at(vs[a]));
      if (vs[a]->fixed()) continue;
      for (size_t b = a; b < vs.size(); ++b) {
        if (!vs[b]->fixed()) slots_.push_back(slot_for(block_of.at(vs[a]), block_of.at(vs[b])));
      }
    }
  }
  edge_vertex_begin_.push_back(static_cast<int>(edge_vertex_offset_.size()));
  edge_slot_begin_.push_back(static_cast<int>(slots_.size()));
  // An edge's blocks lie in the columns of its free vertices; the last of them ends its reach.
  edge_values_end_.clear();
  for (const EdgeBase* edge : active_edges_) {
    int last_block = -1;
    for (const VertexBase* v : edge->vertices()) {
      if (!v->fixed()) last_block = std::max(last_block, block_of.at(v));
    }
    edge_values_end_.push_back(col_ptr_[active_offset_[last_block] + active_[last_block]->tangentDim()]);
  }
}

void SparseSystem::sizeBuffers(size_t max_edge_dim) {
  scratch_stride_ = max_edge_dim * max_edge_dim;
  scratch_.assign(2 * scratch_stride_ + max_edge_dim, 0.0);
  // Per-edge products: the rhs part of every active vertex, then every block, in slot order.
  size_t max_edge_buffer = 0;
  for (size_t e = 0; e < active_edges_.size(); ++e) {
    size_t size = 0;
    const auto& vs = active_edges_[e]->vertices();
    for (size_t a = 0; a < vs.size(); ++a) {
      if (vs[a]->fixed()) continue;
      size += vs[a]->tangentDim();
      for (size_t b = a; b < vs.size(); ++b) {
        if (!vs[b]->fixed()) size += static_cast<size_t>(vs[a]->tangentDim()) * vs[b]->tangentDim();
      }
    }
    max_edge_buffer = std::max(max_edge_buffer, size);
  }
  edge_buffer_.assign(max_edge_buffer, 0.0);
}

}  // namespace dualgraph
