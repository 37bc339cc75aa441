// SPDX-License-Identifier: MIT
// BlockLmSolver's side of the Levenberg–Marquardt loop it shares with Optimizer (core/lm_loop.h).
#include <algorithm>

#include "dualgraph/core/lm_loop.h"
#include "dualgraph/solvers/block/block_lm_solver.h"

namespace dualgraph {

double BlockLmSolver::lmMaxDiagonal() const {
  double max_diagonal = 0.0;
  for (size_t j = 0; j < active_.size(); ++j) {
    const BlockCholesky::Block& diagonal = h_[cholesky_.diagonalIndex(static_cast<int>(j))];
    for (int c = 0; c < block_dim_[j]; ++c) max_diagonal = std::max(max_diagonal, diagonal(c, c));
  }
  return max_diagonal;
}

void BlockLmSolver::lmPush() {
  for (VertexBase* v : active_) v->push();
}
void BlockLmSolver::lmPop() {
  for (VertexBase* v : active_) v->pop();
}
void BlockLmSolver::lmDiscardTop() {
  for (VertexBase* v : active_) v->discardTop();
}
double BlockLmSolver::lmPredictedDecrease() const { return dampingEnergy() + step_.dot(rhs_); }
double BlockLmSolver::lmStepInfNorm() const { return step_.lpNorm<Eigen::Infinity>(); }

void BlockLmSolver::runLevenbergMarquardt(const OptimizerParams& params, double start_ms, SolverSummary& summary) {
  runLevenbergMarquardtLoop(*this, params, start_ms, summary);
}

}  // namespace dualgraph
