// SPDX-License-Identifier: MIT
// dualgraph and Ceres side by side on the public pose graphs: the same problem (vertices, edges,
// information, the highest-id vertex fixed), from the same initial estimate, with the same iteration
// cap (100) and relative-decrease stop (1e-9), each solve cold (our Optimizer built in the timed
// region, structure and symbolic analysis included, as Ceres preprocesses inside Solve). The pair
// runs back to back, so dualgraph / Ceres is a ratio measured in one run. Wall time.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "bench/bench_data.h"
#include "bench/ceres_pose_graph.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/solvers/linear_solver_factory.h"

namespace dualgraph {
namespace {

constexpr int kMaxIterations = 100;
constexpr double kRelativeDecreaseStop = 1e-9;

void setSolveCounters(benchmark::State& state, double total_ms, int iterations, int factorizations,
                      double initial_chi2, double final_chi2) {
  state.counters["iterations"] = iterations;
  state.counters["factorizations"] = factorizations;
  state.counters["ms_per_iteration"] = iterations > 0 ? total_ms / iterations : 0.0;
  state.counters["initial_chi2"] = initial_chi2;
  state.counters["final_chi2"] = final_chi2;
}

/// Ours: a fresh Optimizer (pattern, CHOLMOD analysis) and a full LM solve, from the initial estimate.
void BM_SideBySide_Dualgraph(benchmark::State& state, const std::string& name, LmDamping damping) {
  bench::LoadedGraph& loaded = bench::loadDataset(name);
  if (!loaded.ok) return state.SkipWithError(loaded.error.c_str());
  OptimizerParams params;
  params.max_iterations = kMaxIterations;
  params.relative_decrease_stop = kRelativeDecreaseStop;
  params.damping = damping;
  SolverSummary summary;
  for (auto _ : state) {
    state.PauseTiming();
    bench::pushAll(loaded.graph);
    state.ResumeTiming();
    Optimizer optimizer(loaded.graph, makeLinearSolver(LinearSolverKind::kCholmod));
    summary = optimizer.optimize(params);
    benchmark::DoNotOptimize(&summary);
    state.PauseTiming();
    bench::popAll(loaded.graph);
    state.ResumeTiming();
  }
  if (!summary.usable()) return state.SkipWithError(summary.message.c_str());
  setSolveCounters(state, summary.total_ms, summary.iterations, summary.factorizations, summary.initial_chi2,
                   summary.final_chi2);
  state.counters["structure_ms"] = summary.structure_ms;
  state.SetLabel(std::string(lmDampingName(damping)) + " " + terminationReasonName(summary.termination));
}

/// Ceres: Solve from the same initial estimate (copied into the parameter blocks outside the timing).
void BM_SideBySide_Ceres(benchmark::State& state, const std::string& name) {
  bench::LoadedGraph& loaded = bench::loadDataset(name);
  if (!loaded.ok) return state.SkipWithError(loaded.error.c_str());
  Result<std::unique_ptr<bench::CeresPoseGraph>> peer = bench::CeresPoseGraph::create(loaded.graph);
  if (!peer.ok()) return state.SkipWithError(peer.status().message().c_str());
  bench::CeresSolveOptions options;
  options.max_iterations = kMaxIterations;
  options.function_tolerance = kRelativeDecreaseStop;
  bench::CeresSolveOutcome outcome;
  for (auto _ : state) {
    state.PauseTiming();
    (*peer)->copyEstimatesFrom(loaded.graph);
    state.ResumeTiming();
    outcome = (*peer)->solve(options);
    benchmark::DoNotOptimize(&outcome);
  }
  if (!outcome.usable) return state.SkipWithError(outcome.termination.c_str());
  setSolveCounters(state, outcome.total_ms, outcome.iterations, outcome.linear_solves, outcome.initial_chi2,
                   outcome.final_chi2);
  state.counters["jacobian_ms"] = outcome.jacobian_ms;
  state.counters["linear_solver_ms"] = outcome.linear_solver_ms;
  // The Ceres optimum evaluated with our own edges: equal to final_chi2 when the residuals agree.
  bench::pushAll(loaded.graph);
  (*peer)->copyEstimatesTo(loaded.graph);
  state.counters["final_chi2_our_edges"] = loaded.graph.chi2(true);
  bench::popAll(loaded.graph);
  state.SetLabel(outcome.termination.substr(0, outcome.termination.find(':')));
}

#define DG_SIDE_BY_SIDE(dataset)                                                                        \
  BENCHMARK_CAPTURE(BM_SideBySide_Dualgraph, dataset, #dataset, LmDamping::kIdentity)                      \
      ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);                                    \
  BENCHMARK_CAPTURE(BM_SideBySide_Dualgraph, dataset##_diagonal, #dataset, LmDamping::kDiagonal)           \
      ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);                                    \
  BENCHMARK_CAPTURE(BM_SideBySide_Ceres, dataset, #dataset)->Unit(benchmark::kMillisecond)->UseRealTime()     \
      ->Iterations(1)

DG_SIDE_BY_SIDE(sphere2500);
DG_SIDE_BY_SIDE(parking-garage);
DG_SIDE_BY_SIDE(intel);
DG_SIDE_BY_SIDE(smallGrid3D);

}  // namespace
}  // namespace dualgraph
