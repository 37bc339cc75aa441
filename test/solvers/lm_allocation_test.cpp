// SPDX-License-Identifier: MIT
// No heap allocation by the engine inside the Levenberg–Marquardt / Gauss–Newton iteration once the
// structure is built: this executable counts every malloc/calloc/realloc (operator new included:
// libstdc++'s new calls malloc) and compares the counts at consecutive iteration callbacks: any
// allocation inside an iteration (after the first, which builds the structure and runs the symbolic
// analysis) shows up as a non-zero difference. Allocations inside the linear solver are attributed to it
// by a forwarding solver: none either for EigenSolver (and AutoSolver on this small graph); CHOLMOD's
// are printed, not asserted (cholmod_factorize allocates its permuted transpose at every call).
// The temporary graph's block solver (solvers/block/block_lm_solver.h, its own LM on BlockCholesky) the same
// way, with both kernel sets, and its marginals when computed again.
// (Interposing malloc is not possible under AddressSanitizer, which owns malloc: skipped there, also when
// only the libraries are instrumented: DUALGRAPH_TEST_LINKS_SANITIZERS, test/CMakeLists.txt.)
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdlib>
#include <random>

#include "dualgraph/core/optimizer.h"
#include "dualgraph/core/linear_solver.h"
#include "dualgraph/solvers/block/block_lm_solver.h"
#include "dualgraph/solvers/block/block_kernels_avx2.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/vertex_se3.h"

#if defined(__SANITIZE_ADDRESS__) || DUALGRAPH_TEST_LINKS_SANITIZERS  // (test files may be uninstrumented)
#define DUALGRAPH_COUNT_MALLOC 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define DUALGRAPH_COUNT_MALLOC 0
#endif
#endif
#ifndef DUALGRAPH_COUNT_MALLOC
#define DUALGRAPH_COUNT_MALLOC 1
#endif

namespace {
std::atomic<long> g_allocations{0};         ///< outside the linear solver
std::atomic<long> g_solver_allocations{0};  ///< inside LinearSolver calls (CHOLMOD's / Eigen's own)
std::atomic<bool> g_in_solver{false};
void countAllocation() {
  (g_in_solver.load(std::memory_order_relaxed) ? g_solver_allocations : g_allocations)
      .fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

#if DUALGRAPH_COUNT_MALLOC
extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* pointer, size_t size);
void* malloc(size_t size) {
  countAllocation();
  return __libc_malloc(size);
}
void* calloc(size_t count, size_t size) {
  countAllocation();
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, size_t size) {
  countAllocation();
  return __libc_realloc(pointer, size);
}
}
#endif

namespace dualgraph {
namespace {

/// A noisy SE(3) pose graph: a 3-turn spiral of 60 poses with odometry and loop closures between
/// turns, the first pose fixed, every estimate perturbed so LM needs many iterations.
void buildSpiral(Graph& graph) {
  std::mt19937 rng(17);
  std::normal_distribution<double> noise(0.0, 1.0);
  auto perturbation = [&](double sigma) {
    Vector6d v;
    for (int k = 0; k < 6; ++k) v(k) = sigma * noise(rng);
    v.tail<3>() *= 0.2;
    return g2oIncrement(v);
  };
  std::vector<Eigen::Isometry3d> truth;
  for (int k = 0; k < 60; ++k) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    const double angle = 2.0 * M_PI * k / 20.0;
    pose.translation() << 5.0 * std::cos(angle), 5.0 * std::sin(angle), 0.1 * k;
    pose.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    truth.push_back(pose);
    auto vertex = std::make_unique<VertexSE3>(k);
    vertex->setEstimate(k == 0 ? pose : pose * perturbation(0.3));
    vertex->setFixed(k == 0);
    ASSERT_TRUE(graph.addVertex(std::move(vertex)).ok());
  }
  auto connect = [&](int a, int b) {
    auto edge = std::make_unique<EdgeSE3>();
    edge->setMeasurement(truth[a].inverse() * truth[b] * perturbation(0.02));
    ASSERT_TRUE(edge->setVertex(0, graph.vertex(a)).ok());
    ASSERT_TRUE(edge->setVertex(1, graph.vertex(b)).ok());
    ASSERT_TRUE(graph.addEdge(std::move(edge)).ok());
  };
  for (int k = 0; k + 1 < 60; ++k) connect(k, k + 1);
  for (int k = 0; k + 20 < 60; ++k) connect(k, k + 20);
}

/// Allocations between consecutive iteration callbacks (the callback writes into preallocated arrays):
/// the engine's in `engine`, the linear solver library's in `library`.
void allocationsPerIteration(Optimizer& optimizer, Algorithm algorithm, SolverSummary& summary,
                             std::vector<long>& engine, std::vector<long>& library) {
  std::array<long, 64> engine_at{}, library_at{};
  int calls = 0;
  OptimizerParams params;
  params.algorithm = algorithm;
  params.max_iterations = 30;
  params.callback = [&](const IterationSummary&) {
    if (calls >= static_cast<int>(engine_at.size())) return;
    engine_at[calls] = g_allocations.load();
    library_at[calls++] = g_solver_allocations.load();
  };
  summary = optimizer.optimize(params);
  for (int k = 1; k < calls; ++k) {
    engine.push_back(engine_at[k] - engine_at[k - 1]);
    library.push_back(library_at[k] - library_at[k - 1]);
  }
}

/// Forwards to a real solver and attributes the allocations made inside it to the library.
class AttributingSolver final : public LinearSolver {
 public:
  explicit AttributingSolver(std::unique_ptr<LinearSolver> inner) : inner_(std::move(inner)) {}
  Status analyze(const SparseMatrixView& m) override { return inside([&] { return inner_->analyze(m); }); }
  Status factorize(const SparseMatrixView& m) override { return inside([&] { return inner_->factorize(m); }); }
  Status solve(const double* b, double* x) override { return inside([&] { return inner_->solve(b, x); }); }
  Status solveColumns(const double* B, double* X, int n, int c) override {
    return inside([&] { return inner_->solveColumns(B, X, n, c); });
  }
  std::string name() const override { return inner_->name(); }

 private:
  template <typename F>
  Status inside(F&& call) {
    g_in_solver = true;
    Status status = call();
    g_in_solver = false;
    return status;
  }
  std::unique_ptr<LinearSolver> inner_;
};

class LmAllocation : public ::testing::TestWithParam<std::tuple<LinearSolverKind, Algorithm>> {};

TEST_P(LmAllocation, IterationsAllocateNothingOnceTheStructureIsBuilt) {
  if (!DUALGRAPH_COUNT_MALLOC) GTEST_SKIP() << "malloc cannot be interposed under AddressSanitizer";
  const auto [kind, algorithm] = GetParam();
  Graph graph;
  buildSpiral(graph);
  Optimizer optimizer(graph, std::make_unique<AttributingSolver>(makeLinearSolver(kind)));
  // The counter itself works: building anything allocates.
  const long probe = g_allocations.load();
  { std::vector<double> v(100, 1.0); EXPECT_GT(v.size(), 0u); }
  ASSERT_GT(g_allocations.load(), probe);
  SolverSummary summary;
  std::vector<long> engine, library;
  allocationsPerIteration(optimizer, algorithm, summary, engine, library);
  ASSERT_TRUE(summary.usable()) << summary.message;
  ASSERT_GE(engine.size(), 3u) << "too few iterations to say anything";
  long library_total = 0;
  for (size_t k = 0; k < engine.size(); ++k) {
    EXPECT_EQ(engine[k], 0) << "iteration " << k + 2 << " of " << summary.iterations;
    // Our EigenSolver factorises and solves the pre-ordered matrix in place: nothing either.
    if (kind != LinearSolverKind::kCholmod) {
      EXPECT_EQ(library[k], 0) << "iteration " << k + 2;
    }
    library_total += library[k];
  }
  // CHOLMOD's cholmod_factorize allocates the permuted transpose of H at every call: reported, not hidden.
  std::cout << "[ alloc ] " << linearSolverKindName(kind) << ", " << summary.iterations
            << " iterations: engine allocations in iterations 2.." << summary.iterations << ": 0; linear solver: "
            << library_total << "\n";
}

/// Parameter: the AVX2 + FMA kernels on (skipped without them) or the baseline ones.
class TemporarySolverAllocation : public ::testing::TestWithParam<bool> {
 protected:
  void TearDown() override { block_kernels_avx2::setEnabled(true); }
};

TEST_P(TemporarySolverAllocation, IterationsAndRepeatedMarginalsAllocateNothing) {
  if (!DUALGRAPH_COUNT_MALLOC) GTEST_SKIP() << "malloc cannot be interposed under AddressSanitizer";
  if (block_kernels_avx2::setEnabled(GetParam()) != GetParam()) GTEST_SKIP() << "this CPU has no AVX2 + FMA";
  Graph graph;
  buildSpiral(graph);
  BlockLmSolver solver;
  ASSERT_TRUE(solver.setGraph(graph).ok());
  std::array<long, 64> at{};
  int calls = 0;
  OptimizerParams params;
  params.max_iterations = 30;
  params.relative_decrease_stop = 1e-12;
  params.callback = [&](const IterationSummary&) {
    if (calls < static_cast<int>(at.size())) at[calls++] = g_allocations.load();
  };
  const SolverSummary summary = solver.optimize(params);
  ASSERT_TRUE(summary.usable()) << summary.message;
  ASSERT_GE(calls, 3) << "too few iterations to say anything";
  // Iteration 1 may size the vertices' undo stacks; none after it (the linear algebra included).
  for (int k = 1; k < calls; ++k) EXPECT_EQ(at[k] - at[k - 1], 0) << "iteration " << k + 1 << " of " << summary.iterations;
  ASSERT_TRUE(solver.computeMarginals().ok());
  const long before = g_allocations.load();
  ASSERT_TRUE(solver.computeMarginals().ok());
  EXPECT_EQ(g_allocations.load(), before) << "a second computeMarginals allocated";
}

INSTANTIATE_TEST_SUITE_P(Kernels, TemporarySolverAllocation, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info) { return info.param ? "Avx2" : "Baseline"; });

INSTANTIATE_TEST_SUITE_P(
    SolversAndAlgorithms, LmAllocation,
    ::testing::Combine(::testing::Values(LinearSolverKind::kCholmod, LinearSolverKind::kEigen, LinearSolverKind::kAuto),
                       ::testing::Values(Algorithm::kLevenbergMarquardt, Algorithm::kGaussNewton)));

}  // namespace
}  // namespace dualgraph
