// SPDX-License-Identifier: MIT
// Shared pieces of the core tests, which depend on core only: the user-defined point types
// (user_types.h), the dense reference solver (dense_solver.h), generic linear-map types whose
// Jacobian blocks are not symmetric (so a transposed scatter into H cannot go unnoticed), graph
// builders with fixed seeds, and the dense JᵀWJ oracle.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdlib>
#include <initializer_list>
#include <iomanip>
#include <memory>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/robust_kernel.h"
#include "dualgraph/core/type_registry.h"
#include "test/core/dense_solver.h"
#include "test/core/user_types.h"

namespace dualgraph::testing {

/// The user types under the tags the test texts use.
inline Status registerUserTypes(TypeRegistry& registry) {
  DG_RETURN_IF_ERROR(registry.registerVertex<VertexPoint2>("VERTEX_P2"));
  DG_RETURN_IF_ERROR(registry.registerEdge<EdgePoint2Relative>("EDGE_P2_REL"));
  DG_RETURN_IF_ERROR(registry.registerEdge<EdgePoint2Range>("EDGE_P2_RANGE"));
  return registry.registerEdge<EdgePoint2Prior>("EDGE_P2_PRIOR");
}

inline VertexPoint2* addPoint(Graph& graph, int id, const Eigen::Vector2d& p, bool fixed = false) {
  auto v = std::make_unique<VertexPoint2>(id);
  v->setEstimate(p);
  v->setFixed(fixed);
  VertexPoint2* raw = v.get();
  const Status added = graph.addVertex(std::move(v));
  EXPECT_TRUE(added.ok()) << added.toString();
  return added.ok() ? raw : nullptr;
}

/// Adds an edge of type `E` on the vertices `ids` (slot order) with measurement `z`; nullptr (and a
/// test failure) when the graph refuses it.
template <typename E>
E* addEdge(Graph& graph, std::initializer_list<int> ids, const typename E::Measurement& z,
           const typename E::InformationMatrix& information = E::InformationMatrix::Identity()) {
  auto edge = std::make_unique<E>();
  size_t slot = 0;
  for (int id : ids) {
    const Status set = edge->setVertex(slot++, graph.vertex(id));
    EXPECT_TRUE(set.ok()) << set.toString();
  }
  edge->setMeasurement(z);
  edge->setInformation(information);
  auto added = graph.addEdge(std::move(edge));
  EXPECT_TRUE(added.ok()) << added.status().toString();
  return added.ok() ? static_cast<E*>(*added) : nullptr;
}

/// A random symmetric positive-definite N×N matrix (AAᵀ + 0.5 I, A with N(0, scale²) entries).
template <int N>
Eigen::Matrix<double, N, N> randomInformation(std::mt19937& rng, double scale = 1.0) {
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, N, N> a;
  for (int r = 0; r < N; ++r) {
    for (int c = 0; c < N; ++c) a(r, c) = scale * normal(rng);
  }
  Eigen::Matrix<double, N, N> information = a * a.transpose() + 0.5 * Eigen::Matrix<double, N, N>::Identity();
  return 0.5 * (information + information.transpose());
}

/// A point in R^D with additive increment; tag-free (registered only where a test needs it).
template <int D>
class VertexVector : public BaseVertex<D, Eigen::Matrix<double, D, 1>> {
  using Base = BaseVertex<D, Eigen::Matrix<double, D, 1>>;

 public:
  using Base::Base;
  Status read(TokenReader& in) override { return in.template readVector<D>(this->estimate_, "x"); }
  void write(std::ostream& out) const override {
    out << std::setprecision(17);
    for (int k = 0; k < D; ++k) out << (k ? " " : "") << this->estimate_[k];
  }

 protected:
  void oplusImpl(const typename Base::Tangent& delta) override { this->estimate_ += delta; }
};

/// e = Σ_k M_k x_k − z with a fixed E×D_k map M_k per slot; analytic Jacobians M_k. With random
/// maps the off-diagonal blocks M_aᵀ W M_b of H are not symmetric, so a block scattered without
/// the transpose it needs shows up in the comparison with a dense JᵀWJ.
template <int E, typename... Vs>
class EdgeLinear : public BaseEdge<E, Eigen::Matrix<double, E, 1>, Vs...> {
  using Base = BaseEdge<E, Eigen::Matrix<double, E, 1>, Vs...>;

 public:
  EdgeLinear() { setMaps(std::index_sequence_for<Vs...>{}, nullptr); }

  /// Random maps with standard-normal entries.
  void randomizeMaps(std::mt19937& rng) { setMaps(std::index_sequence_for<Vs...>{}, &rng); }

  void computeError() override {
    this->error_ = -this->measurement_;
    addTerms(std::index_sequence_for<Vs...>{});
  }
  Status read(TokenReader& in, const ParameterContainer&) override {
    return in.error("EdgeLinear is not readable");
  }
  void write(std::ostream&) const override {}

 protected:
  void linearizeOplus() override { copyMaps(std::index_sequence_for<Vs...>{}); }

 private:
  template <size_t... I>
  void setMaps(std::index_sequence<I...>, std::mt19937* rng) {
    (fillMap(std::get<I>(maps_), rng), ...);
  }
  template <typename M>
  static void fillMap(M& map, std::mt19937* rng) {
    if (rng == nullptr) {
      map.setZero();
      map.diagonal().setOnes();
      return;
    }
    std::normal_distribution<double> normal;
    for (int r = 0; r < map.rows(); ++r) {
      for (int c = 0; c < map.cols(); ++c) map(r, c) = normal(*rng);
    }
  }
  template <size_t... I>
  void addTerms(std::index_sequence<I...>) {
    ((this->error_ += std::get<I>(maps_) * this->template vertexAs<I>()->estimate()), ...);
  }
  template <size_t... I>
  void copyMaps(std::index_sequence<I...>) {
    ((this->template jacobianOplus<I>() = std::get<I>(maps_)), ...);
  }

  std::tuple<Eigen::Matrix<double, E, Vs::kDim>...> maps_;
};

/// A seeded random graph of `kRandomGraphPoints` points (spread ~3 m) with relative edges (random
/// correlated information), range edges, priors, edges in both id orders, vertices 4 and 17 fixed,
/// and `kernel` (may be null) on half of the edges. Some measurements match the state
/// closely and some are far off, so a robust kernel sees both of its regimes.
constexpr int kRandomGraphPoints = 30;
inline void buildRandomPointGraph(Graph& graph, unsigned seed,
                                  const std::shared_ptr<const RobustKernel>& kernel = nullptr) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<int> pick(0, kRandomGraphPoints - 1);
  for (int id = 0; id < kRandomGraphPoints; ++id) {
    addPoint(graph, id, {3.0 * normal(rng), 3.0 * normal(rng)}, id == 4 || id == 17);
  }
  const auto estimate = [&graph](int id) { return graph.vertexAs<VertexPoint2>(id)->estimate(); };
  for (int k = 0; k < 90; ++k) {
    const int i = pick(rng);
    const int j = pick(rng);
    if (i == j) continue;
    const double noise = k % 2 == 0 ? 0.01 : 2.0;  // near-consistent and far-off measurements
    EdgeBase* edge = nullptr;
    if (k % 3 == 0) {
      const double range = (estimate(j) - estimate(i)).norm() + noise * normal(rng);
      edge = addEdge<EdgePoint2Range>(graph, {i, j}, range, Eigen::Matrix<double, 1, 1>(0.5 + std::abs(normal(rng))));
    } else {
      const Eigen::Vector2d z = estimate(j) - estimate(i) + noise * Eigen::Vector2d(normal(rng), normal(rng));
      edge = addEdge<EdgePoint2Relative>(graph, {i, j}, z, randomInformation<2>(rng));
    }
    if (edge != nullptr && kernel != nullptr && (k / 2) % 2 == 0) edge->setRobustKernel(kernel);
  }
  for (int id : {0, 9, 23}) {
    addEdge<EdgePoint2Prior>(graph, {id}, estimate(id) + Eigen::Vector2d(normal(rng), normal(rng)),
                             randomInformation<2>(rng));
  }
}

/// H = Σ Jᵀ W J, b = −Σ Jᵀ W e with W = ρ'(s)Ω, s = eᵀΩe, built densely from each edge's raw
/// jacobianData/informationData/errorData (call `linearize()` on every edge first). The column
/// offsets are derived here, independently of SparseSystem: free vertices attached to an edge, in
/// increasing id order, packed.
struct DenseNormalEquations {
  Eigen::MatrixXd H;
  Eigen::VectorXd b;
  std::vector<int> offset_by_id;  ///< indexed by vertex id; −1 when not in the system
  int downweighted_edges = 0;     ///< edges with ρ'(s) < 1
  int transposed_blocks = 0;      ///< free slot pairs (a < b) whose vertex ids are in decreasing order
};

inline DenseNormalEquations denseNormalEquations(const Graph& graph) {
  DenseNormalEquations out;
  int max_id = -1;
  for (const auto& [id, vertex] : graph.vertices()) max_id = std::max(max_id, id);
  out.offset_by_id.assign(max_id + 1, -1);
  std::vector<bool> attached(max_id + 1, false);
  for (const auto& edge : graph.edges()) {
    for (const VertexBase* v : edge->vertices()) attached[v->id()] = true;
  }
  int n = 0;
  for (const auto& [id, vertex] : graph.vertices()) {
    if (attached[id] && !vertex->fixed()) {
      out.offset_by_id[id] = n;
      n += vertex->tangentDim();
    }
  }
  out.H = Eigen::MatrixXd::Zero(n, n);
  out.b = Eigen::VectorXd::Zero(n);
  for (const auto& edge : graph.edges()) {
    const int m = edge->errorDim();
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, n);
    std::vector<int> free_ids;
    for (size_t k = 0; k < edge->numVertices(); ++k) {
      const VertexBase* v = edge->vertex(k);
      const int offset = out.offset_by_id[v->id()];
      if (offset < 0) continue;
      J.block(0, offset, m, v->tangentDim()) =
          Eigen::Map<const Eigen::MatrixXd>(edge->jacobianData(k), m, v->tangentDim());
      free_ids.push_back(v->id());
    }
    for (size_t a = 0; a < free_ids.size(); ++a) {
      for (size_t c = a + 1; c < free_ids.size(); ++c) out.transposed_blocks += free_ids[a] > free_ids[c];
    }
    const Eigen::Map<const Eigen::MatrixXd> information(edge->informationData(), m, m);
    const Eigen::Map<const Eigen::VectorXd> e(edge->errorData(), m);
    const double s = e.dot(information * e);
    double weight = 1.0;
    if (edge->robustKernel() != nullptr) weight = edge->robustKernel()->robustify(s)[1];
    if (weight < 1.0) ++out.downweighted_edges;
    const Eigen::MatrixXd W = weight * information;
    out.H += J.transpose() * W * J;
    out.b -= J.transpose() * W * e;
  }
  return out;
}

/// max |a − b| relative to max(1, max |b|).
inline double relativeMaxDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  return (a - b).cwiseAbs().maxCoeff() / scale;
}

/// True when `text` contains `fragment`; on failure shows both.
inline ::testing::AssertionResult contains(const std::string& text, const std::string& fragment) {
  if (text.find(fragment) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << fragment << "'";
}

}  // namespace dualgraph::testing
