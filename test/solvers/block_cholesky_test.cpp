// SPDX-License-Identifier: MIT
// BlockCholesky against dense Eigen (LLT, inverse) on seeded random SPD block-sparse matrices, once with the
// baseline (SSE2) kernels and once with the AVX2 + FMA ones (skipped, saying so, on a CPU without them).
#include "dualgraph/solvers/block/block_cholesky.h"
#include "dualgraph/solvers/block/block_kernels_avx2.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace dualgraph {
namespace {

using Block = BlockCholesky::Block;
using Pairs = std::vector<std::pair<int, int>>;

/// A random SPD matrix with the given off-diagonal block pattern: Σ over the pairs (and every diagonal
/// block) of JᵀJ terms, as a least-squares problem builds it, so it is SPD and exactly block-sparse.
/// Blocks listed in `padded` (block index → real dimension < 6) keep only their first `dim` rows and
/// columns; the rest is the identity diagonal with zero coupling.
struct Problem {
  Eigen::MatrixXd dense;
  Pairs pairs;
};

Problem randomProblem(int blocks, const Pairs& pairs, std::mt19937& rng, const std::vector<int>& dims = {}) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const int n = 6 * blocks;
  Problem problem{Eigen::MatrixXd::Zero(n, n), pairs};
  auto dim_of = [&](int b) { return dims.empty() ? 6 : dims[b]; };
  auto add_term = [&](int a, int b) {  // a 6-row residual on blocks a and b (b may equal a)
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, n);
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < dim_of(a); ++c) J(r, 6 * a + c) = normal(rng);
      for (int c = 0; c < dim_of(b); ++c) J(r, 6 * b + c) = normal(rng);
    }
    problem.dense += J.transpose() * J;
  };
  for (int b = 0; b < blocks; ++b) add_term(b, b);
  for (const auto& [a, b] : pairs) add_term(a, b);
  for (int b = 0; b < blocks; ++b) {
    for (int c = dim_of(b); c < 6; ++c) problem.dense(6 * b + c, 6 * b + c) = 1.0;
  }
  return problem;
}

/// H in BlockCholesky's storage.
BlockCholesky::BlockVector toBlocks(const BlockCholesky& solver, const Eigen::MatrixXd& dense) {
  BlockCholesky::BlockVector blocks(solver.numStoredBlocks(), Block::Zero());
  for (int j = 0; j < solver.numBlocks(); ++j) {
    for (int i = j; i < solver.numBlocks(); ++i) {
      const int index = solver.blockIndex(i, j);
      if (index >= 0) blocks[index] = dense.block<6, 6>(6 * i, 6 * j);
    }
  }
  return blocks;
}

/// A pose chain 0-1-…-(p-1) with `gates` landmarks interleaved: each pose sees the gates in a sliding window.
Pairs chainWithGates(int poses, int gates, int per_pose, int& blocks) {
  blocks = poses + gates;
  Pairs pairs;
  // Block order: poses 0..p-1 at even positions when convenient; here gates after poses (arrow-like tail).
  for (int k = 0; k + 1 < poses; ++k) pairs.emplace_back(k, k + 1);
  for (int k = 0; k < poses; ++k) {
    for (int g = 0; g < per_pose; ++g) pairs.emplace_back(k, poses + (k * gates / poses + g) % gates);
  }
  return pairs;
}

void expectMatchesDense(const Problem& problem, int blocks, bool check_inverse = true) {
  BlockCholesky solver;
  ASSERT_TRUE(solver.analyse(blocks, problem.pairs).ok());
  const BlockCholesky::BlockVector h = toBlocks(solver, problem.dense);
  const Status factorized = solver.factorize(h.data());
  ASSERT_TRUE(factorized.ok()) << factorized.message();
  const int n = 6 * blocks;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd b(n);
  for (int k = 0; k < n; ++k) b[k] = normal(rng);
  Eigen::VectorXd x(n);
  ASSERT_TRUE(solver.solve(b.data(), x.data()).ok());
  const Eigen::VectorXd expected = problem.dense.llt().solve(b);
  EXPECT_LE((x - expected).norm(), 1e-10 * expected.norm()) << "solve differs from dense LLT";
  if (!check_inverse) return;
  ASSERT_TRUE(solver.selectedInverse().ok());
  const Eigen::MatrixXd inverse = problem.dense.inverse();
  for (int j = 0; j < blocks; ++j) {
    const Eigen::MatrixXd expected_block = inverse.block<6, 6>(6 * j, 6 * j);
    const double error = (solver.inverseDiagonal(j) - expected_block).norm();
    EXPECT_LE(error, 1e-10 * expected_block.norm()) << "diagonal block " << j << "\nblock:\n"
                                                    << solver.inverseDiagonal(j) << "\ndense:\n" << expected_block;
  }
}

/// Every test runs with both kernel sets (the parameter: AVX2 + FMA on).
class BlockCholeskyKernels : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    if (block_kernels_avx2::setEnabled(GetParam()) != GetParam()) GTEST_SKIP() << "this CPU has no AVX2 + FMA";
  }
  void TearDown() override { block_kernels_avx2::setEnabled(true); }
};
INSTANTIATE_TEST_SUITE_P(Kernels, BlockCholeskyKernels, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info) { return info.param ? "Avx2" : "Baseline"; });

TEST_P(BlockCholeskyKernels, ChainMatchesDenseSolveAndInverse) {
  std::mt19937 rng(1);
  Pairs pairs;
  for (int k = 0; k + 1 < 12; ++k) pairs.emplace_back(k + 1, k);  // either order is accepted
  expectMatchesDense(randomProblem(12, pairs, rng), 12);
}

TEST_P(BlockCholeskyKernels, ArrowMatchesDenseSolveAndInverse) {
  std::mt19937 rng(2);
  Pairs pairs;
  for (int k = 0; k < 9; ++k) pairs.emplace_back(k, 9);  // every block coupled to the last: fill-free arrow
  for (int k = 0; k < 9; ++k) pairs.emplace_back(0, k + 1 == 9 ? 1 : k + 1);  // and to the first: full fill
  expectMatchesDense(randomProblem(10, pairs, rng), 10);
}

TEST_P(BlockCholeskyKernels, ChainWithGatesMatchesDenseSolveAndInverse) {
  std::mt19937 rng(3);
  int blocks = 0;
  const Pairs pairs = chainWithGates(20, 5, 3, blocks);
  expectMatchesDense(randomProblem(blocks, pairs, rng), blocks);
}

// Two elimination trees (chains 0-…-5 with a chord 1-4, and 6-…-9): Σ of blocks {2, 7} needs the columns
// on their paths to the roots, {2, 3, 4, 5} and {7, 8, 9}; those equal the full recursion's bit for bit,
// and the others are not computed.
TEST_P(BlockCholeskyKernels, SubsetInverseComputesThePathsToTheRootsOnlyWithTheSameValues) {
  std::mt19937 rng(9);
  const Pairs pairs = {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}, {1, 4}, {6, 7}, {7, 8}, {8, 9}};
  const Problem problem = randomProblem(10, pairs, rng);
  BlockCholesky reference, solver;  // the subset on a solver that never computed the rest
  for (BlockCholesky* s : {&reference, &solver}) {
    ASSERT_TRUE(s->analyse(10, pairs).ok());
    ASSERT_TRUE(s->factorize(toBlocks(*s, problem.dense).data()).ok());
  }
  ASSERT_TRUE(reference.selectedInverse().ok());
  std::vector<Block, Eigen::aligned_allocator<Block>> full;
  for (int j = 0; j < 10; ++j) {
    EXPECT_TRUE(reference.inverseComputed(j));
    full.push_back(reference.inverseDiagonal(j));
  }
  ASSERT_TRUE(solver.selectedInverse({7, 2}).ok());
  const std::vector<bool> expected = {false, false, true, true, true, true, false, true, true, true};
  const Eigen::MatrixXd inverse = problem.dense.inverse();
  for (int j = 0; j < 10; ++j) {
    SCOPED_TRACE("block " + std::to_string(j));
    EXPECT_EQ(solver.inverseComputed(j), expected[j]);
    if (!expected[j]) continue;
    EXPECT_TRUE((solver.inverseDiagonal(j).array() == full[j].array()).all());
    const Eigen::MatrixXd dense_block = inverse.block<6, 6>(6 * j, 6 * j);
    EXPECT_LE((solver.inverseDiagonal(j) - dense_block).norm(), 1e-10 * dense_block.norm());
  }
  EXPECT_FALSE(solver.inverseComputed(10));
  EXPECT_FALSE(solver.inverseComputed(-1));
  // A new factor has no Σ until the next selected inverse.
  ASSERT_TRUE(solver.factorize(toBlocks(solver, problem.dense).data()).ok());
  for (int j = 0; j < 10; ++j) EXPECT_FALSE(solver.inverseComputed(j)) << "block " << j;
  ASSERT_TRUE(solver.analyse(10, pairs).ok());
  ASSERT_TRUE(solver.selectedInverse({2}).code() == StatusCode::kFailedPrecondition);
  for (int j = 0; j < 10; ++j) EXPECT_FALSE(solver.inverseComputed(j)) << "block " << j;
}

TEST_P(BlockCholeskyKernels, SubsetInverseRejectsBlocksOutOfRangeAndAnUnfactorisedMatrix) {
  std::mt19937 rng(10);
  const Pairs pairs = {{0, 1}, {1, 2}};
  const Problem problem = randomProblem(3, pairs, rng);
  BlockCholesky solver;
  ASSERT_TRUE(solver.analyse(3, pairs).ok());
  EXPECT_EQ(solver.selectedInverse({0}).code(), StatusCode::kFailedPrecondition);
  ASSERT_TRUE(solver.factorize(toBlocks(solver, problem.dense).data()).ok());
  for (const int bad : {3, -1}) {
    ASSERT_TRUE(solver.selectedInverse().ok());
    EXPECT_EQ(solver.selectedInverse({1, bad}).code(), StatusCode::kInvalidArgument);
    for (int j = 0; j < 3; ++j) EXPECT_FALSE(solver.inverseComputed(j)) << "block " << j;
  }
  ASSERT_TRUE(solver.selectedInverse({}).ok());  // nothing asked, nothing computed
  for (int j = 0; j < 3; ++j) EXPECT_FALSE(solver.inverseComputed(j)) << "block " << j;
}

TEST_P(BlockCholeskyKernels, PaddedBlocksLeaveTheRealPartExact) {
  std::mt19937 rng(4);
  int blocks = 0;
  const Pairs pairs = chainWithGates(8, 4, 2, blocks);
  std::vector<int> dims(blocks, 6);
  for (int g = 8; g < blocks; ++g) dims[g] = 3;  // point landmarks
  const Problem problem = randomProblem(blocks, pairs, rng, dims);
  expectMatchesDense(problem, blocks);
  // The real 3×3 part of a padded block's inverse is the inverse of the unpadded matrix's block.
  std::vector<int> real;
  for (int b = 0; b < blocks; ++b) {
    for (int c = 0; c < dims[b]; ++c) real.push_back(6 * b + c);
  }
  Eigen::MatrixXd unpadded(real.size(), real.size());
  for (size_t r = 0; r < real.size(); ++r) {
    for (size_t c = 0; c < real.size(); ++c) unpadded(r, c) = problem.dense(real[r], real[c]);
  }
  const Eigen::MatrixXd inverse = unpadded.inverse();
  BlockCholesky solver;
  ASSERT_TRUE(solver.analyse(blocks, pairs).ok());
  ASSERT_TRUE(solver.factorize(toBlocks(solver, problem.dense).data()).ok());
  ASSERT_TRUE(solver.selectedInverse().ok());
  const int last_gate_row = static_cast<int>(real.size()) - 3;
  const Eigen::Matrix3d expected = inverse.block<3, 3>(last_gate_row, last_gate_row);
  EXPECT_LE((solver.inverseDiagonal(blocks - 1).topLeftCorner<3, 3>() - expected).norm(), 1e-10 * expected.norm());
  const Eigen::Matrix3d padding = solver.inverseDiagonal(blocks - 1).bottomRightCorner<3, 3>();
  EXPECT_EQ(padding, Eigen::Matrix3d::Identity());
}

TEST_P(BlockCholeskyKernels, DiagonalAdditionIsFactorisedWithoutChangingTheInput) {
  std::mt19937 rng(5);
  int blocks = 0;
  const Pairs pairs = chainWithGates(10, 3, 2, blocks);
  Problem problem = randomProblem(blocks, pairs, rng);
  BlockCholesky solver;
  ASSERT_TRUE(solver.analyse(blocks, pairs).ok());
  const BlockCholesky::BlockVector h = toBlocks(solver, problem.dense);
  const BlockCholesky::BlockVector h_before = h;
  std::vector<double> add(6 * blocks);
  for (size_t k = 0; k < add.size(); ++k) add[k] = 0.5 + 0.01 * static_cast<double>(k);
  ASSERT_TRUE(solver.factorize(h.data(), add.data()).ok());
  for (size_t k = 0; k < add.size(); ++k) problem.dense(k, k) += add[k];
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(6 * blocks, -1.0, 1.0);
  Eigen::VectorXd x = b;
  ASSERT_TRUE(solver.solve(x.data(), x.data()).ok());  // in place
  const Eigen::VectorXd expected = problem.dense.llt().solve(b);
  EXPECT_LE((x - expected).norm(), 1e-10 * expected.norm());
  for (size_t k = 0; k < h.size(); ++k) EXPECT_EQ(h[k], h_before[k]) << "stored block " << k;
}

TEST_P(BlockCholeskyKernels, NotPositiveDefiniteIsAStatus) {
  std::mt19937 rng(6);
  Pairs pairs = {{0, 1}, {1, 2}};
  Problem problem = randomProblem(3, pairs, rng);
  // Make the matrix indefinite: a negative eigenvalue in the middle block.
  problem.dense.block<6, 6>(6, 6) -= 1e3 * Eigen::MatrixXd::Identity(6, 6);
  BlockCholesky solver;
  ASSERT_TRUE(solver.analyse(3, pairs).ok());
  const Status status = solver.factorize(toBlocks(solver, problem.dense).data());
  EXPECT_EQ(status.code(), StatusCode::kNotPositiveDefinite) << status.message();
  EXPECT_FALSE(solver.factorized());
  Eigen::VectorXd x(18);
  EXPECT_EQ(solver.solve(x.data(), x.data()).code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(solver.selectedInverse().code(), StatusCode::kFailedPrecondition);
}

TEST_P(BlockCholeskyKernels, SingularMatrixIsNotPositiveDefinite) {
  BlockCholesky solver;
  ASSERT_TRUE(solver.analyse(2, {{0, 1}}).ok());
  BlockCholesky::BlockVector h(solver.numStoredBlocks(), Block::Zero());
  h[solver.diagonalIndex(0)].setIdentity();  // block 1 is all zero
  EXPECT_EQ(solver.factorize(h.data()).code(), StatusCode::kNotPositiveDefinite);
}

TEST_P(BlockCholeskyKernels, NanInputIsANumericalError) {
  std::mt19937 rng(8);
  Pairs pairs = {{0, 1}, {1, 2}, {0, 2}};
  Problem problem = randomProblem(3, pairs, rng);
  problem.dense(2, 9) = problem.dense(9, 2) = std::numeric_limits<double>::quiet_NaN();  // block (1, 0)
  BlockCholesky solver;
  ASSERT_TRUE(solver.analyse(3, pairs).ok());
  const Status status = solver.factorize(toBlocks(solver, problem.dense).data());
  EXPECT_EQ(status.code(), StatusCode::kNumericalError) << status.message();
}

TEST_P(BlockCholeskyKernels, BadPatternIsInvalidArgument) {
  BlockCholesky solver;
  EXPECT_EQ(solver.analyse(3, {{0, 3}}).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(solver.analyse(3, {{1, 1}}).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(solver.analyse(3, {{-1, 2}}).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(solver.analyse(-1, {}).code(), StatusCode::kInvalidArgument);
}

TEST_P(BlockCholeskyKernels, EmptyMatrixFactorisesSolvesAndInverts) {
  BlockCholesky solver;
  ASSERT_TRUE(solver.analyse(0, {}).ok());
  EXPECT_TRUE(solver.factorize(nullptr).ok());
  EXPECT_TRUE(solver.solve(nullptr, nullptr).ok());
  EXPECT_TRUE(solver.selectedInverse().ok());
}

TEST_P(BlockCholeskyKernels, FillIsInThePatternAndOnlyThere) {
  // Star on block 0 (first): eliminating it couples every other block — full fill below.
  BlockCholesky solver;
  ASSERT_TRUE(solver.analyse(4, {{0, 1}, {0, 2}, {0, 3}}).ok());
  EXPECT_EQ(solver.numStoredBlocks(), 10);
  EXPECT_GE(solver.blockIndex(3, 2), 0);
  EXPECT_GE(solver.blockIndex(3, 1), 0);
  // The same star on the last block: no fill.
  ASSERT_TRUE(solver.analyse(4, {{3, 0}, {3, 1}, {3, 2}}).ok());
  EXPECT_EQ(solver.numStoredBlocks(), 7);
  EXPECT_EQ(solver.blockIndex(2, 1), -1);
  EXPECT_EQ(solver.blockIndex(1, 2), -1);  // upper triangle is never stored
}

TEST(BlockCholeskyKernelSets, AgreeOnFactorSolveInverseAndFailures) {
  if (!block_kernels_avx2::setEnabled(true)) GTEST_SKIP() << "this CPU has no AVX2 + FMA";
  std::mt19937 rng(21);
  int blocks = 0;
  const Pairs pairs = chainWithGates(30, 8, 3, blocks);
  const Problem problem = randomProblem(blocks, pairs, rng);
  Eigen::VectorXd b(6 * blocks);
  for (int i = 0; i < b.size(); ++i) b[i] = std::normal_distribution<double>()(rng);
  BlockCholesky solvers[2];
  Eigen::VectorXd x[2];
  for (int avx2 = 0; avx2 < 2; ++avx2) {
    block_kernels_avx2::setEnabled(avx2 == 1);
    ASSERT_TRUE(solvers[avx2].analyse(blocks, pairs).ok());
    ASSERT_TRUE(solvers[avx2].factorize(toBlocks(solvers[avx2], problem.dense).data()).ok());
    x[avx2].resize(b.size());
    ASSERT_TRUE(solvers[avx2].solve(b.data(), x[avx2].data()).ok());
    ASSERT_TRUE(solvers[avx2].selectedInverse().ok());
  }
  block_kernels_avx2::setEnabled(true);
  EXPECT_LE((x[0] - x[1]).lpNorm<Eigen::Infinity>(), 1e-10 * x[0].lpNorm<Eigen::Infinity>());
  for (int j = 0; j < blocks; ++j) {
    const Block& s0 = solvers[0].inverseDiagonal(j);
    EXPECT_LE((s0 - solvers[1].inverseDiagonal(j)).lpNorm<Eigen::Infinity>(), 1e-10 * s0.lpNorm<Eigen::Infinity>()) << j;
  }
  // The same failure, at the same row, from both.
  Problem indefinite = problem;
  indefinite.dense.block<6, 6>(6 * 7, 6 * 7) -= 1e4 * Eigen::MatrixXd::Identity(6, 6);
  std::string messages[2];
  for (int avx2 = 0; avx2 < 2; ++avx2) {
    block_kernels_avx2::setEnabled(avx2 == 1);
    const Status status = solvers[avx2].factorize(toBlocks(solvers[avx2], indefinite.dense).data());
    EXPECT_EQ(status.code(), StatusCode::kNotPositiveDefinite) << status.message();
    messages[avx2] = status.message().substr(status.message().find(" at row "));
  }
  block_kernels_avx2::setEnabled(true);
  EXPECT_EQ(messages[0], messages[1]);
}

}  // namespace
}  // namespace dualgraph
