// SPDX-License-Identifier: MIT
// The 6×6 block kernels (solvers/block_kernels.h) against Eigen's plain products on seeded random blocks,
// including aliasing (in-place) use and the parts of C each kernel must leave alone.
#include "solvers/block_kernels.h"

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
