// SPDX-License-Identifier: MIT
// Test matrices in the optimiser's layout (block-sparse, upper-triangular CSC) and the solver
// configurations every behavioural test runs against.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "dualgraph/core/linear_solver.h"
#include "dualgraph/core/status.h"
#include "dualgraph/solvers/cholmod_solver.h"
#include "dualgraph/solvers/eigen_solver.h"

namespace dualgraph {

/// gtest prints codes by name ("NotPositiveDefinite") instead of as bytes.
inline void PrintTo(StatusCode code, std::ostream* os) { *os << statusCodeName(code); }

namespace testing {

/// An upper-triangular CSC matrix that owns its arrays.
struct Csc {
  int n = 0;
  std::vector<int> col_ptr{0};
  std::vector<int> row_index;
  std::vector<double> values;
  SparseMatrixView view() const { return SparseMatrixView{n, col_ptr.data(), row_index.data(), values.data()}; }
};

/// The upper triangle of `dense` restricted to the structural pattern (`pattern(r, c) != 0`),
/// written column by column with sorted rows, as SparseSystem lays out H. Structural entries are
/// kept even when their value is 0, so a pattern survives value changes.
inline Csc toUpperCsc(const Eigen::MatrixXd& dense, const Eigen::MatrixXi& pattern) {
  Csc csc;
  csc.n = static_cast<int>(dense.rows());
  csc.col_ptr.assign(1, 0);
  for (int c = 0; c < csc.n; ++c) {
    for (int r = 0; r <= c; ++r) {
      if (pattern(r, c) == 0) continue;
      csc.row_index.push_back(r);
      csc.values.push_back(dense(r, c));
    }
    csc.col_ptr.push_back(static_cast<int>(csc.row_index.size()));
  }
  return csc;
}

/// A seeded random SPD matrix H = Σ J_kᵀ J_k + δ I like a pose graph's: one factor per block
/// (a prior), a chain of odometry factors between consecutive blocks and blocks/3 random loop
/// closures (none with `loop_closures` false: a pure chain); each factor has block_dim rows. The pattern marks whole blocks.
struct BlockProblem {
  Eigen::MatrixXd dense;
  Eigen::MatrixXi pattern;
  int n() const { return static_cast<int>(dense.rows()); }
  Csc csc() const { return toUpperCsc(dense, pattern); }
  /// Same pattern, values H + shift·I (what Levenberg–Marquardt's damping does).
  Csc shifted(double shift) const {
    return toUpperCsc(dense + shift * Eigen::MatrixXd::Identity(n(), n()), pattern);
  }
};

inline BlockProblem randomBlockSpd(int blocks, int block_dim, unsigned seed, double delta = 1e-2,
                                   bool loop_closures = true) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, blocks - 1);
  const int n = blocks * block_dim;
  BlockProblem problem;
  problem.dense = delta * Eigen::MatrixXd::Identity(n, n);
  problem.pattern = Eigen::MatrixXi::Zero(n, n);
  auto add_factor = [&](int i, int j) {
    // J = [J_i  J_j]; only the blocks J_aᵀ J_b of H change (a dense JᵀJ would cost O(n²) per factor).
    std::vector<int> touched{i};
    if (j != i) touched.push_back(j);
    std::vector<Eigen::MatrixXd> jacobians;
    for (size_t t = 0; t < touched.size(); ++t) {
      Eigen::MatrixXd jacobian(block_dim, block_dim);
      for (int r = 0; r < block_dim; ++r) {
        for (int c = 0; c < block_dim; ++c) jacobian(r, c) = uniform(rng);
      }
      jacobians.push_back(jacobian);
    }
    for (size_t a = 0; a < touched.size(); ++a) {
      for (size_t b = 0; b < touched.size(); ++b) {
        problem.dense.block(touched[a] * block_dim, touched[b] * block_dim, block_dim, block_dim) +=
            jacobians[a].transpose() * jacobians[b];
        problem.pattern.block(touched[a] * block_dim, touched[b] * block_dim, block_dim, block_dim).setOnes();
      }
    }
  };
  for (int k = 0; k < blocks; ++k) add_factor(k, k);
  for (int k = 0; k + 1 < blocks; ++k) add_factor(k, k + 1);
  for (int k = 0; loop_closures && k < blocks / 3; ++k) add_factor(pick(rng), pick(rng));
  return problem;
}

inline Eigen::VectorXd randomVector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd v(n);
  for (int k = 0; k < n; ++k) v[k] = normal(rng);
  return v;
}

/// One solver configuration under test.
struct SolverCase {
  std::string label;
  std::function<std::unique_ptr<LinearSolver>()> make;
};

inline void PrintTo(const SolverCase& solver_case, std::ostream* os) { *os << solver_case.label; }

inline std::vector<SolverCase> allSolverCases() {
  return {
      {"CholmodAuto", [] { return std::make_unique<CholmodSolver>(); }},
      {"CholmodSupernodal",
       [] {
         CholmodOptions options;
         options.factorization = CholmodFactorization::kSupernodal;
         return std::make_unique<CholmodSolver>(options);
       }},
      {"CholmodSimplicial",
       [] {
         CholmodOptions options;
         options.factorization = CholmodFactorization::kSimplicial;
         return std::make_unique<CholmodSolver>(options);
       }},
      {"CholmodSupernodalAmd",
       [] {
         CholmodOptions options;
         options.ordering = CholmodOrdering::kAmd;
         return std::make_unique<CholmodSolver>(options);
       }},
      {"Eigen", [] { return std::make_unique<EigenSolver>(); }},
      {"EigenNatural", [] { return std::make_unique<EigenSolver>(EigenOrdering::kNatural); }},
  };
}

}  // namespace testing
}  // namespace dualgraph
