// SPDX-License-Identifier: MIT
// BlockLmSolver's assembly: one edge's Jᵀ W J blocks and Jᵀ W e straight into the 6×6 block storage.
#include "dualgraph/solvers/block/block_lm_solver.h"
#include "dualgraph/solvers/block/block_kernels_avx2.h"

namespace dualgraph {
namespace {


using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using ConstMap = Eigen::Map<const Eigen::MatrixXd>;
using ConstMap6 = Eigen::Map<const Matrix6>;

/// Which 3×3 quadrants of a 6×6 Jacobian are not exactly zero (bit 2r + c for quadrant (r, c)). SE(3)
/// Jacobians have zero quadrants by construction (EdgeSE3: J_i's lower left, J_j's off-diagonal ones);
/// skipping them saves a third of the assembly's products, whatever the edge type.
unsigned nonzeroQuadrants(const ConstMap6& j) {
  unsigned mask = 0;
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 2; ++c) {
      if (!(j.block<3, 3>(3 * r, 3 * c).array() == 0.0).all()) mask |= 1u << (2 * r + c);
    }
  }
  return mask;
}

/// g = w_information · j over j's nonzero quadrants.
void weightedProduct(const Matrix6& w_information, const ConstMap6& j, unsigned mask, Matrix6& g) {
  for (int c = 0; c < 2; ++c) {
    auto g_c = g.block<6, 3>(0, 3 * c);
    g_c.setZero();
    for (int r = 0; r < 2; ++r) {
      if ((mask >> (2 * r + c)) & 1u) g_c.noalias() += w_information.block<6, 3>(0, 3 * r) * j.block<3, 3>(3 * r, 3 * c);
    }
  }
}

/// h += jᵀ g over j's nonzero quadrants.
void addTransposedProduct(const ConstMap6& j, unsigned mask, const Matrix6& g, BlockCholesky::Block& h) {
  for (int r = 0; r < 2; ++r) {
    for (int k = 0; k < 2; ++k) {
      if ((mask >> (2 * k + r)) & 1u) h.block<3, 6>(3 * r, 0).noalias() += j.block<3, 3>(3 * k, 3 * r).transpose() * g.block<3, 6>(3 * k, 0);
    }
  }
}

}  // namespace

void BlockLmSolver::assembleEdge(size_t k, bool avx2) {
  const EdgeBase& edge = *active_edges_[k];
  const int m = edge.errorDim();
  const RobustKernel* kernel = edge.robustKernel();
  // The errors are those of the last evaluateChi2, whose eᵀΩe is kept.
  const double weight = kernel != nullptr ? kernel->robustify(plain_chi2_[active_source_[k]])[1] : 1.0;
  const int* blocks = edge_block_.data() + edge_begin_[k];
  const int slots = edge_begin_[k + 1] - edge_begin_[k];
  const int* pair = pair_index_.data() + pair_begin_[k];
  bool uniform = m == kB;
  for (int a = 0; a < slots && uniform; ++a) uniform = blocks[a] < 0 || block_dim_[blocks[a]] == kB;
  const unsigned char* first = pair_first_.data() + pair_begin_[k];  // assign, not add (see pair_first_)
  if (uniform && avx2) {  // SE(3) edges, AVX2 + FMA: P_a = (w Ω J_a)ᵀ once per vertex, H_rc = P_r J_c
    const double* information = edge.informationData();
    const double* error = edge.errorData();
    alignas(32) double transposed[kMaxSlots][36];
    const double* jacobians[kMaxSlots];
    unsigned masks[kMaxSlots];
    for (int a = 0; a < slots; ++a) {
      if (blocks[a] < 0) continue;
      jacobians[a] = edge.jacobianData(a);
      masks[a] = block_kernels_avx2::nonzeroQuadrants(jacobians[a]);
      block_kernels_avx2::weightedJacobianTransposed(transposed[a], rhs_.data() + kB * blocks[a], information, weight,
                                                     jacobians[a], masks[a], error);
    }
    for (int a = 0; a < slots; ++a) {
      if (blocks[a] < 0) continue;
      for (int b = a; b < slots; ++b) {
        if (blocks[b] < 0) continue;
        const bool lower = blocks[a] >= blocks[b];  // stored block (row, col) = J_rowᵀ W J_col = P_row J_col
        const int col = lower ? b : a;
        block_kernels_avx2::addProduct(h_[*pair++].data(), transposed[lower ? a : b], jacobians[col], masks[col],
                                       *first++ != 0);
      }
    }
    return;
  }
  if (uniform) {  // SE(3) edges: fixed-size products only
    const Matrix6 w_information = weight * ConstMap6(edge.informationData());
    const Eigen::Map<const Vector6> error(edge.errorData());
    Matrix6 weighted[kMaxSlots];  // G_a = w Ω J_a
    unsigned masks[kMaxSlots];
    for (int a = 0; a < slots; ++a) {
      if (blocks[a] < 0) continue;
      const ConstMap6 jacobian(edge.jacobianData(a));
      masks[a] = nonzeroQuadrants(jacobian);
      weightedProduct(w_information, jacobian, masks[a], weighted[a]);
      rhs_.segment<kB>(kB * blocks[a]).noalias() -= weighted[a].transpose() * error;
    }
    for (int a = 0; a < slots; ++a) {
      if (blocks[a] < 0) continue;
      for (int b = a; b < slots; ++b) {
        if (blocks[b] < 0) continue;
        const bool lower = blocks[a] >= blocks[b];  // stored block (row, col) = J_rowᵀ G_col
        const int row = lower ? a : b;
        BlockCholesky::Block& h = h_[*pair++];
        if (*first++ != 0) h.setZero();
        addTransposedProduct(ConstMap6(edge.jacobianData(row)), masks[row], weighted[lower ? b : a], h);
      }
    }
    return;
  }
  const ConstMap information(edge.informationData(), m, m);
  const Eigen::Map<const Eigen::VectorXd> error(edge.errorData(), m);
  Small weighted[kMaxSlots];
  for (int a = 0; a < slots; ++a) {
    if (blocks[a] < 0) continue;
    const int da = block_dim_[blocks[a]];
    weighted[a].noalias() = weight * (information * ConstMap(edge.jacobianData(a), m, da));
    rhs_.segment(kB * blocks[a], da).noalias() -= weighted[a].transpose() * error;
  }
  for (int a = 0; a < slots; ++a) {
    if (blocks[a] < 0) continue;
    for (int b = a; b < slots; ++b) {
      if (blocks[b] < 0) continue;
      const bool lower = blocks[a] >= blocks[b];
      const int row = lower ? a : b;
      const int col = lower ? b : a;
      const int rows = block_dim_[blocks[row]];
      const int cols = block_dim_[blocks[col]];
      BlockCholesky::Block& h = h_[*pair++];
      if (*first++ != 0) h.setZero();
      h.topLeftCorner(rows, cols).noalias() += ConstMap(edge.jacobianData(row), m, rows).transpose() * weighted[col];
    }
  }
}

}  // namespace dualgraph
