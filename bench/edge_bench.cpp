// SPDX-License-Identifier: MIT
// Linearisation cost per edge type: the analytic Jacobians each type ships against the central-difference
// fallback every edge inherits (EdgeBase::numericJacobian, what a new type gets before it writes its own),
// on 1024 edges with random, seeded states (error + Jacobians of every edge; items = edges).
#include <benchmark/benchmark.h>

#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/types/edge_point_xyz_prior.h"
#include "dualgraph/types/edge_se2.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/edge_se3_prior.h"
#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se2.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

constexpr int kEdges = 1024;

/// A graph holding kEdges edges of one type over fresh vertices.
struct EdgeSet {
  Graph graph;
  std::vector<EdgeBase*> edges;
};

class Sampler {
 public:
  explicit Sampler(unsigned seed) : rng_(seed) {}
  double normal(double sigma) { return sigma * normal_(rng_); }
  Eigen::Vector3d vector3(double sigma) { return Eigen::Vector3d(normal(sigma), normal(sigma), normal(sigma)); }
  /// A pose with translation ~ N(0, σ_t²) per axis and rotation vector ~ N(0, σ_r²) per axis.
  Eigen::Isometry3d pose(double sigma_t, double sigma_r) {
    Vector6d xi;
    xi << vector3(sigma_t), vector3(sigma_r);
    return se3Exp(xi);
  }

 private:
  std::mt19937 rng_;
  std::normal_distribution<double> normal_;
};

template <typename V>
V* addVertex(EdgeSet& set, const typename V::Estimate& estimate) {
  const int id = static_cast<int>(set.graph.numVertices());
  auto vertex = std::make_unique<V>(id);
  vertex->setEstimate(estimate);
  V* raw = vertex.get();
  (void)set.graph.addVertex(std::move(vertex));
  return raw;
}

void addEdge(EdgeSet& set, std::unique_ptr<EdgeBase> edge, std::vector<VertexBase*> vertices) {
  for (size_t i = 0; i < vertices.size(); ++i) (void)edge->setVertex(i, vertices[i]);
  Result<EdgeBase*> added = set.graph.addEdge(std::move(edge));
  if (added.ok()) set.edges.push_back(*added);
}

// One builder per type: states spread over a 20 m cube and all rotations, measurements near the truth.
std::unique_ptr<EdgeSet> edgeSE3Set() {
  auto set = std::make_unique<EdgeSet>();
  Sampler s(1);
  for (int k = 0; k < kEdges; ++k) {
    VertexSE3* a = addVertex<VertexSE3>(*set, s.pose(10.0, 2.0));
    VertexSE3* b = addVertex<VertexSE3>(*set, s.pose(10.0, 2.0));
    auto edge = std::make_unique<EdgeSE3>();
    edge->setMeasurement(a->estimate().inverse() * b->estimate() * s.pose(0.05, 0.02));
    addEdge(*set, std::move(edge), {a, b});
  }
  return set;
}

std::unique_ptr<EdgeSet> edgeSE3PriorSet() {
  auto set = std::make_unique<EdgeSet>();
  Sampler s(2);
  for (int k = 0; k < kEdges; ++k) {
    VertexSE3* a = addVertex<VertexSE3>(*set, s.pose(10.0, 2.0));
    auto edge = std::make_unique<EdgeSE3Prior>();
    const Eigen::Isometry3d body_T_sensor = s.pose(0.2, 0.5);
    edge->setOffset(0, body_T_sensor);
    edge->setMeasurement(a->estimate() * body_T_sensor * s.pose(0.05, 0.02));
    addEdge(*set, std::move(edge), {a});
  }
  return set;
}

std::unique_ptr<EdgeSet> edgeSE3PointXYZSet() {
  auto set = std::make_unique<EdgeSet>();
  Sampler s(3);
  for (int k = 0; k < kEdges; ++k) {
    VertexSE3* a = addVertex<VertexSE3>(*set, s.pose(10.0, 2.0));
    VertexPointXYZ* p = addVertex<VertexPointXYZ>(*set, s.vector3(10.0));
    auto edge = std::make_unique<EdgeSE3PointXYZ>();
    const Eigen::Isometry3d body_T_sensor = s.pose(0.2, 0.5);
    edge->setOffset(0, body_T_sensor);
    edge->setMeasurement((a->estimate() * body_T_sensor).inverse() * p->estimate() + s.vector3(0.05));
    addEdge(*set, std::move(edge), {a, p});
  }
  return set;
}

std::unique_ptr<EdgeSet> edgePointXYZPriorSet() {
  auto set = std::make_unique<EdgeSet>();
  Sampler s(4);
  for (int k = 0; k < kEdges; ++k) {
    VertexPointXYZ* p = addVertex<VertexPointXYZ>(*set, s.vector3(10.0));
    auto edge = std::make_unique<EdgePointXYZPrior>();
    edge->setMeasurement(p->estimate() + s.vector3(0.05));
    addEdge(*set, std::move(edge), {p});
  }
  return set;
}

std::unique_ptr<EdgeSet> edgeSE2Set() {
  auto set = std::make_unique<EdgeSet>();
  Sampler s(5);
  for (int k = 0; k < kEdges; ++k) {
    VertexSE2* a = addVertex<VertexSE2>(*set, SE2(s.normal(10.0), s.normal(10.0), s.normal(2.0)));
    VertexSE2* b = addVertex<VertexSE2>(*set, SE2(s.normal(10.0), s.normal(10.0), s.normal(2.0)));
    auto edge = std::make_unique<EdgeSE2>();
    edge->setMeasurement(a->estimate().inverse() * b->estimate() * SE2(s.normal(0.05), s.normal(0.05), s.normal(0.02)));
    addEdge(*set, std::move(edge), {a, b});
  }
  return set;
}

using Builder = std::function<std::unique_ptr<EdgeSet>()>;

/// Error and analytic Jacobians of every edge (EdgeBase::linearize).
void linearizeAnalytic(benchmark::State& state, const Builder& build) {
  const std::unique_ptr<EdgeSet> set = build();
  if (set->edges.size() != kEdges) return state.SkipWithError("could not build the edges");
  for (auto _ : state) {
    for (EdgeBase* edge : set->edges) {
      edge->linearize();
      benchmark::DoNotOptimize(edge->jacobianData(0));
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kEdges);
}

/// Error and central-difference Jacobians of every edge through the vertices' own plus (the fallback).
void linearizeNumeric(benchmark::State& state, const Builder& build) {
  const std::unique_ptr<EdgeSet> set = build();
  if (set->edges.size() != kEdges) return state.SkipWithError("could not build the edges");
  std::vector<double> jacobian(6 * 6);
  for (auto _ : state) {
    for (EdgeBase* edge : set->edges) {
      edge->computeError();
      for (size_t i = 0; i < edge->numVertices(); ++i) {
        edge->numericJacobian(i, jacobian.data());
        benchmark::DoNotOptimize(jacobian.data());
      }
    }
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kEdges);
}

#define DG_EDGE_BENCH(Type, builder)                                                                      \
  void BM_##Type##_LinearizeAnalytic(benchmark::State& state) { linearizeAnalytic(state, builder); }    \
  void BM_##Type##_LinearizeNumeric(benchmark::State& state) { linearizeNumeric(state, builder); }      \
  BENCHMARK(BM_##Type##_LinearizeAnalytic)->Unit(benchmark::kMicrosecond);                               \
  BENCHMARK(BM_##Type##_LinearizeNumeric)->Unit(benchmark::kMicrosecond)

DG_EDGE_BENCH(EdgeSE3, edgeSE3Set);
DG_EDGE_BENCH(EdgeSE3Prior, edgeSE3PriorSet);
DG_EDGE_BENCH(EdgeSE3PointXYZ, edgeSE3PointXYZSet);
DG_EDGE_BENCH(EdgePointXYZPrior, edgePointXYZPriorSet);
DG_EDGE_BENCH(EdgeSE2, edgeSE2Set);

}  // namespace
}  // namespace dualgraph
