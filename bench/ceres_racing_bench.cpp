// SPDX-License-Identifier: MIT
// dualgraph and Ceres side by side on the racing main graph: the Localizer's full-batch main graph at the
// end of the simulated RATM race (≈ 250 and ≈ 1800 keyframes: bench/race_fixture.h), copied, its free
// vertices perturbed by a seeded random increment (σ 0.1 m and δq 0.01 ≈ 1.1°, the same start for both),
// then solved cold by each: our Optimizer with the Localizer's linear solver (auto) or CHOLMOD, and Ceres
// (SPARSE_NORMAL_CHOLESKY, SuiteSparse), with the main graph's stopping rules (≤ 10 iterations,
// relative decrease 1e-6) and with the engine's defaults (≤ 100, 1e-9). Same vertices, edges, information
// matrices and Huber kernels (Ceres' HuberLoss is the same ρ). Wall time; the pair runs back to back.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

#include "bench/bench_data.h"
#include "bench/ceres_pose_graph.h"
#include "bench/perturb_graph.h"
#include "bench/race_fixture.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/solvers/linear_solver_factory.h"

namespace dualgraph {
namespace {

/// The perturbed copy of a race's final full-batch main graph, built once per d_main.
struct RacingProblem {
  Graph graph;
  LinearSolverKind localizer_solver = LinearSolverKind::kAuto;
  size_t keyframes = 0;
  bool ok = false;
  std::string error;
};

RacingProblem& racingProblem(double d_main) {
  static std::map<double, std::unique_ptr<RacingProblem>> cache;
  std::unique_ptr<RacingProblem>& slot = cache[d_main];
  if (slot) return *slot;
  slot = std::make_unique<RacingProblem>();
  RacingProblem& p = *slot;
  const Result<Sequence>& sequence = bench::ratmSequence();
  Result<SequenceRunParams> params = bench::raceRunParams(d_main, 0);
  Status status = !sequence.ok() ? sequence.status() : params.status();
  if (status.ok()) {
    p.localizer_solver = params->localizer.linear_solver;
    Result<std::unique_ptr<Localizer>> localizer = bench::runRaceLocalizer(*sequence, *params);
    status = localizer.ok() ? cloneGraph((*localizer)->mainGraph().graph(), p.graph) : localizer.status();
    if (localizer.ok()) p.keyframes = (*localizer)->mainGraph().keyframes().size();
  }
  if (status.ok()) bench::perturbGraph(p.graph, 0.1, 0.01, 1);
  p.ok = status.ok();
  p.error = status.message();
  return p;
}

struct StopRules {
  int max_iterations;
  double relative_decrease;
};
constexpr StopRules kMainGraphRules{10, 1e-6};  // LocalizerParams main_max_iterations / main_relative_decrease_stop
constexpr StopRules kEngineRules{100, 1e-9};    // OptimizerParams defaults

void setCounters(benchmark::State& state, const RacingProblem& p, double total_ms, int iterations, int factorizations,
                 double initial_chi2, double final_chi2) {
  state.counters["keyframes"] = static_cast<double>(p.keyframes);
  state.counters["edges"] = static_cast<double>(p.graph.numEdges());
  state.counters["iterations"] = iterations;
  state.counters["factorizations"] = factorizations;
  state.counters["ms_per_iteration"] = iterations > 0 ? total_ms / iterations : 0.0;
  state.counters["initial_chi2"] = initial_chi2;
  state.counters["final_chi2"] = final_chi2;
}

/// Ours, cold: a fresh Optimizer (pattern, symbolic analysis) and LM from the perturbed start.
void BM_RacingMainGraph_Dualgraph(benchmark::State& state, double d_main, StopRules rules, bool cholmod,
                                  LmDamping damping) {
  RacingProblem& p = racingProblem(d_main);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  const LinearSolverKind kind = cholmod ? LinearSolverKind::kCholmod : p.localizer_solver;
  OptimizerParams params;
  params.max_iterations = rules.max_iterations;
  params.relative_decrease_stop = rules.relative_decrease;
  params.damping = damping;
  SolverSummary summary;
  for (auto _ : state) {
    state.PauseTiming();
    bench::pushAll(p.graph);
    state.ResumeTiming();
    Optimizer optimizer(p.graph, makeLinearSolver(kind));
    summary = optimizer.optimize(params);
    benchmark::DoNotOptimize(&summary);
    state.PauseTiming();
    bench::popAll(p.graph);
    state.ResumeTiming();
  }
  if (!summary.usable()) return state.SkipWithError(summary.message.c_str());
  setCounters(state, p, summary.total_ms, summary.iterations, summary.factorizations, summary.initial_chi2,
              summary.final_chi2);
  state.SetLabel(std::string(linearSolverKindName(kind)) + " " + lmDampingName(damping) + " " +
                 terminationReasonName(summary.termination));
}

/// Ceres from the same perturbed start.
void BM_RacingMainGraph_Ceres(benchmark::State& state, double d_main, StopRules rules) {
  RacingProblem& p = racingProblem(d_main);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  Result<std::unique_ptr<bench::CeresPoseGraph>> peer = bench::CeresPoseGraph::create(p.graph);
  if (!peer.ok()) return state.SkipWithError(peer.status().message().c_str());
  bench::CeresSolveOptions options;
  options.max_iterations = rules.max_iterations;
  options.function_tolerance = rules.relative_decrease;
  bench::CeresSolveOutcome outcome;
  for (auto _ : state) {
    state.PauseTiming();
    (*peer)->copyEstimatesFrom(p.graph);
    state.ResumeTiming();
    outcome = (*peer)->solve(options);
    benchmark::DoNotOptimize(&outcome);
  }
  if (!outcome.usable) return state.SkipWithError(outcome.termination.c_str());
  setCounters(state, p, outcome.total_ms, outcome.iterations, outcome.linear_solves, outcome.initial_chi2,
              outcome.final_chi2);
  state.counters["jacobian_ms"] = outcome.jacobian_ms;
  state.counters["linear_solver_ms"] = outcome.linear_solver_ms;
  bench::pushAll(p.graph);
  (*peer)->copyEstimatesTo(p.graph);
  state.counters["final_chi2_our_edges"] = p.graph.chi2(true);
  bench::popAll(p.graph);
  state.SetLabel(outcome.termination.substr(0, outcome.termination.find(':')));
}

#define DG_RACING_SIDE_BY_SIDE(name, d_main, rules)                                                              \
  BENCHMARK_CAPTURE(BM_RacingMainGraph_Dualgraph, name, d_main, rules, false, LmDamping::kIdentity)            \
      ->Unit(benchmark::kMillisecond)->UseRealTime();                                                           \
  BENCHMARK_CAPTURE(BM_RacingMainGraph_Dualgraph, name##_diagonal, d_main, rules, false, LmDamping::kDiagonal)  \
      ->Unit(benchmark::kMillisecond)->UseRealTime();                                                           \
  BENCHMARK_CAPTURE(BM_RacingMainGraph_Dualgraph, name##_cholmod, d_main, rules, true, LmDamping::kIdentity)    \
      ->Unit(benchmark::kMillisecond)->UseRealTime();                                                           \
  BENCHMARK_CAPTURE(BM_RacingMainGraph_Ceres, name, d_main, rules)->Unit(benchmark::kMillisecond)->UseRealTime()

DG_RACING_SIDE_BY_SIDE(kf250_cap10, bench::kDMain250, kMainGraphRules);
DG_RACING_SIDE_BY_SIDE(kf1800_cap10, bench::kDMain1800, kMainGraphRules);
DG_RACING_SIDE_BY_SIDE(kf250_cap100, bench::kDMain250, kEngineRules);
DG_RACING_SIDE_BY_SIDE(kf1800_cap100, bench::kDMain1800, kEngineRules);

}  // namespace
}  // namespace dualgraph
