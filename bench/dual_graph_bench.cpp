// SPDX-License-Identifier: MIT
// The dual graph's own costs: distilling a temporary graph (build, LM, marginals: what the Localizer
// does when a keyframe arrives), the marginals of its gates alone, and the main graph's per-keyframe
// update over a whole simulated RATM race at the sizes of the paper's Table I.
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>
#include <vector>

#include "bench/bench_data.h"
#include "bench/race_fixture.h"
#include "bench/temporary_fixture.h"
#include "dualgraph/solvers/block/block_kernels_avx2.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/solvers/marginal_covariance.h"

namespace dualgraph {
namespace {

/// TemporaryGraph::distil on a recorded interval (args: gates, poses, gates seen per pose, solver 0 = block
/// (the default), 1 = graph (the generic Optimizer, the former path), avx2 1 = the block kernels chosen at
/// run time (AVX2 + FMA when the CPU has them, the default), 0 = the baseline SSE2 ones forced; model_stop 1 =
/// temp_model_decrease_stop as configured (the default), 0 = off): the graph is built, optimised and
/// its gates' marginals inverted into edges. One TemporaryGraph is reused, as in the Localizer (its block
/// solver keeps its buffers): the observations are recorded again before each call, outside the timing
/// (distil clears them). Manual time around distil alone.
void BM_TemporaryGraph_Distil(benchmark::State& state) {
  bench::TemporaryScenario scenario = bench::makeTemporaryScenario(
      static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), static_cast<int>(state.range(2)));
  scenario.params.temp_solver = state.range(3) == 0 ? TemporarySolverKind::kBlock : TemporarySolverKind::kGraph;
  if (state.range(5) == 0) scenario.params.temp_model_decrease_stop = 0.0;  // the relative rule alone
  TemporaryGraph temporary(scenario.params, scenario.kernel);
  DistillationResult result;
  const bool avx2 = block_kernels_avx2::setEnabled(state.range(4) != 0);
  struct RestoreKernels {
    ~RestoreKernels() { block_kernels_avx2::setEnabled(true); }
  } restore;
  for (auto _ : state) {
    if (Status s = bench::recordInto(temporary, scenario); !s.ok()) return state.SkipWithError(s.message().c_str());
    const auto start = std::chrono::steady_clock::now();
    result = bench::distilScenario(temporary, scenario);
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    benchmark::DoNotOptimize(&result);
  }
  if (result.skipped_gates > 0) return state.SkipWithError(result.skip_reason.c_str());
  state.counters["distilled_gates"] = static_cast<double>(result.gates.size());
  state.counters["nodes"] = result.nodes;
  state.counters["edges"] = result.edges;
  state.counters["lm_iterations"] = result.iterations;
  state.counters["avx2"] = avx2 ? 1 : 0;
}
BENCHMARK(BM_TemporaryGraph_Distil)
    ->ArgNames({"gates", "poses", "per_pose", "graph", "avx2", "model_stop"})
    ->ArgsProduct({{4}, {20}, {4}, {0, 1}, {1}, {1}})
    ->ArgsProduct({{11}, {50}, {4, 11}, {0, 1}, {1}, {1}})
    ->ArgsProduct({{11}, {50}, {4}, {0}, {0}, {1}})
    ->ArgsProduct({{11}, {50}, {4}, {0}, {1}, {0}})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

/// The marginal covariances of every gate of an optimised temporary graph (MarginalCovariance::compute,
/// then one block per gate, as distil does), with the Localizer's solver (auto: Eigen at this size) and
/// CHOLMOD (args: gates, poses, gates seen per pose, solver 0 = auto, 1 = cholmod).
void BM_TemporaryGraph_GateMarginals(benchmark::State& state) {
  const bench::TemporaryScenario scenario = bench::makeTemporaryScenario(
      static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), static_cast<int>(state.range(2)));
  const LinearSolverKind kind = state.range(3) == 0 ? LinearSolverKind::kAuto : LinearSolverKind::kCholmod;
  Graph graph;
  std::vector<int> gate_ids;
  if (Status s = bench::buildTemporaryGraph(scenario, graph, gate_ids); !s.ok()) return state.SkipWithError(s.message().c_str());
  Optimizer optimizer(graph, makeLinearSolver(kind));
  OptimizerParams lm;
  lm.max_iterations = scenario.params.temp_max_iterations;
  lm.relative_decrease_stop = 1e-6;
  if (!optimizer.optimize(lm).usable()) return state.SkipWithError("temporary graph optimisation failed");
  const bool joint = state.range(4) != 0;
  double trace = 0.0;
  for (auto _ : state) {
    MarginalCovariance marginals;
    if (Status s = marginals.compute(optimizer, graph); !s.ok()) return state.SkipWithError(s.message().c_str());
    if (joint) {  // every gate's columns in one solve
      Result<Eigen::MatrixXd> block = marginals.jointBlock(gate_ids);
      if (!block.ok()) return state.SkipWithError(block.status().message().c_str());
      trace += block->trace();
      continue;
    }
    for (int id : gate_ids) {
      Result<Eigen::MatrixXd> block = marginals.block(id);
      if (!block.ok()) return state.SkipWithError(block.status().message().c_str());
      trace += block->trace();
    }
  }
  benchmark::DoNotOptimize(&trace);
  state.SetLabel(linearSolverKindName(kind));
  state.counters["gates"] = static_cast<double>(gate_ids.size());
  state.counters["edges"] = static_cast<double>(graph.numEdges());
}
BENCHMARK(BM_TemporaryGraph_GateMarginals)
    ->ArgNames({"gates", "poses", "per_pose", "cholmod", "joint"})
    ->Args({4, 20, 4, 0, 0})
    ->Args({11, 50, 4, 0, 0})
    ->Args({11, 50, 4, 0, 1})
    ->Args({11, 50, 4, 1, 0})
    ->Args({11, 50, 4, 1, 1})
    ->Args({11, 50, 11, 0, 0})
    ->Unit(benchmark::kMicrosecond);

/// A whole causal run (`dualgraph run`'s path: runSequence with data/config/default.yaml) over the
/// simulated RATM race with d_main as given (d_temp 0.1 m); main_window −1 = the configuration's
/// (fixed-lag), 0 = full batch. Reported: the Localizer's own per-keyframe main-graph update times
/// (KeyframeStats::optimize_ms: χ² gate marginals, LM, marginalisation) over the run and over the last
/// 50 keyframes, the main graph's size at the end. The iteration time is the whole run (frontend included).
void BM_MainGraph_KeyframeUpdate(benchmark::State& state, double d_main, int main_window) {
  const Result<Sequence>& sequence = bench::ratmSequence();
  if (!sequence.ok()) return state.SkipWithError(sequence.status().message().c_str());
  Result<SequenceRunParams> params = bench::raceRunParams(d_main, main_window);
  if (!params.ok()) return state.SkipWithError(params.status().message().c_str());
  std::vector<KeyframeStats> stats;
  size_t keyframes = 0;
  for (auto _ : state) {
    Result<SequenceRunResult> run = runSequence(*sequence, *params);
    if (!run.ok()) return state.SkipWithError(run.status().message().c_str());
    stats = run->stats;
    keyframes = run->keyframes.size();
  }
  std::vector<double> all, last50, temp;
  double iterations = 0.0;
  for (const KeyframeStats& row : stats) {
    all.push_back(row.optimize_ms);
    temp.push_back(row.temp_ms);
    iterations += row.iterations;
  }
  last50.assign(all.end() - static_cast<long>(std::min<size_t>(50, all.size())), all.end());
  state.counters["keyframes"] = static_cast<double>(keyframes);
  state.counters["main_edges"] = stats.empty() ? 0.0 : stats.back().main_edges;
  state.counters["active_edges"] = stats.empty() ? 0.0 : stats.back().active_edges;
  state.counters["main_window"] = params->localizer.main_window;
  state.counters["opt_ms_p50"] = bench::percentile(all, 0.50);
  state.counters["opt_ms_p95"] = bench::percentile(all, 0.95);
  state.counters["opt_ms_max"] = bench::percentile(all, 1.0);
  state.counters["last50_ms_p50"] = bench::percentile(last50, 0.50);
  state.counters["last50_ms_p95"] = bench::percentile(last50, 0.95);
  state.counters["last50_ms_max"] = bench::percentile(last50, 1.0);
  state.counters["temp_ms_p95"] = bench::percentile(temp, 0.95);
  state.counters["lm_iterations_mean"] = all.empty() ? 0.0 : iterations / static_cast<double>(all.size());
}

// d_main chosen so the keyframe counts land near Table I's rows (≈ 250 / 1000 / 1800 keyframes) on this
// 448 m race; see bench/README.md for the sizes reached.
#define DG_KEYFRAME_BENCH(name, d_main, window)                                                   \
  BENCHMARK_CAPTURE(BM_MainGraph_KeyframeUpdate, name, d_main, window)->Unit(benchmark::kSecond) \
      ->Iterations(1)->UseRealTime()

DG_KEYFRAME_BENCH(kf250_fixed_lag, bench::kDMain250, -1);
DG_KEYFRAME_BENCH(kf1000_fixed_lag, bench::kDMain1000, -1);
DG_KEYFRAME_BENCH(kf1800_fixed_lag, bench::kDMain1800, -1);
DG_KEYFRAME_BENCH(kf250_full_batch, bench::kDMain250, 0);
DG_KEYFRAME_BENCH(kf1000_full_batch, bench::kDMain1000, 0);
DG_KEYFRAME_BENCH(kf1800_full_batch, bench::kDMain1800, 0);

}  // namespace
}  // namespace dualgraph
