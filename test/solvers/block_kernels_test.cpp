// SPDX-License-Identifier: MIT
// The 6×6 block kernels (solvers/block_kernels.h) against Eigen's plain products on seeded random blocks,
// including aliasing (in-place) use and the parts of C each kernel must leave alone; the AVX2 + FMA
// assembly kernels (solvers/block_kernels_avx2.h) the same way.
#include "solvers/block_kernels.h"
#include "solvers/block_kernels_avx2.h"

#include <gtest/gtest.h>

#include <random>

namespace dualgraph {
namespace {

using Block = block_kernels::Block;

class BlockKernels : public ::testing::Test {
 protected:
  Block random() {
    Block b;
    for (int i = 0; i < 36; ++i) b.data()[i] = normal_(rng_);
    return b;
  }
  Block randomLower() {
    Block l = random();
    l.triangularView<Eigen::StrictlyUpper>().setZero();
    return l;
  }
  /// Same to round-off (the kernels sum the same terms as Eigen, in another order).
  static void expectNear(const Block& actual, const Block& expected) {
    EXPECT_LE((actual - expected).lpNorm<Eigen::Infinity>(), 1e-13 * (1.0 + expected.lpNorm<Eigen::Infinity>()))
        << "actual\n" << actual << "\nexpected\n" << expected;
  }
  std::mt19937 rng_{18};
  std::normal_distribution<double> normal_;
};

TEST_F(BlockKernels, ProductsMatchEigen) {
  for (int trial = 0; trial < 50; ++trial) {
    const Block a = random(), b = random(), c = random();
    Block out = c;
    block_kernels::subtractProductTransposed(out, a, b);
    expectNear(out, c - a * b.transpose());
    out = c;
    block_kernels::subtractProduct(out, a, b);
    expectNear(out, c - a * b);
    out = c;
    block_kernels::subtractTransposedProduct(out, a, b);
    expectNear(out, c - a.transpose() * b);
  }
}

TEST_F(BlockKernels, GramLowerUpdatesTheLowerTriangleOnly) {
  for (int trial = 0; trial < 50; ++trial) {
    const Block a = random(), c = random();
    Block out = c;
    block_kernels::subtractGramLower(out, a);
    const Block expected = c - a * a.transpose();
    Block lower_out = out.triangularView<Eigen::Lower>();
    expectNear(lower_out, Block(expected.triangularView<Eigen::Lower>()));
    for (int j = 0; j < 6; ++j) {  // upper entries outside the diagonal packets keep their value
      for (int i = 0; i < j; ++i) {
        if (i / 2 != j / 2) {
          EXPECT_EQ(out(i, j), c(i, j)) << "(" << i << ", " << j << ")";
        }
      }
    }
  }
}

TEST_F(BlockKernels, TriangularProductsMatchEigen) {
  for (int trial = 0; trial < 50; ++trial) {
    const Block x = random(), l = randomLower();
    Block in_place = x;
    block_kernels::multiplyTransposedLowerInPlace(in_place, l);
    expectNear(in_place, x * l.transpose());
    Block w = random();
    block_kernels::multiplyLower(w, x, l);
    expectNear(w, x * l);
  }
}

TEST_F(BlockKernels, IdentityAndZeroAreExact) {
  const Block x = random();
  Block in_place = x;
  block_kernels::multiplyTransposedLowerInPlace(in_place, Block::Identity());
  EXPECT_EQ(in_place, x);
  Block w;
  block_kernels::multiplyLower(w, x, Block::Identity());
  EXPECT_EQ(w, x);
  Block c = x;
  block_kernels::subtractProduct(c, Block::Zero(), x);
  EXPECT_EQ(c, x);
}

}  // namespace
}  // namespace dualgraph

namespace dualgraph {
namespace {

/// The AVX2 + FMA assembly kernels (solvers/block_kernels_avx2.h) against Eigen, at unaligned addresses
/// (one double past a 32-byte boundary) as well as aligned ones. Skipped, saying so, without AVX2 + FMA.
class BlockKernelsAvx2 : public BlockKernels {
 protected:
  void SetUp() override {
    if (!block_kernels_avx2::enabled()) GTEST_SKIP() << "this CPU has no AVX2 + FMA";
  }
};

TEST_F(BlockKernelsAvx2, AssemblyProductsMatchEigenAtAnyAlignment) {
  alignas(32) double buffer[4 * 36 + 8];
  for (int offset : {0, 1, 2, 3}) {
    double* g = buffer + offset;
    double* h = g + 36;
    double* w = h + 36;
    double* j = w + 36;
    for (int trial = 0; trial < 20; ++trial) {
      const Block w_block = random(), j_block = random(), h_block = random();
      Eigen::Map<Block> w_map(w), j_map(j), h_map(h);
      w_map = w_block;
      j_map = j_block;
      h_map = h_block;
      block_kernels_avx2::multiply(g, w, j);
      const Block g_block = Eigen::Map<const Block>(g);
      expectNear(g_block, w_block * j_block);
      block_kernels_avx2::addTransposedProduct(h, j, g);
      expectNear(Block(h_map), h_block + j_block.transpose() * g_block);
      Eigen::Matrix<double, 6, 1> e, r;
      for (int i = 0; i < 6; ++i) e[i] = normal_(rng_), r[i] = normal_(rng_);
      const Eigen::Matrix<double, 6, 1> expected = r - g_block.transpose() * e;
      block_kernels_avx2::subtractTransposedTimesVector(r.data(), g, e.data());
      EXPECT_LE((r - expected).lpNorm<Eigen::Infinity>(), 1e-13 * (1.0 + expected.lpNorm<Eigen::Infinity>())) << offset;
    }
  }
}

TEST(BlockKernelsAvx2Switch, SetEnabledFalseBypassesAndTrueRestoresWhenAvailable) {
  const bool available = block_kernels_avx2::setEnabled(true);
  EXPECT_FALSE(block_kernels_avx2::setEnabled(false));
  EXPECT_FALSE(block_kernels_avx2::enabled());
  EXPECT_EQ(block_kernels_avx2::setEnabled(true), available);
}

}  // namespace
}  // namespace dualgraph
