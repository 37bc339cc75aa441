// SPDX-License-Identifier: MIT
// SparseSystem: the assembled upper-triangular CSC H and the rhs against a dense Σ JᵀWJ, −Σ JᵀWe
// built independently from the edges' raw data; layout invariants; damping; excluded vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/core/sparse_system.h"
#include "test/core/test_fixtures.h"

namespace dualgraph {
namespace {

using testing::addEdge;
using testing::addPoint;
using testing::buildRandomPointGraph;
using testing::DenseNormalEquations;
using testing::denseFromUpper;
using testing::denseNormalEquations;
using testing::EdgeLinear;
using testing::EdgePoint2Prior;
using testing::EdgePoint2Relative;
using testing::relativeMaxDifference;
using testing::VertexPoint2;
using testing::VertexVector;

using V3 = VertexVector<3>;
using V6 = VertexVector<6>;

void linearizeAll(const Graph& graph) {
  for (const auto& edge : graph.edges()) edge->linearize();
}

/// Adds an EdgeLinear with random maps, measurement and information on `ids`.
template <typename E>
E* addLinear(Graph& graph, std::initializer_list<int> ids, std::mt19937& rng,
             const std::shared_ptr<const RobustKernel>& kernel) {
  std::normal_distribution<double> normal;
  typename E::Measurement z;
  for (int k = 0; k < z.size(); ++k) z[k] = normal(rng);
  E* edge = addEdge<E>(graph, ids, z, testing::randomInformation<E::kErrorDim>(rng));
  if (edge == nullptr) return nullptr;
  edge->randomizeMaps(rng);
  if (kernel != nullptr && normal(rng) > 0.0) edge->setRobustKernel(kernel);
  return edge;
}

/// 8 points (2-D), 8 vertices in R³ and 8 in R⁶ with shuffled ids; one R³ and one R⁶ vertex
/// fixed. Edges with random linear maps cover every assembly path: square 3×3 and 6×6 blocks
/// (the fixed-size kernels), unary ones, 2-D ones, non-square mixed-dimension ones in both slot
/// orders, a ternary edge, and a 3-D error on an R³ and a fixed R⁶ vertex.
void buildMixedDimensionGraph(Graph& graph, unsigned seed, const std::shared_ptr<const RobustKernel>& kernel) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<int> ids(24);
  std::iota(ids.begin(), ids.end(), 0);
  std::shuffle(ids.begin(), ids.end(), rng);
  std::vector<int> p2(ids.begin(), ids.begin() + 8);
  std::vector<int> v3(ids.begin() + 8, ids.begin() + 16);
  std::vector<int> v6(ids.begin() + 16, ids.end());
  for (int id : p2) addPoint(graph, id, {normal(rng), normal(rng)});
  for (int id : v3) {
    auto v = std::make_unique<V3>(id);
    V3::Estimate x;
    for (int k = 0; k < 3; ++k) x[k] = normal(rng);
    v->setEstimate(x);
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  for (int id : v6) {
    auto v = std::make_unique<V6>(id);
    V6::Estimate x;
    for (int k = 0; k < 6; ++k) x[k] = normal(rng);
    v->setEstimate(x);
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  graph.vertex(v3[0])->setFixed(true);
  graph.vertex(v6[0])->setFixed(true);

  auto pick = [&rng](const std::vector<int>& from) {
    return from[std::uniform_int_distribution<size_t>(0, from.size() - 1)(rng)];
  };
  auto pickPair = [&](const std::vector<int>& from) {
    const int a = pick(from);
    int b = pick(from);
    while (b == a) b = pick(from);
    return std::make_pair(a, b);
  };
  for (int k = 0; k < 12; ++k) {
    const auto [a, b] = pickPair(v3);
    addLinear<EdgeLinear<3, V3, V3>>(graph, {a, b}, rng, kernel);
  }
  for (int k = 0; k < 10; ++k) {
    const auto [a, b] = pickPair(v6);
    addLinear<EdgeLinear<6, V6, V6>>(graph, {a, b}, rng, kernel);
  }
  for (int k = 0; k < 4; ++k) addLinear<EdgeLinear<6, V6>>(graph, {pick(v6)}, rng, kernel);
  for (int k = 0; k < 3; ++k) addLinear<EdgeLinear<3, V3>>(graph, {pick(v3)}, rng, kernel);
  for (int k = 0; k < 8; ++k) {
    const auto [a, b] = pickPair(p2);
    addLinear<EdgeLinear<2, VertexPoint2, VertexPoint2>>(graph, {a, b}, rng, kernel);
  }
  for (int k = 0; k < 6; ++k) {
    addLinear<EdgeLinear<4, VertexPoint2, V3>>(graph, {pick(p2), pick(v3)}, rng, kernel);
    addLinear<EdgeLinear<4, V3, VertexPoint2>>(graph, {pick(v3), pick(p2)}, rng, kernel);
  }
  for (int k = 0; k < 5; ++k) {
    addLinear<EdgeLinear<5, V6, VertexPoint2, V3>>(graph, {pick(v6), pick(p2), pick(v3)}, rng, kernel);
  }
  for (int k = 1; k < 3; ++k) addLinear<EdgeLinear<3, V3, V6>>(graph, {v3[k], v6[0]}, rng, kernel);
  addLinear<EdgeLinear<3, V3, V6>>(graph, {v3[3], v6[1]}, rng, kernel);
}

/// Checks the CSC invariants of an upper-triangular SparseMatrixView and returns the message of
/// the first violation.
::testing::AssertionResult isSortedUpperTriangle(const SparseMatrixView& m) {
  if (m.col_ptr[0] != 0) return ::testing::AssertionFailure() << "col_ptr[0] = " << m.col_ptr[0];
  for (int c = 0; c < m.n; ++c) {
    const int begin = m.col_ptr[c];
    const int end = m.col_ptr[c + 1];
    if (end <= begin) return ::testing::AssertionFailure() << "column " << c << " is empty";
    for (int k = begin; k < end; ++k) {
      if (m.row_index[k] < 0 || m.row_index[k] > c) {
        return ::testing::AssertionFailure() << "column " << c << " holds row " << m.row_index[k]
                                             << " (lower triangle or out of range)";
      }
      if (k > begin && m.row_index[k - 1] >= m.row_index[k]) {
        return ::testing::AssertionFailure() << "column " << c << ": rows " << m.row_index[k - 1] << ", "
                                             << m.row_index[k] << " not strictly increasing";
      }
    }
    if (m.row_index[end - 1] != c) {
      return ::testing::AssertionFailure() << "column " << c << " does not end at its diagonal";
    }
  }
  return ::testing::AssertionSuccess();
}

/// Stored entries the block pattern needs: each free vertex's upper-triangular diagonal block and
/// one dense block per pair of free vertices sharing an edge.
long expectedNonzeros(const Graph& graph) {
  std::set<std::pair<const VertexBase*, const VertexBase*>> pairs;
  std::set<const VertexBase*> active;
  for (const auto& edge : graph.edges()) {
    std::vector<const VertexBase*> free;
    for (const VertexBase* v : edge->vertices()) {
      if (!v->fixed()) free.push_back(v);
    }
    active.insert(free.begin(), free.end());
    for (size_t a = 0; a < free.size(); ++a) {
      for (size_t b = a + 1; b < free.size(); ++b) pairs.emplace(std::min(free[a], free[b]), std::max(free[a], free[b]));
    }
  }
  long nnz = 0;
  for (const VertexBase* v : active) nnz += v->tangentDim() * (v->tangentDim() + 1) / 2;
  for (const auto& [a, b] : pairs) nnz += static_cast<long>(a->tangentDim()) * b->tangentDim();
  return nnz;
}

/// Smallest max|B − Bᵀ| over the per-edge off-diagonal blocks B = J_aᵀ Ω J_b joining two free
/// vertices of equal dimension (+∞ when there is none). Edges must be linearised.
double minOffDiagonalAsymmetry(const Graph& graph) {
  double smallest = std::numeric_limits<double>::infinity();
  for (const auto& edge : graph.edges()) {
    const int m = edge->errorDim();
    const Eigen::Map<const Eigen::MatrixXd> information(edge->informationData(), m, m);
    for (size_t a = 0; a < edge->numVertices(); ++a) {
      for (size_t b = a + 1; b < edge->numVertices(); ++b) {
        const VertexBase* va = edge->vertex(a);
        const VertexBase* vb = edge->vertex(b);
        if (va->fixed() || vb->fixed() || va->tangentDim() != vb->tangentDim()) continue;
        const int d = va->tangentDim();
        const Eigen::MatrixXd block = Eigen::Map<const Eigen::MatrixXd>(edge->jacobianData(a), m, d).transpose() *
                                      information * Eigen::Map<const Eigen::MatrixXd>(edge->jacobianData(b), m, d);
        smallest = std::min(smallest, (block - block.transpose()).cwiseAbs().maxCoeff());
      }
    }
  }
  return smallest;
}

/// Builds, linearises and assembles `graph`, and compares H and b with the dense oracle.
DenseNormalEquations expectMatchesDense(const Graph& graph, SparseSystem& system) {
  const Status built = system.build(graph);
  EXPECT_TRUE(built.ok()) << built.toString();
  linearizeAll(graph);
  system.assemble();
  DenseNormalEquations dense = denseNormalEquations(graph);
  EXPECT_EQ(system.dim(), dense.H.rows());
  if (system.dim() != dense.H.rows()) return dense;
  const Eigen::MatrixXd H = denseFromUpper(system.matrix());
  EXPECT_LT(relativeMaxDifference(H, dense.H), 1e-13)
      << "worst entry difference " << (H - dense.H).cwiseAbs().maxCoeff();
  EXPECT_LT(relativeMaxDifference(system.rhs(), dense.b), 1e-13)
      << "worst rhs difference " << (system.rhs() - dense.b).cwiseAbs().maxCoeff();
  for (const auto& [id, vertex] : graph.vertices()) {
    EXPECT_EQ(system.offsetOf(vertex.get()), dense.offset_by_id[id]) << "vertex " << id;
  }
  EXPECT_TRUE(isSortedUpperTriangle(system.matrix()));
  EXPECT_EQ(system.matrix().nnz(), expectedNonzeros(graph));
  return dense;
}

class SparseSystemWithKernel : public ::testing::TestWithParam<const char*> {
 protected:
  std::shared_ptr<const RobustKernel> kernel() const {
    const std::string spec = GetParam();
    if (spec == "none") return nullptr;
    auto made = makeRobustKernel(spec);
    EXPECT_TRUE(made.ok());
    return made.ok() ? *made : nullptr;
  }
};

TEST_P(SparseSystemWithKernel, HessianMatchesDenseJtWJ) {
  for (unsigned seed : {3u, 4u, 5u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Graph graph;
    buildRandomPointGraph(graph, seed, kernel());
    addPoint(graph, 99, {1, 1});  // no edges
    SparseSystem system;
    const DenseNormalEquations dense = expectMatchesDense(graph, system);
    EXPECT_GT(dense.transposed_blocks, 10) << "edges in both id orders";
    if (kernel() != nullptr) {
      EXPECT_GT(dense.downweighted_edges, 3) << "the kernel must actually reweight some edges";
    }
  }
}

TEST_P(SparseSystemWithKernel, FixedSizeAndMixedDimensionBlocksMatchDenseJtWJ) {
  for (unsigned seed : {21u, 22u, 23u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Graph graph;
    buildMixedDimensionGraph(graph, seed, kernel());
    SparseSystem system;
    const DenseNormalEquations dense = expectMatchesDense(graph, system);
    EXPECT_GT(dense.transposed_blocks, 5);
    EXPECT_GT(minOffDiagonalAsymmetry(graph), 1e-3)
        << "every square off-diagonal block is non-symmetric, so a missed transpose would show";
  }
}

INSTANTIATE_TEST_SUITE_P(Kernels, SparseSystemWithKernel,
                         ::testing::Values("none", "huber:0.5", "cauchy:1", "tukey:3", "dcs:1"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (c == ':' || c == '.') c = '_';
                           }
                           return name;
                         });

TEST(SparseSystem, IsolatedAndFixedVerticesAreExcluded) {
  Graph graph;
  buildRandomPointGraph(graph, 3);
  addPoint(graph, 99, {1, 1});                   // no edges
  addPoint(graph, 100, {1, 1}, /*fixed=*/true);  // fixed and attached below
  addPoint(graph, 101, {2, 1}, /*fixed=*/true);
  const EdgeBase* all_fixed = addEdge<EdgePoint2Relative>(graph, {100, 101}, {1, 0});  // not in the system
  addEdge<EdgePoint2Relative>(graph, {100, 5}, {1, 0});
  SparseSystem system;
  ASSERT_TRUE(system.build(graph).ok());
  EXPECT_EQ(system.dim(), 2 * (testing::kRandomGraphPoints - 2)) << "30 points, 4 and 17 fixed";
  for (int id : {4, 17, 99, 100, 101}) EXPECT_EQ(system.offsetOf(graph.vertex(id)), -1) << id;
  EXPECT_EQ(system.offsetOf(nullptr), -1);
  // Active vertices in increasing id order, packed.
  const auto& active = system.activeVertices();
  ASSERT_EQ(active.size(), static_cast<size_t>(testing::kRandomGraphPoints - 2));
  for (size_t k = 0; k < active.size(); ++k) {
    EXPECT_EQ(system.offsetOf(active[k]), static_cast<int>(2 * k));
    if (k > 0) {
      EXPECT_LT(active[k - 1]->id(), active[k]->id());
    }
    EXPECT_FALSE(active[k]->fixed());
  }
  // Active edges: every edge touching a free vertex, in graph order.
  std::vector<EdgeBase*> expected;
  for (const auto& edge : graph.edges()) {
    const auto& vs = edge->vertices();
    if (std::any_of(vs.begin(), vs.end(), [](const VertexBase* v) { return !v->fixed(); })) {
      expected.push_back(edge.get());
    }
  }
  EXPECT_EQ(system.activeEdges(), expected);
  const auto& active_edges = system.activeEdges();
  EXPECT_EQ(std::find(active_edges.begin(), active_edges.end(), all_fixed), active_edges.end());
}

TEST(SparseSystem, DampingAddsLambdaOnlyToTheDiagonalAndIsReversible) {
  Graph graph;
  buildRandomPointGraph(graph, 6, *makeRobustKernel("huber:1"));
  SparseSystem system;
  expectMatchesDense(graph, system);
  const Eigen::MatrixXd undamped = denseFromUpper(system.matrix());
  const double max_diagonal = system.maxDiagonal();
  EXPECT_EQ(max_diagonal, undamped.diagonal().maxCoeff());
  const Eigen::VectorXd rhs = system.rhs();
  for (double lambda : {2.5, 1e-3, 1e6}) {
    system.setDamping(lambda);
    const Eigen::MatrixXd damped = denseFromUpper(system.matrix());
    Eigen::MatrixXd off = damped - undamped;
    off.diagonal().setZero();
    EXPECT_EQ(off.cwiseAbs().maxCoeff(), 0.0) << "off-diagonal entries untouched";
    EXPECT_LT(((damped - undamped).diagonal().array() - lambda).abs().maxCoeff(), 1e-9 * std::max(1.0, lambda));
    EXPECT_EQ(system.maxDiagonal(), max_diagonal) << "the undamped diagonal is kept aside";
    EXPECT_EQ(system.rhs(), rhs) << "damping does not touch b";
  }
  system.setDamping(0.0);
  EXPECT_EQ(denseFromUpper(system.matrix()), undamped) << "damping does not accumulate";
}

TEST(SparseSystem, ScaledDampingAddsLambdaTimesTheClampedDiagonalAndReportsItsEnergy) {
  Graph graph;
  buildRandomPointGraph(graph, 6, *makeRobustKernel("huber:1"));
  SparseSystem system;
  expectMatchesDense(graph, system);
  const Eigen::MatrixXd undamped = denseFromUpper(system.matrix());
  const Eigen::VectorXd d = undamped.diagonal();
  const double lo = d.minCoeff() * 2.0, hi = d.maxCoeff() / 2.0;  // both clamps bite
  ASSERT_LT(lo, hi);
  const Eigen::VectorXd delta = Eigen::VectorXd::LinSpaced(system.dim(), -1.0, 2.0);
  for (double lambda : {0.5, 1e-4, 1e3}) {
    system.setScaledDamping(lambda, lo, hi);
    const Eigen::MatrixXd damped = denseFromUpper(system.matrix());
    Eigen::MatrixXd off = damped - undamped;
    off.diagonal().setZero();
    EXPECT_EQ(off.cwiseAbs().maxCoeff(), 0.0) << "off-diagonal entries untouched";
    const Eigen::VectorXd expected = lambda * d.cwiseMax(lo).cwiseMin(hi);
    // (d + λc) − d loses the bits of d: compare to d's magnitude.
    EXPECT_LT(((damped - undamped).diagonal() - expected).cwiseAbs().maxCoeff(),
              1e-14 * (d.maxCoeff() + expected.maxCoeff()));
    EXPECT_NEAR(system.dampingEnergy(delta.data()), delta.dot(expected.cwiseProduct(delta)),
                1e-12 * expected.maxCoeff() * delta.squaredNorm());
  }
  system.setDamping(0.25);
  EXPECT_NEAR(system.dampingEnergy(delta.data()), 0.25 * delta.squaredNorm(), 1e-12 * delta.squaredNorm());
  system.setScaledDamping(0.0, lo, hi);
  EXPECT_EQ(denseFromUpper(system.matrix()), undamped) << "damping does not accumulate";
  EXPECT_EQ(system.dampingEnergy(delta.data()), 0.0);
}

TEST(SparseSystem, ReassemblingAfterAMoveRefillsInsteadOfAccumulating) {
  Graph graph;
  buildRandomPointGraph(graph, 8, *makeRobustKernel("cauchy:1"));
  SparseSystem system;
  expectMatchesDense(graph, system);
  std::mt19937 rng(8);
  std::normal_distribution<double> normal(0.0, 0.3);
  for (const auto& [id, vertex] : graph.vertices()) {
    const double delta[] = {normal(rng), normal(rng)};
    vertex->plus(delta);
  }
  linearizeAll(graph);
  system.assemble();
  const DenseNormalEquations moved = denseNormalEquations(graph);
  EXPECT_LT(relativeMaxDifference(denseFromUpper(system.matrix()), moved.H), 1e-13);
  EXPECT_LT(relativeMaxDifference(system.rhs(), moved.b), 1e-13);
  system.assemble();  // same state twice: same values
  EXPECT_LT(relativeMaxDifference(denseFromUpper(system.matrix()), moved.H), 1e-13);
}

TEST(SparseSystem, RebuildingForAChangedGraphStartsFromScratch) {
  Graph graph;
  buildRandomPointGraph(graph, 9);
  SparseSystem system;
  expectMatchesDense(graph, system);
  addPoint(graph, 40, {0, 0});
  addEdge<EdgePoint2Relative>(graph, {40, 2}, {1, 1});
  ASSERT_TRUE(graph.setFixed(0, true).ok());
  ASSERT_TRUE(graph.setFixed(4, false).ok());
  expectMatchesDense(graph, system);
}

TEST(SparseSystem, ApplyUpdateMovesEachActiveVertexByItsSegment) {
  Graph graph;
  buildMixedDimensionGraph(graph, 31, nullptr);
  addPoint(graph, 50, {7, 7});  // isolated
  SparseSystem system;
  ASSERT_TRUE(system.build(graph).ok());
  std::map<int, Eigen::VectorXd> before;
  auto state = [](const VertexBase* v) -> Eigen::VectorXd {
    if (auto* p = dynamic_cast<const VertexPoint2*>(v)) return p->estimate();
    if (auto* p = dynamic_cast<const V3*>(v)) return p->estimate();
    return dynamic_cast<const V6*>(v)->estimate();
  };
  for (const auto& [id, v] : graph.vertices()) before[id] = state(v.get());
  Eigen::VectorXd delta(system.dim());
  for (int k = 0; k < delta.size(); ++k) delta[k] = 0.25 * k - 3.0;
  system.applyUpdate(delta.data());
  for (const auto& [id, v] : graph.vertices()) {
    const int offset = system.offsetOf(v.get());
    const Eigen::VectorXd moved = state(v.get()) - before[id];
    if (offset < 0) {
      EXPECT_EQ(moved.cwiseAbs().maxCoeff(), 0.0) << "vertex " << id << " is not in the system";
    } else {
      EXPECT_LT((moved - delta.segment(offset, v->tangentDim())).cwiseAbs().maxCoeff(), 1e-12) << "vertex " << id;
    }
  }
}

TEST(SparseSystem, GraphWithoutFreeVerticesHasDimensionZero) {
  Graph graph;
  addPoint(graph, 0, {0, 0}, true);
  addPoint(graph, 1, {1, 0}, true);
  addEdge<EdgePoint2Relative>(graph, {0, 1}, {1, 0});
  addPoint(graph, 2, {5, 0});  // free but isolated
  SparseSystem system;
  ASSERT_TRUE(system.build(graph).ok());
  EXPECT_EQ(system.dim(), 0);
  EXPECT_EQ(system.matrix().nnz(), 0);
  EXPECT_TRUE(system.activeVertices().empty());
  EXPECT_TRUE(system.activeEdges().empty());
  system.assemble();
  system.setDamping(1.0);
  EXPECT_EQ(system.rhs().size(), 0);
  EXPECT_EQ(system.maxDiagonal(), 0.0);

  Graph empty;
  ASSERT_TRUE(system.build(empty).ok());
  EXPECT_EQ(system.dim(), 0);
}

TEST(SparseSystem, UnaryEdgeAloneGivesADiagonalBlock) {
  Graph graph;
  addPoint(graph, 3, {2, -1});
  Eigen::Matrix2d information;
  information << 4, 1, 1, 2;
  addEdge<EdgePoint2Prior>(graph, {3}, {0, 0}, information);
  SparseSystem system;
  expectMatchesDense(graph, system);
  EXPECT_EQ(system.matrix().nnz(), 3);
  EXPECT_EQ(denseFromUpper(system.matrix()), Eigen::MatrixXd(information));
  EXPECT_LT((system.rhs() - (-(information * Eigen::Vector2d(2, -1)))).cwiseAbs().maxCoeff(), 1e-15);
}

}  // namespace
}  // namespace dualgraph
