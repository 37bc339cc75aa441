// SPDX-License-Identifier: MIT
#include "core/sparse_system.h"

#include <algorithm>
#include <string>

namespace dualgraph {

Status SparseSystem::build(const Graph& graph) {
  *this = SparseSystem();
  // Active vertices: not fixed and touched by an edge, in increasing id order (deterministic).
  std::unordered_map<const VertexBase*, int> block_of;
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
  const int num_blocks = static_cast<int>(active_.size());

  // Block pattern: for each block column j, the sorted block rows i <= j.
  std::vector<std::vector<int>> rows_of_column(num_blocks);
  for (int k = 0; k < num_blocks; ++k) rows_of_column[k].push_back(k);
  size_t max_edge_dim = 0;
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

  // Scalar CSC layout of the upper triangle; block_row_offset[j][r] = row offset of rows[r].
  std::vector<std::vector<int>> block_row_offset(num_blocks);
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

  // Per-edge scatter slots.
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
  return Status();
}

SparseMatrixView SparseSystem::matrix() const {
  SparseMatrixView view;
  view.n = dim_;
  view.col_ptr = col_ptr_.data();
  view.row_index = row_index_.data();
  view.values = values_.data();
  return view;
}

int SparseSystem::offsetOf(const VertexBase* vertex) const {
  const auto it = offset_by_vertex_.find(vertex);
  return it == offset_by_vertex_.end() ? -1 : it->second;
}

double SparseSystem::maxDiagonal() const {
  double m = 0.0;
  for (double d : undamped_diagonal_) m = std::max(m, d);
  return m;
}

void SparseSystem::assemble() {
  beginAssembly();
  assembleEdges(0, active_edges_.size());
  finishAssembly();
}

void SparseSystem::beginAssembly() {
  values_cleared_ = 0;
  rhs_.setZero();
}

void SparseSystem::assembleEdges(size_t begin, size_t end) {
  size_t reach = values_cleared_;
  for (size_t e = begin; e < end; ++e) reach = std::max(reach, static_cast<size_t>(edge_values_end_[e]));
  if (reach > values_cleared_) {
    std::fill(values_.begin() + values_cleared_, values_.begin() + reach, 0.0);
    values_cleared_ = reach;
  }
  // Fixed-size edges scatter straight from registers; others through a small per-edge buffer.
  for (size_t e = begin; e < end; ++e) {
    switch (edge_kernel_[e]) {
      case EdgeKernel::kFixed6: assembleEdgeFixed<6>(e); break;
      case EdgeKernel::kFixed3: assembleEdgeFixed<3>(e); break;
      case EdgeKernel::kDynamic:
        computeEdgeDynamic(e, edge_buffer_.data());
        scatterEdge(e, edge_buffer_.data());
        break;
    }
  }
}

void SparseSystem::finishAssembly() {
  std::fill(values_.begin() + values_cleared_, values_.end(), 0.0);  // nothing normally: every column is reached
  values_cleared_ = values_.size();
  for (int k = 0; k < dim_; ++k) undamped_diagonal_[k] = values_[diagonal_index_[k]];
}

void SparseSystem::setDamping(double lambda) {
  for (int k = 0; k < dim_; ++k) values_[diagonal_index_[k]] = undamped_diagonal_[k] + lambda;
}

void SparseSystem::setScaledDamping(double lambda, double min_diagonal, double max_diagonal) {
  for (int k = 0; k < dim_; ++k) {
    const double d = undamped_diagonal_[k];
    values_[diagonal_index_[k]] = d + lambda * std::clamp(d, min_diagonal, max_diagonal);
  }
}

double SparseSystem::dampingEnergy(const double* delta) const {
  double sum = 0.0;
  for (int k = 0; k < dim_; ++k) sum += (values_[diagonal_index_[k]] - undamped_diagonal_[k]) * delta[k] * delta[k];
  return sum;
}

/// Fixed-size kernel for edges whose error and active vertices all have dimension N (SE(3) and
/// SE(2) pose graphs): nothing is sized at run time. With G_b = w Ω J_b (Ω symmetric), every
/// block is J_aᵀ G_b, a matrix of dot products of columns, added straight into H's columns: the
/// upper triangle only for the diagonal blocks, J_bᵀ G_a for a block stored transposed. b_a is
/// −G_aᵀ e.
template <int N>
void SparseSystem::assembleEdgeFixed(size_t edge_index) {
  using Square = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;
  using SquareMap = Eigen::Map<const Square>;
  const EdgeBase& edge = *active_edges_[edge_index];
  const SquareMap information(edge.informationData());
  const Eigen::Map<const Vector> error(edge.errorData());
  const RobustKernel* kernel = edge.robustKernel();
  const double weight = kernel != nullptr ? kernel->robustify(edge.chi2())[1] : 1.0;

  const int v_begin = edge_vertex_begin_[edge_index];
  const int num_slots = edge_vertex_begin_[edge_index + 1] - v_begin;
  constexpr int kMaxSlots = 4;
  if (num_slots > kMaxSlots) {  // hyper-edges with many fixed-size vertices: the general path
    computeEdgeDynamic(edge_index, edge_buffer_.data());
    scatterEdge(edge_index, edge_buffer_.data());
    return;
  }
  Square weighted[kMaxSlots];  // G_a = w Ω J_a for the active slots
  const double* jacobians[kMaxSlots];
  for (int a = 0; a < num_slots; ++a) {
    const int offset_a = edge_vertex_offset_[v_begin + a];
    if (offset_a < 0) continue;
    jacobians[a] = edge.jacobianData(a);
    if (kernel != nullptr) {
      weighted[a].noalias() = weight * (information * SquareMap(jacobians[a]));
    } else {
      weighted[a].noalias() = information * SquareMap(jacobians[a]);
    }
    rhs_.template segment<N>(offset_a).noalias() -= weighted[a].transpose() * error;
  }
  int slot_index = edge_slot_begin_[edge_index];
  for (int a = 0; a < num_slots; ++a) {
    if (edge_vertex_offset_[v_begin + a] < 0) continue;
    for (int b = a; b < num_slots; ++b) {
      if (edge_vertex_offset_[v_begin + b] < 0) continue;
      const BlockSlot& slot = slots_[slot_index++];
      // The stored block is J_rᵀ G_c: (a, b), or (b, a) when it lands transposed.
      const int r = slot.transposed ? b : a;
      const int c = slot.transposed ? a : b;
      const SquareMap jacobian_r(jacobians[r]);
      const Square& weighted_c = weighted[c];
      double* values = values_.data() + slot.row_offset;
      const int* col_ptr = col_ptr_.data() + slot.first_column;
      if (slot.diagonal) {
        for (int col = 0; col < N; ++col) {
          double* column = values + col_ptr[col];
          for (int row = 0; row <= col; ++row) column[row] += jacobian_r.col(row).dot(weighted_c.col(col));
        }
      } else {
        for (int col = 0; col < N; ++col) {
          double* column = values + col_ptr[col];
          for (int row = 0; row < N; ++row) column[row] += jacobian_r.col(row).dot(weighted_c.col(col));
        }
      }
    }
  }
}

void SparseSystem::computeEdgeDynamic(size_t edge_index, double* out) {
  using MatrixMap = Eigen::Map<Eigen::MatrixXd>;
  using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd>;
  const EdgeBase& edge = *active_edges_[edge_index];
  const int m = edge.errorDim();
  const ConstMatrixMap information(edge.informationData(), m, m);
  const Eigen::Map<const Eigen::VectorXd> error(edge.errorData(), m);
  double weight = 1.0;
  if (const RobustKernel* kernel = edge.robustKernel()) weight = kernel->robustify(edge.chi2())[1];

  MatrixMap weighted_error(scratch_.data() + 2 * scratch_stride_, m, 1);
  weighted_error.noalias() = weight * (information * error);
  const int v_begin = edge_vertex_begin_[edge_index];
  const int num_slots = edge_vertex_begin_[edge_index + 1] - v_begin;
  for (int a = 0; a < num_slots; ++a) {
    if (edge_vertex_offset_[v_begin + a] < 0) continue;
    const int da = edge.vertex(a)->tangentDim();
    const ConstMatrixMap jacobian_a(edge.jacobianData(a), m, da);
    MatrixMap(out, da, 1).noalias() = -(jacobian_a.transpose() * weighted_error);
    out += da;
    MatrixMap jt_w(scratch_.data(), da, m);  // J_aᵀ W
    jt_w.noalias() = weight * (jacobian_a.transpose() * information);
    for (int b = a; b < num_slots; ++b) {
      if (edge_vertex_offset_[v_begin + b] < 0) continue;
      const int db = edge.vertex(b)->tangentDim();
      MatrixMap(out, da, db).noalias() = jt_w * ConstMatrixMap(edge.jacobianData(b), m, db);
      out += da * db;
    }
  }
}

void SparseSystem::scatterEdge(size_t edge_index, const double* in) {
  const EdgeBase& edge = *active_edges_[edge_index];
  const int v_begin = edge_vertex_begin_[edge_index];
  const int num_slots = edge_vertex_begin_[edge_index + 1] - v_begin;
  int slot = edge_slot_begin_[edge_index];
  for (int a = 0; a < num_slots; ++a) {
    const int offset_a = edge_vertex_offset_[v_begin + a];
    if (offset_a < 0) continue;
    const int da = edge.vertex(a)->tangentDim();
    for (int r = 0; r < da; ++r) rhs_[offset_a + r] += in[r];
    in += da;
    for (int b = a; b < num_slots; ++b) {
      if (edge_vertex_offset_[v_begin + b] < 0) continue;
      const int db = edge.vertex(b)->tangentDim();
      scatter(slots_[slot++], in, da, db);
      in += da * db;
    }
  }
}

void SparseSystem::scatter(const BlockSlot& slot, const double* block, int rows, int cols) {
  // `block` is rows × cols column-major for the edge's (a, b) order.
  if (!slot.transposed) {
    for (int c = 0; c < cols; ++c) {
      double* column = values_.data() + col_ptr_[slot.first_column + c] + slot.row_offset;
      const int row_end = slot.diagonal ? c + 1 : rows;
      for (int r = 0; r < row_end; ++r) column[r] += block[c * rows + r];
    }
  } else {
    // Stored block is the transpose: `cols` rows × `rows` columns.
    for (int c = 0; c < rows; ++c) {
      double* column = values_.data() + col_ptr_[slot.first_column + c] + slot.row_offset;
      for (int r = 0; r < cols; ++r) column[r] += block[r * rows + c];
    }
  }
}

void SparseSystem::applyUpdate(const double* delta) const {
  for (size_t k = 0; k < active_.size(); ++k) active_[k]->plus(delta + active_offset_[k]);
}

}  // namespace dualgraph
