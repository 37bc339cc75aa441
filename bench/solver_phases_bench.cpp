// SPDX-License-Identifier: MIT
// The phases of one LM iteration timed one by one on the real pose graphs — linearisation of every
// edge, Hessian assembly, CHOLMOD's symbolic analysis, numeric factorisation and solve through our
// CholmodSolver — and the marginal covariances of every pose of parking-garage.
// Data: ../shared/data/posegraph (DUALGRAPH_SHARED_DIR).
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <algorithm>
#include <map>
#include <memory>
#include <string>

#include "bench/bench_data.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/core/sparse_system.h"
#include "dualgraph/solvers/cholmod_solver.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/solvers/marginal_covariance.h"

namespace dualgraph {
namespace {

CholmodOptions supernodalOptions() {
  CholmodOptions options;
  options.factorization = CholmodFactorization::kSupernodal;
  return options;
}

/// A dataset's system linearised and assembled at the initial estimate, analysed and factorised once, with
/// the supernodal factorisation (the simplicial one is BM_Cholmod_FactorizeSimplicial; CholmodSolver's
/// default, kAuto, picks one of the two per pattern).
struct Phases {
  SparseSystem system;
  CholmodSolver solver{supernodalOptions()};
  bool ok = false;
  std::string error;
};

Phases& phases(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Phases>> cache;
  std::unique_ptr<Phases>& slot = cache[name];
  if (slot) return *slot;
  slot = std::make_unique<Phases>();
  Phases& p = *slot;
  bench::LoadedGraph& loaded = bench::loadDataset(name);
  if (!loaded.ok) {
    p.error = loaded.error;
    return p;
  }
  if (Status built = p.system.build(loaded.graph); !built.ok()) {
    p.error = built.message();
    return p;
  }
  for (EdgeBase* edge : p.system.activeEdges()) edge->linearize();
  p.system.assemble();
  Status status = p.solver.analyze(p.system.matrix());
  if (status.ok()) status = p.solver.factorize(p.system.matrix());
  p.ok = status.ok();
  if (!p.ok) p.error = status.message();
  return p;
}

void setSizeCounters(benchmark::State& state, const Phases& p) {
  state.counters["dim"] = p.system.dim();
  state.counters["H_nnz"] = p.system.matrix().nnz();
  state.counters["L_nnz"] = p.solver.lastFactorNnz();
}

/// Error and Jacobians of every active edge (in an LM iteration this is fused with the assembly).
void BM_PoseGraph_Linearize(benchmark::State& state, const std::string& name) {
  Phases& p = phases(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  for (auto _ : state) {
    for (EdgeBase* edge : p.system.activeEdges()) edge->linearize();
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(p.system.activeEdges().size()));
}

/// H = Σ JᵀΩJ and b into the prebuilt pattern (Jacobians current).
void BM_PoseGraph_Assemble(benchmark::State& state, const std::string& name) {
  Phases& p = phases(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  for (auto _ : state) {
    p.system.assemble();
    benchmark::DoNotOptimize(p.system.rhs().data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(p.system.activeEdges().size()));
  setSizeCounters(state, p);
}

/// Ordering + symbolic factorisation (once per structure in the optimiser), on a fresh solver.
void BM_Cholmod_Analyze(benchmark::State& state, const std::string& name) {
  Phases& p = phases(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  CholmodSolver solver;
  for (auto _ : state) {
    const Status status = solver.analyze(p.system.matrix());
    if (!status.ok()) return state.SkipWithError(status.message().c_str());
  }
  state.SetLabel(solver.orderingUsed());
  setSizeCounters(state, p);
}

/// Numeric supernodal factorisation of the analysed pattern (once per LM trial).
void BM_Cholmod_Factorize(benchmark::State& state, const std::string& name) {
  Phases& p = phases(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  for (auto _ : state) {
    const Status status = p.solver.factorize(p.system.matrix());
    if (!status.ok()) return state.SkipWithError(status.message().c_str());
  }
  setSizeCounters(state, p);
  state.counters["GFLOPs"] = benchmark::Counter(p.solver.factorFlops() * 1e-9 * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}

/// The same numeric factorisation with CHOLMOD's simplicial LLᵀ (CholmodFactorization::kSimplicial), analysed
/// outside the loop: on very sparse factors (2-D graphs) the supernodal BLAS-3 path has more overhead than it
/// saves; CHOLMOD's own CHOLMOD_AUTO choice makes this switch by flops per factor entry.
void BM_Cholmod_FactorizeSimplicial(benchmark::State& state, const std::string& name) {
  Phases& p = phases(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  CholmodOptions options;
  options.factorization = CholmodFactorization::kSimplicial;
  CholmodSolver solver(options);
  if (Status s = solver.analyze(p.system.matrix()); !s.ok()) return state.SkipWithError(s.message().c_str());
  for (auto _ : state) {
    const Status status = solver.factorize(p.system.matrix());
    if (!status.ok()) return state.SkipWithError(status.message().c_str());
  }
  setSizeCounters(state, p);
  state.counters["flops_per_L_entry"] = solver.factorFlops() / std::max(1.0, solver.lastFactorNnz());
}

/// Forward and back substitution with the factor (once per LM trial).
void BM_Cholmod_Solve(benchmark::State& state, const std::string& name) {
  Phases& p = phases(name);
  if (!p.ok) return state.SkipWithError(p.error.c_str());
  Eigen::VectorXd x(p.system.dim());
  for (auto _ : state) {
    const Status status = p.solver.solve(p.system.rhs().data(), x.data());
    if (!status.ok()) return state.SkipWithError(status.message().c_str());
    benchmark::DoNotOptimize(x.data());
  }
  setSizeCounters(state, p);
}

#define DG_PHASES_BENCH(dataset)                                                                    \
  BENCHMARK_CAPTURE(BM_PoseGraph_Linearize, dataset, #dataset)->Unit(benchmark::kMillisecond);      \
  BENCHMARK_CAPTURE(BM_PoseGraph_Assemble, dataset, #dataset)->Unit(benchmark::kMillisecond);       \
  BENCHMARK_CAPTURE(BM_Cholmod_Analyze, dataset, #dataset)->Unit(benchmark::kMillisecond);          \
  BENCHMARK_CAPTURE(BM_Cholmod_Factorize, dataset, #dataset)->Unit(benchmark::kMillisecond);        \
  BENCHMARK_CAPTURE(BM_Cholmod_FactorizeSimplicial, dataset, #dataset)->Unit(benchmark::kMillisecond); \
  BENCHMARK_CAPTURE(BM_Cholmod_Solve, dataset, #dataset)->Unit(benchmark::kMillisecond)

DG_PHASES_BENCH(sphere2500);
DG_PHASES_BENCH(parking-garage);
DG_PHASES_BENCH(intel);

/// The marginal covariance of every pose of a dataset (at its initial estimate: the cost does not depend
/// on the values): MarginalCovariance::compute (one factorisation), then jointBlock over groups of
/// `range(0)` vertices (one block solve with 6·group right-hand sides each), keeping the diagonal blocks.
void BM_Marginals_AllPoseBlocks(benchmark::State& state, const std::string& name) {
  bench::LoadedGraph& loaded = bench::loadDataset(name);
  if (!loaded.ok) return state.SkipWithError(loaded.error.c_str());
  std::vector<int> free_ids;
  for (const auto& [id, vertex] : loaded.graph.vertices()) {
    if (!vertex->fixed()) free_ids.push_back(id);
  }
  const size_t group = static_cast<size_t>(state.range(0));
  Optimizer optimizer(loaded.graph, makeLinearSolver(LinearSolverKind::kCholmod));
  double trace = 0.0;
  for (auto _ : state) {
    MarginalCovariance marginals;
    if (Status s = marginals.compute(optimizer, loaded.graph); !s.ok()) return state.SkipWithError(s.message().c_str());
    for (size_t begin = 0; begin < free_ids.size(); begin += group) {
      const size_t end = std::min(free_ids.size(), begin + group);
      Result<Eigen::MatrixXd> joint =
          marginals.jointBlock(std::vector<int>(free_ids.begin() + static_cast<long>(begin), free_ids.begin() + static_cast<long>(end)));
      if (!joint.ok()) return state.SkipWithError(joint.status().message().c_str());
      trace += joint->trace();  // the diagonal blocks are what a caller keeps
    }
  }
  benchmark::DoNotOptimize(&trace);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(free_ids.size()));
  state.counters["poses"] = static_cast<double>(free_ids.size());
}
// clang-format off (the name is stringized: `parking-garage` must stay as written)
BENCHMARK_CAPTURE(BM_Marginals_AllPoseBlocks, parking-garage, "parking-garage")
    ->Arg(16)->Arg(64)->Arg(256)->ArgName("group")->Unit(benchmark::kMillisecond)->Iterations(1);
// clang-format on

}  // namespace
}  // namespace dualgraph
