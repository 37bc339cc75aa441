// SPDX-License-Identifier: MIT
// One LM iteration of our engine against the bare CHOLMOD factorisation + solve of exactly the
// Hessian that iteration builds, on the real 3-D pose graphs, so the engine's overhead shows as a
// ratio measured in the same run. Data: ../shared/data/posegraph (DUALGRAPH_SHARED_DIR).
#include <benchmark/benchmark.h>
#include <cholmod.h>

#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/types/register_types.h"

namespace dualgraph {
namespace {

std::string datasetPath(const std::string& name) {
  const char* dir = std::getenv("DUALGRAPH_SHARED_DIR");
  return std::string(dir != nullptr ? dir : DUALGRAPH_DEFAULT_SHARED_DIR) + "/data/posegraph/" + name + ".g2o";
}

/// A loaded dataset with the gauge fixed and an optimiser whose structure is built.
struct Problem {
  TypeRegistry registry;
  Graph graph;
  std::unique_ptr<Optimizer> optimizer;
  bool ok = false;
  std::string error;
};

Problem& problem(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Problem>> cache;
  auto& slot = cache[name];
  if (slot) return *slot;
  slot = std::make_unique<Problem>();
  Problem& p = *slot;
  (void)registerBuiltinTypes(p.registry);
  const auto report = readG2o(datasetPath(name), p.registry, p.graph);
  if (!report.ok()) {
    p.error = report.status().message();
    return p;
  }
  if (VertexBase* gauge = chooseGaugeVertex(p.graph, GaugeChoice::kHighestId)) (void)p.graph.setFixed(gauge->id(), true);
  p.optimizer = std::make_unique<Optimizer>(p.graph, makeLinearSolver(LinearSolverKind::kCholmod));
  // Builds the structure and the symbolic analysis outside the timed loops.
  p.ok = p.optimizer->factorizeAtCurrentEstimate().ok();
  if (!p.ok) p.error = "factorisation at the initial estimate failed";
  return p;
}

void pushAll(Graph& graph) {
  for (auto& [id, v] : graph.vertices()) v->push();
}
void popAll(Graph& graph) {
  for (auto& [id, v] : graph.vertices()) v->pop();
}

/// One LM iteration from the initial estimate: χ², linearise, assemble, damp, factorise, solve,
/// update, χ². The estimate is restored outside the timed region.
void BM_PoseGraph_LmIteration(benchmark::State& state, const std::string& name) {
  Problem& p = problem(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  OptimizerParams params;
  params.max_iterations = 1;
  int factorizations = 0;
  for (auto _ : state) {
    state.PauseTiming();
    pushAll(p.graph);
    state.ResumeTiming();
    const SolverSummary summary = p.optimizer->optimize(params);
    benchmark::DoNotOptimize(&summary);
    factorizations += summary.factorizations;
    state.PauseTiming();
    popAll(p.graph);
    state.ResumeTiming();
  }
  state.counters["factorizations_per_iteration"] =
      benchmark::Counter(factorizations, benchmark::Counter::kAvgIterations);
}

/// The same single iteration timed by the optimiser's own phase clocks: Jacobians + assembly +
/// factorisation + solve + update and χ² of the trial — what a steady-state iteration costs,
/// i.e. without the initial χ² evaluation that every optimize() call starts with.
void BM_PoseGraph_LmIterationPhases(benchmark::State& state, const std::string& name) {
  Problem& p = problem(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  OptimizerParams params;
  params.max_iterations = 1;
  for (auto _ : state) {
    pushAll(p.graph);
    const SolverSummary summary = p.optimizer->optimize(params);
    benchmark::DoNotOptimize(&summary);
    state.SetIterationTime(1e-3 * (summary.linearize_ms + summary.assemble_ms + summary.factorize_ms +
                                   summary.solve_ms + summary.update_ms));
    popAll(p.graph);
  }
}

/// The floor: CHOLMOD (same settings as CholmodSolver: CHOLMOD's own supernodal/simplicial choice, LLᵀ,
/// default ordering, analysed once outside the loop) numeric factorisation + solve of the very Hessian the
/// LM iteration above builds.
void BM_PoseGraph_BareCholmodFactorSolve(benchmark::State& state, const std::string& name) {
  Problem& p = problem(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  const SparseSystem& system = p.optimizer->system();
  const SparseMatrixView view = system.matrix();
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  common.supernodal = CHOLMOD_AUTO;
  common.final_ll = 1;
  cholmod_sparse a{};
  a.nrow = a.ncol = view.n;
  a.nzmax = view.nnz();
  a.p = const_cast<int*>(view.col_ptr);
  a.i = const_cast<int*>(view.row_index);
  a.x = const_cast<double*>(view.values);
  a.stype = 1;
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_REAL;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  cholmod_factor* factor = cholmod_analyze(&a, &common);
  cholmod_dense* b = cholmod_zeros(view.n, 1, CHOLMOD_REAL, &common);
  for (int k = 0; k < view.n; ++k) static_cast<double*>(b->x)[k] = system.rhs()[k];
  cholmod_dense* x = nullptr;
  cholmod_dense* y = nullptr;
  cholmod_dense* e = nullptr;
  for (auto _ : state) {
    cholmod_factorize(&a, factor, &common);
    cholmod_solve2(CHOLMOD_A, factor, b, nullptr, &x, nullptr, &y, &e, &common);
    benchmark::DoNotOptimize(x->x);
  }
  if (common.status != CHOLMOD_OK) state.SkipWithError("CHOLMOD reported an error");
  state.counters["factor_nnz"] = static_cast<double>(common.lnz);
  cholmod_free_dense(&x, &common);
  cholmod_free_dense(&y, &common);
  cholmod_free_dense(&e, &common);
  cholmod_free_dense(&b, &common);
  cholmod_free_factor(&factor, &common);
  cholmod_finish(&common);
}

/// A full solve (≤ 100 LM iterations) from the initial estimate, as `dualgraph optimize` runs it.
void BM_PoseGraph_FullSolve(benchmark::State& state, const std::string& name) {
  Problem& p = problem(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  OptimizerParams params;
  int iterations = 0;
  for (auto _ : state) {
    state.PauseTiming();
    pushAll(p.graph);
    state.ResumeTiming();
    const SolverSummary summary = p.optimizer->optimize(params);
    iterations += summary.iterations;
    benchmark::DoNotOptimize(&summary);
    state.PauseTiming();
    popAll(p.graph);
    state.ResumeTiming();
  }
  state.counters["lm_iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
}

#define DG_POSEGRAPH_BENCH(dataset)                                                              \
  BENCHMARK_CAPTURE(BM_PoseGraph_LmIteration, dataset, #dataset)->Unit(benchmark::kMillisecond); \
  BENCHMARK_CAPTURE(BM_PoseGraph_LmIterationPhases, dataset, #dataset)                           \
      ->UseManualTime()                                                                          \
      ->Unit(benchmark::kMillisecond);                                                           \
  BENCHMARK_CAPTURE(BM_PoseGraph_BareCholmodFactorSolve, dataset, #dataset)                      \
      ->Unit(benchmark::kMillisecond);                                                           \
  BENCHMARK_CAPTURE(BM_PoseGraph_FullSolve, dataset, #dataset)->Unit(benchmark::kMillisecond)->Iterations(3)

DG_POSEGRAPH_BENCH(sphere2500);
DG_POSEGRAPH_BENCH(parking-garage);
DG_POSEGRAPH_BENCH(smallGrid3D);
DG_POSEGRAPH_BENCH(intel);

}  // namespace
}  // namespace dualgraph
// main(): bench/bench_main.cpp
