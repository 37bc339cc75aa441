// SPDX-License-Identifier: MIT
// TemporarySolver's side of the Levenberg–Marquardt loop it shares with Optimizer (core/lm_loop.h).
#include <algorithm>

#include "core/lm_loop.h"
#include "dual_graph/temporary_solver.h"

namespace dualgraph {

double TemporarySolver::lmMaxDiagonal() const {
  double max_diagonal = 0.0;
  for (size_t j = 0; j < active_.size(); ++j) {
    const BlockCholesky::Block& diagonal = h_[cholesky_.diagonalIndex(static_cast<int>(j))];
    for (int c = 0; c < block_dim_[j]; ++c) max_diagonal = std::max(max_diagonal, diagonal(c, c));
  }
  return max_diagonal;
}

void TemporarySolver::lmPush() {
  for (VertexBase* v : active_) v->push();
}
void TemporarySolver::lmPop() {
  for (VertexBase* v : active_) v->pop();
}
void TemporarySolver::lmDiscardTop() {
  for (VertexBase* v : active_) v->discardTop();
}
double TemporarySolver::lmPredictedDecrease() const { return dampingEnergy() + step_.dot(rhs_); }
double TemporarySolver::lmStepInfNorm() const { return step_.lpNorm<Eigen::Infinity>(); }

void TemporarySolver::runLevenbergMarquardt(const OptimizerParams& params, double start_ms, SolverSummary& summary) {
  runLevenbergMarquardtLoop(*this, params, start_ms, summary);
}

}  // namespace dualgraph
