// SPDX-License-Identifier: MIT
#include "dualgraph/core/sparse_system.h"

#include <algorithm>
#include <string>

namespace dualgraph {

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
  const double* constant = edge.robustKernel() == nullptr ? edge.constantHessianData() : nullptr;
  if (constant != nullptr) {  // blocks copied from the edge's own JᵀΩJ (no m × m products)
    computeEdgeFromConstantHessian(edge, constant, weighted_error.data(), v_begin, num_slots, out);
    return;
  }
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

void SparseSystem::computeEdgeFromConstantHessian(const EdgeBase& edge, const double* hessian,
                                                  const double* weighted_error, int v_begin, int num_slots,
                                                  double* out) const {
  using ConstMatrixMap = Eigen::Map<const Eigen::MatrixXd>;
  const int m = edge.errorDim();
  int total = 0;
  for (int a = 0; a < num_slots; ++a) total += edge.vertex(a)->tangentDim();
  const ConstMatrixMap full(hessian, total, total);
  const Eigen::Map<const Eigen::VectorXd> we(weighted_error, m);
  int column_a = 0;
  for (int a = 0; a < num_slots; ++a) {
    const int da = edge.vertex(a)->tangentDim();
    if (edge_vertex_offset_[v_begin + a] >= 0) {
      Eigen::Map<Eigen::VectorXd>(out, da).noalias() = -(ConstMatrixMap(edge.jacobianData(a), m, da).transpose() * we);
      out += da;
      int column_b = column_a;
      for (int b = a; b < num_slots; ++b) {
        const int db = edge.vertex(b)->tangentDim();
        if (edge_vertex_offset_[v_begin + b] >= 0) {
          Eigen::Map<Eigen::MatrixXd>(out, da, db) = full.block(column_a, column_b, da, db);
          out += da * db;
        }
        column_b += db;
      }
    }
    column_a += da;
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
