// SPDX-License-Identifier: MIT
// BlockCholesky alone on the temporary graph's pattern, so that a change of its kernels is measured
// without the rest of a distillation (BM_TemporaryGraph_Distil): the numeric factorisation, the
// selected inverse of the gate blocks (as distil asks for it) and of every block.
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "dualgraph/solvers/block/block_cholesky.h"
#include "dualgraph/solvers/block/block_kernels_avx2.h"

namespace dualgraph {
namespace {

using Pairs = std::vector<std::pair<int, int>>;
using Block = BlockCholesky::Block;

/// The temporary graph's order (TemporaryGraph::assignVertexIds): `poses` poses in a chain flying past
/// `gates` gates, each pose seeing `per_pose` consecutive ones (a window sliding from the first gates to the
/// last), every gate right after the last pose that sees it. H = Σ JᵀJ over the chain, the observations and a prior per block, with seeded
/// random 6×6 Jacobians (SPD and exactly block-sparse, as a least-squares problem builds it).
struct TemporaryPattern {
  BlockCholesky solver;
  BlockCholesky::BlockVector h;
  std::vector<int> gate_blocks;
  bool ok = false;
};

TemporaryPattern makePattern(int poses, int gates, int per_pose) {
  TemporaryPattern pattern;
  std::vector<std::vector<int>> seen(static_cast<size_t>(poses));  // per pose: the gates it sees
  std::vector<int> last_pose(static_cast<size_t>(gates), -1);
  for (int k = 0; k < poses; ++k) {
    for (int g = 0; g < per_pose; ++g) {
      const int gate = k * (gates - per_pose + 1) / poses + g;
      seen[k].push_back(gate);
      last_pose[gate] = k;
    }
  }
  std::vector<int> pose_block(static_cast<size_t>(poses)), gate_block(static_cast<size_t>(gates), -1);
  int next = 0;
  for (int k = 0; k < poses; ++k) {
    pose_block[k] = next++;
    for (int gate = 0; gate < gates; ++gate) {
      if (last_pose[gate] == k) gate_block[gate] = next++;
    }
  }
  Pairs pairs;
  for (int k = 0; k + 1 < poses; ++k) pairs.emplace_back(pose_block[k], pose_block[k + 1]);
  for (int k = 0; k < poses; ++k) {
    for (int gate : seen[k]) pairs.emplace_back(pose_block[k], gate_block[gate]);
  }
  const int blocks = next;
  if (!pattern.solver.analyse(blocks, pairs).ok()) return pattern;
  pattern.h.assign(static_cast<size_t>(pattern.solver.numStoredBlocks()), Block::Zero());
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto random = [&] {
    Block j;
    for (int i = 0; i < 36; ++i) j.data()[i] = normal(rng);
    return j;
  };
  for (int b = 0; b < blocks; ++b) pattern.h[pattern.solver.diagonalIndex(b)] += Block::Identity();
  for (const auto& [a, b] : pairs) {
    const Block j_a = random(), j_b = random();
    pattern.h[pattern.solver.diagonalIndex(a)] += j_a.transpose() * j_a;
    pattern.h[pattern.solver.diagonalIndex(b)] += j_b.transpose() * j_b;
    const int row = std::max(a, b), col = std::min(a, b);
    pattern.h[pattern.solver.blockIndex(row, col)] += (row == a ? j_a : j_b).transpose() * (row == a ? j_b : j_a);
  }
  for (int gate = 0; gate < gates; ++gate) {
    if (gate_block[gate] >= 0) pattern.gate_blocks.push_back(gate_block[gate]);
  }
  pattern.ok = pattern.solver.factorize(pattern.h.data()).ok();
  return pattern;
}

/// Args: poses, gates, gates seen per pose, phase (0: factorize, 1: selected inverse of the gates,
/// 2: of every block), AVX2 kernels (1) or the baseline ones (0).
void BM_BlockCholesky_TemporaryPattern(benchmark::State& state) {
  TemporaryPattern pattern = makePattern(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                                         static_cast<int>(state.range(2)));
  if (!pattern.ok) return state.SkipWithError("the pattern did not factorise");
  const bool avx2 = block_kernels_avx2::setEnabled(state.range(4) != 0);
  struct RestoreKernels {
    ~RestoreKernels() { block_kernels_avx2::setEnabled(true); }
  } restore;
  const int phase = static_cast<int>(state.range(3));
  for (auto _ : state) {
    const Status status = phase == 0   ? pattern.solver.factorize(pattern.h.data())
                          : phase == 1 ? pattern.solver.selectedInverse(pattern.gate_blocks)
                                       : pattern.solver.selectedInverse();
    if (!status.ok()) return state.SkipWithError(status.message().c_str());
    benchmark::ClobberMemory();
  }
  state.counters["blocks"] = pattern.solver.numBlocks();
  state.counters["stored_blocks"] = pattern.solver.numStoredBlocks();
  state.counters["avx2"] = avx2 ? 1 : 0;
}
BENCHMARK(BM_BlockCholesky_TemporaryPattern)
    ->ArgNames({"poses", "gates", "per_pose", "phase", "avx2"})
    ->ArgsProduct({{50}, {11}, {4}, {0, 1, 2}, {1}})
    ->ArgsProduct({{50}, {11}, {4}, {0}, {0}})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dualgraph
