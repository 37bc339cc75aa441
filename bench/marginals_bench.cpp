// SPDX-License-Identifier: MIT
// Every vertex's marginal covariance from the selected inverse of CHOLMOD's factor against one numeric
// factorisation of the same undamped H, and against the per-vertex solve path, on parking-garage, sphere2500
// and torus3D (at their initial estimates: the cost does not depend on the values). Results: bench/README.md.
// Data: ../shared/data/posegraph (DUALGRAPH_SHARED_DIR).
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_data.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/solvers/cholmod_solver.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/solvers/marginal_covariance.h"

namespace dualgraph {
namespace {

/// A dataset's undamped H at the initial estimate (through the optimiser, as MarginalCovariance builds it)
/// and every free vertex's rows.
struct MarginalsFixture {
  std::unique_ptr<Optimizer> optimizer;
  std::vector<int> free_ids;
  std::vector<int> offsets;
  std::vector<int> dims;
  size_t block_entries = 0;
  bool ok = false;
  std::string error;
};

MarginalsFixture& marginalsFixture(const std::string& name) {
  static std::map<std::string, std::unique_ptr<MarginalsFixture>> cache;
  std::unique_ptr<MarginalsFixture>& slot = cache[name];
  if (slot) return *slot;
  slot = std::make_unique<MarginalsFixture>();
  MarginalsFixture& f = *slot;
  bench::LoadedGraph& loaded = bench::loadDataset(name);
  if (!loaded.ok) {
    f.error = loaded.error;
    return f;
  }
  f.optimizer = std::make_unique<Optimizer>(loaded.graph, makeLinearSolver(LinearSolverKind::kCholmod));
  if (Status s = f.optimizer->factorizeAtCurrentEstimate(); !s.ok()) {
    f.error = s.message();
    return f;
  }
  for (const VertexBase* vertex : f.optimizer->system().activeVertices()) {
    f.free_ids.push_back(vertex->id());
    f.offsets.push_back(f.optimizer->system().offsetOf(vertex));
    f.dims.push_back(vertex->tangentDim());
    f.block_entries += static_cast<size_t>(vertex->tangentDim() * vertex->tangentDim());
  }
  f.ok = true;
  return f;
}

/// range(0): 0 = CHOLMOD's own choice (kAuto, what the optimiser uses), 1 = supernodal, 2 = simplicial.
CholmodOptions factorizationOption(int64_t kind) {
  CholmodOptions options;
  options.factorization = kind == 1 ? CholmodFactorization::kSupernodal
                          : kind == 2 ? CholmodFactorization::kSimplicial
                                      : CholmodFactorization::kAuto;
  return options;
}

/// A CholmodSolver of the benchmark's kind, analysed for the fixture's H; false (skipped) on failure.
bool prepareSolver(benchmark::State& state, const MarginalsFixture& f, CholmodSolver& solver) {
  if (!f.ok) {
    state.SkipWithError(f.error.c_str());
    return false;
  }
  const SparseMatrixView h = f.optimizer->system().matrix();
  Status s = solver.analyze(h);
  if (s.ok()) s = solver.factorize(h);
  if (!s.ok()) {
    state.SkipWithError(s.message().c_str());
    return false;
  }
  state.SetLabel(solver.name());
  state.counters["dim"] = h.n;
  state.counters["L_nnz"] = solver.lastFactorNnz();
  state.counters["vertices"] = static_cast<double>(f.free_ids.size());
  return true;
}

/// One numeric factorisation of the undamped H (the reference cost).
void BM_Marginals_Factorize(benchmark::State& state, const std::string& name) {
  MarginalsFixture& f = marginalsFixture(name);
  CholmodSolver solver(factorizationOption(state.range(0)));
  if (!prepareSolver(state, f, solver)) return;
  const SparseMatrixView h = f.optimizer->system().matrix();
  for (auto _ : state) {
    if (Status s = solver.factorize(h); !s.ok()) return state.SkipWithError(s.message().c_str());
  }
}

/// The selected inverse alone: every free vertex's diagonal block of H⁻¹ from a fresh factor (the
/// factorisation itself is outside the timed region).
void BM_Marginals_SelectedInverse(benchmark::State& state, const std::string& name) {
  MarginalsFixture& f = marginalsFixture(name);
  CholmodSolver solver(factorizationOption(state.range(0)));
  if (!prepareSolver(state, f, solver)) return;
  const SparseMatrixView h = f.optimizer->system().matrix();
  std::vector<double> blocks(f.block_entries);
  for (auto _ : state) {
    state.PauseTiming();
    if (Status s = solver.factorize(h); !s.ok()) return state.SkipWithError(s.message().c_str());
    state.ResumeTiming();
    const Status s = solver.inverseDiagonalBlocks(f.offsets.data(), f.dims.data(), static_cast<int>(f.offsets.size()),
                                                  blocks.data());
    if (!s.ok()) return state.SkipWithError(s.message().c_str());
    benchmark::DoNotOptimize(blocks.data());
  }
}

/// Factorisation plus selected inverse: every vertex's covariance from H.
void BM_Marginals_FactorizeAndSelectedInverse(benchmark::State& state, const std::string& name) {
  MarginalsFixture& f = marginalsFixture(name);
  CholmodSolver solver(factorizationOption(state.range(0)));
  if (!prepareSolver(state, f, solver)) return;
  const SparseMatrixView h = f.optimizer->system().matrix();
  std::vector<double> blocks(f.block_entries);
  for (auto _ : state) {
    Status s = solver.factorize(h);
    if (s.ok()) {
      s = solver.inverseDiagonalBlocks(f.offsets.data(), f.dims.data(), static_cast<int>(f.offsets.size()),
                                       blocks.data());
    }
    if (!s.ok()) return state.SkipWithError(s.message().c_str());
    benchmark::DoNotOptimize(blocks.data());
  }
}

/// The public path end to end: MarginalCovariance::compute (linearise, assemble, factorise the undamped H,
/// gauge check) then blocks(every free vertex), as `dualgraph optimize --marginals` runs it.
void BM_Marginals_ComputeAndBlocks(benchmark::State& state, const std::string& name) {
  MarginalsFixture& f = marginalsFixture(name);
  if (!f.ok) return state.SkipWithError(f.error.c_str());
  Graph& graph = bench::loadDataset(name).graph;
  for (auto _ : state) {
    MarginalCovariance marginals;
    if (Status s = marginals.compute(*f.optimizer, graph); !s.ok()) return state.SkipWithError(s.message().c_str());
    Result<std::vector<Eigen::MatrixXd>> blocks = marginals.blocks(f.free_ids);
    if (!blocks.ok()) return state.SkipWithError(blocks.status().message().c_str());
    benchmark::DoNotOptimize(blocks->data());
  }
  state.SetLabel(f.optimizer->linearSolver().name());
  state.counters["vertices"] = static_cast<double>(f.free_ids.size());
}

/// The per-vertex path the selected inverse replaces: compute, then block(id) (a solve with tangentDim
/// right-hand sides) for every free vertex.
void BM_Marginals_PerVertexSolves(benchmark::State& state, const std::string& name) {
  MarginalsFixture& f = marginalsFixture(name);
  if (!f.ok) return state.SkipWithError(f.error.c_str());
  Graph& graph = bench::loadDataset(name).graph;
  double trace = 0.0;
  for (auto _ : state) {
    MarginalCovariance marginals;
    if (Status s = marginals.compute(*f.optimizer, graph); !s.ok()) return state.SkipWithError(s.message().c_str());
    for (int id : f.free_ids) {
      Result<Eigen::MatrixXd> sigma = marginals.block(id);
      if (!sigma.ok()) return state.SkipWithError(sigma.status().message().c_str());
      trace += sigma->trace();
    }
  }
  benchmark::DoNotOptimize(&trace);
  state.SetLabel(f.optimizer->linearSolver().name());
  state.counters["vertices"] = static_cast<double>(f.free_ids.size());
}

// clang-format off (the names are stringized: `parking-garage` must stay as written)
#define DG_MARGINALS_BENCH(dataset)                                                                                   \
  BENCHMARK_CAPTURE(BM_Marginals_Factorize, dataset, #dataset)->DenseRange(0, 2)->ArgName("kind")                    \
      ->Unit(benchmark::kMillisecond);                                                                                \
  BENCHMARK_CAPTURE(BM_Marginals_SelectedInverse, dataset, #dataset)->DenseRange(0, 2)->ArgName("kind")              \
      ->Unit(benchmark::kMillisecond);                                                                                \
  BENCHMARK_CAPTURE(BM_Marginals_FactorizeAndSelectedInverse, dataset, #dataset)->DenseRange(0, 2)->ArgName("kind")  \
      ->Unit(benchmark::kMillisecond);                                                                                \
  BENCHMARK_CAPTURE(BM_Marginals_ComputeAndBlocks, dataset, #dataset)->Unit(benchmark::kMillisecond);                \
  BENCHMARK_CAPTURE(BM_Marginals_PerVertexSolves, dataset, #dataset)->Unit(benchmark::kMillisecond)->Iterations(1)
DG_MARGINALS_BENCH(parking-garage);
DG_MARGINALS_BENCH(sphere2500);
DG_MARGINALS_BENCH(torus3D);
// clang-format on

}  // namespace
}  // namespace dualgraph
