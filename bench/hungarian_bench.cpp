// SPDX-License-Identifier: MIT
// Minimum-cost assignment (frontend/gates/hungarian.h) on square cost matrices from 4×4 (one RATM frame's
// gates) to 32×32, uniform random costs with a fixed seed and 10 % forbidden cells (gates outside the
// association gate), as the detection-to-gate association produces them.
#include <benchmark/benchmark.h>

#include <limits>
#include <random>

#include "dualgraph/frontend/gates/hungarian.h"

namespace dualgraph {
namespace {

Eigen::MatrixXd costMatrix(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> cost(0.0, 100.0);
  std::bernoulli_distribution forbidden(0.1);
  Eigen::MatrixXd matrix(n, n);
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) matrix(r, c) = forbidden(rng) ? std::numeric_limits<double>::infinity() : cost(rng);
  }
  return matrix;
}

void BM_Hungarian_Solve(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Eigen::MatrixXd cost = costMatrix(n, 1);
  int assigned = 0;
  for (auto _ : state) {
    Result<Assignment> assignment = solveAssignment(cost);
    if (!assignment.ok()) return state.SkipWithError(assignment.status().message().c_str());
    assigned = assignment->assigned_rows;
    benchmark::DoNotOptimize(&*assignment);
  }
  state.counters["assigned_rows"] = assigned;
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK(BM_Hungarian_Solve)->RangeMultiplier(2)->Range(4, 32)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dualgraph
