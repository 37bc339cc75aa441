// SPDX-License-Identifier: MIT
// The 6×6 block kernels (solvers/block/block_kernels.h) against Eigen's plain products on seeded random blocks,
// including aliasing (in-place) use and the parts of C each kernel must leave alone; the AVX2 + FMA
// assembly kernels (solvers/block/block_kernels_avx2.h) the same way.
#include "dualgraph/solvers/block/block_kernels.h"
#include "dualgraph/solvers/block/block_kernels_avx2.h"

#include <gtest/gtest.h>

#include <limits>
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

/// The AVX2 + FMA assembly kernels (solvers/block/block_kernels_avx2.h) against Eigen, at unaligned addresses
/// (one double past a 32-byte boundary) as well as aligned ones. Skipped, saying so, without AVX2 + FMA.
class BlockKernelsAvx2 : public BlockKernels {
 protected:
  void SetUp() override {
    if (!block_kernels_avx2::enabled()) GTEST_SKIP() << "this CPU has no AVX2 + FMA";
  }
};

/// A random block whose 3×3 quadrants are exactly zero where bit 2r + c of `mask` is clear (some of
/// them −0.0).
Block withZeroQuadrants(Block b, unsigned mask, std::mt19937& rng) {
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 2; ++c) {
      if (((mask >> (2 * r + c)) & 1u) != 0) continue;
      b.block<3, 3>(3 * r, 3 * c).setZero();
      if (rng() % 2 == 0) b(3 * r + 1, 3 * c + 2) = -0.0;
    }
  }
  return b;
}

TEST_F(BlockKernelsAvx2, NonzeroQuadrantsSeesEveryEntryAndTreatsNegativeZeroAsZero) {
  for (unsigned mask = 0; mask < 16; ++mask) {
    const Block j = withZeroQuadrants(random(), mask, rng_);
    EXPECT_EQ(block_kernels_avx2::nonzeroQuadrants(j.data()), mask);
  }
  for (int entry = 0; entry < 36; ++entry) {  // one nonzero (or NaN) entry lights exactly its quadrant
    Block j = Block::Zero();
    j.data()[entry] = entry % 2 == 0 ? 1e-300 : std::numeric_limits<double>::quiet_NaN();
    const int row = entry % 6, col = entry / 6;
    EXPECT_EQ(block_kernels_avx2::nonzeroQuadrants(j.data()), 1u << (2 * (row / 3) + col / 3)) << entry;
  }
}

TEST_F(BlockKernelsAvx2, AssemblyKernelsMatchEigenForEveryQuadrantMaskAtAnyAlignment) {
  alignas(32) double buffer[4 * 36 + 8];
  for (int offset : {0, 1, 2, 3}) {
    double* p = buffer + offset;
    double* h = p + 36;
    double* w = h + 36;
    double* j = w + 36;
    for (unsigned mask = 0; mask < 16; ++mask) {
      const Block root = random();
      const Block w_block = root * root.transpose() + Block::Identity();  // symmetric, as Ω is
      const Block j_block = withZeroQuadrants(random(), mask, rng_), h_block = random();
      Eigen::Map<Block> w_map(w), j_map(j), h_map(h);
      w_map = w_block;
      j_map = j_block;
      h_map = h_block;
      const unsigned found = block_kernels_avx2::nonzeroQuadrants(j);
      const double weight = 0.25 + std::abs(normal_(rng_));
      for (unsigned used : {found, 15u}) {  // the exact mask and the dense fallback
        Eigen::Matrix<double, 6, 1> e, r;
        for (int i = 0; i < 6; ++i) e[i] = normal_(rng_), r[i] = normal_(rng_);
        const Block expected_p = weight * (w_block * j_block).transpose();
        const Eigen::Matrix<double, 6, 1> expected_r = r - expected_p * e;
        block_kernels_avx2::weightedJacobianTransposed(p, r.data(), w, weight, j, used, e.data());
        const Block p_block = Eigen::Map<const Block>(p);
        expectNear(p_block, expected_p);
        EXPECT_LE((r - expected_r).lpNorm<Eigen::Infinity>(), 1e-13 * (1.0 + expected_r.lpNorm<Eigen::Infinity>()));
        const double chi2 = e.dot(w_block * e);
        EXPECT_NEAR(block_kernels_avx2::quadraticForm(w, e.data()), chi2, 1e-13 * (1.0 + std::abs(chi2)));
        h_map = h_block;
        block_kernels_avx2::addProduct(h, p, j, used, false);
        expectNear(Block(h_map), h_block + p_block * j_block);
        block_kernels_avx2::addProduct(h, p, j, used, true);
        expectNear(Block(h_map), p_block * j_block);
      }
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
