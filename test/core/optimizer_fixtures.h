// SPDX-License-Identifier: MIT
// Helpers of the optimiser tests: state snapshots, a dense least-squares oracle for linear point
// graphs written from the measurements, seeded problem builders, and a solver with scripted
// failures.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/core/optimizer.h"
#include "test/core/test_fixtures.h"

namespace dualgraph::testing {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

inline Eigen::Vector2d pointOf(const Graph& graph, int id) { return graph.vertexAs<VertexPoint2>(id)->estimate(); }

inline std::map<int, Eigen::Vector2d> snapshot(const Graph& graph) {
  std::map<int, Eigen::Vector2d> out;
  for (const auto& [id, v] : graph.vertices()) out[id] = pointOf(graph, id);
  return out;
}

/// No optimiser call may leave a pushed estimate behind.
inline void expectCleanStacks(const Graph& graph) {
  for (const auto& [id, v] : graph.vertices()) EXPECT_EQ(v->stackSize(), 0u) << "vertex " << id;
}

/// Edges with at least one free vertex (those in the linear system).
inline int activeEdgeCount(const Graph& graph) {
  int count = 0;
  for (const auto& edge : graph.edges()) {
    const auto& vs = edge->vertices();
    count += std::any_of(vs.begin(), vs.end(), [](const VertexBase* v) { return !v->fixed(); }) ? 1 : 0;
  }
  return count;
}

/// Minimiser of Σ eᵀΩe for a graph of points with relative and prior edges only (linear in the
/// points), from a dense solve of the normal equations written from the measurements (not from the
/// edges' Jacobians); fixed vertices keep their estimates.
inline std::map<int, Eigen::Vector2d> denseLeastSquares(const Graph& graph) {
  std::map<int, int> index;
  for (const auto& edge : graph.edges()) {
    for (const VertexBase* v : edge->vertices()) {
      if (!v->fixed() && index.count(v->id()) == 0) index.emplace(v->id(), 0);
    }
  }
  int n = 0;
  for (auto& [id, k] : index) k = n++;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(2 * n);
  for (const auto& edge : graph.edges()) {
    // r = Σ s_k x_k − z with s_k = ±1 per slot.
    std::vector<std::pair<const VertexBase*, double>> terms;
    Eigen::Vector2d z;
    Eigen::Matrix2d information;
    if (auto* rel = dynamic_cast<const EdgePoint2Relative*>(edge.get())) {
      terms = {{rel->vertex(0), -1.0}, {rel->vertex(1), 1.0}};
      z = rel->measurement();
      information = rel->information();
    } else if (auto* prior = dynamic_cast<const EdgePoint2Prior*>(edge.get())) {
      terms = {{prior->vertex(0), 1.0}};
      z = prior->measurement();
      information = prior->information();
    } else {
      ADD_FAILURE() << "denseLeastSquares handles relative and prior edges only";
      return {};
    }
    Eigen::Vector2d c = z;  // r = A_F x_F − c
    for (const auto& [v, sign] : terms) {
      if (v->fixed()) c -= sign * pointOf(graph, v->id());
    }
    for (const auto& [va, sa] : terms) {
      if (va->fixed()) continue;
      const int a = 2 * index.at(va->id());
      g.segment<2>(a) += sa * information * c;
      for (const auto& [vb, sb] : terms) {
        if (!vb->fixed()) H.block<2, 2>(a, 2 * index.at(vb->id())) += sa * sb * information;
      }
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::VectorXd x = ldlt.solve(g);
  std::map<int, Eigen::Vector2d> out = snapshot(graph);
  for (const auto& [id, k] : index) out[id] = x.segment<2>(2 * k);
  return out;
}

inline void expectAtSolution(const Graph& graph, const std::map<int, Eigen::Vector2d>& expected, double tolerance) {
  for (const auto& [id, p] : expected) {
    EXPECT_LT((pointOf(graph, id) - p).cwiseAbs().maxCoeff(), tolerance)
        << "vertex " << id << ": " << pointOf(graph, id).transpose() << " vs " << p.transpose();
  }
}

/// χ² of `graph` with its points moved to `points` (the graph is restored afterwards).
inline double chi2At(Graph& graph, const std::map<int, Eigen::Vector2d>& points) {
  const auto saved = snapshot(graph);
  for (const auto& [id, p] : points) graph.vertexAs<VertexPoint2>(id)->setEstimate(p);
  const double chi2 = graph.chi2();
  for (const auto& [id, p] : saved) graph.vertexAs<VertexPoint2>(id)->setEstimate(p);
  graph.chi2();  // stored errors back to the current estimate
  return chi2;
}

/// 8 points with random starts, vertex 0 fixed, a chain and loop closures of relative edges in
/// both id orders with correlated information, and two priors.
inline void buildLinearProblem(Graph& graph, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (int id = 0; id < 8; ++id) addPoint(graph, id, {3 * normal(rng), 3 * normal(rng)}, id == 0);
  for (int id = 0; id + 1 < 8; ++id) {
    const bool forward = id % 2 == 0;
    addEdge<EdgePoint2Relative>(graph, {forward ? id : id + 1, forward ? id + 1 : id},
                                {(forward ? 1.0 : -1.0) + 0.1 * normal(rng), 0.1 * normal(rng)},
                                testing::randomInformation<2>(rng));
  }
  for (auto [i, j] : {std::pair{7, 0}, std::pair{2, 6}, std::pair{5, 1}}) {
    addEdge<EdgePoint2Relative>(graph, {i, j}, {static_cast<double>(j - i) + 0.2 * normal(rng), 0.3 * normal(rng)},
                                testing::randomInformation<2>(rng, 2.0));
  }
  addEdge<EdgePoint2Prior>(graph, {3}, {3.2, 0.4}, testing::randomInformation<2>(rng));
  addEdge<EdgePoint2Prior>(graph, {6}, {5.7, -0.3}, testing::randomInformation<2>(rng));
}

inline OptimizerParams paramsFor(Algorithm algorithm) {
  OptimizerParams params;
  params.algorithm = algorithm;
  return params;
}

/// Four fixed anchors and three free points with exact ranges to the anchors and between points.
struct RangeProblem {
  std::map<int, Eigen::Vector2d> truth;
};
inline RangeProblem buildRangeProblem(Graph& graph, double start_noise, unsigned seed) {
  RangeProblem problem;
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  problem.truth = {{0, {0, 0}}, {1, {4, 0}}, {2, {4, 4}}, {3, {0, 4}}, {4, {1, 1.5}}, {5, {3, 1}}, {6, {2.5, 3.2}}};
  for (const auto& [id, p] : problem.truth) {
    const bool anchor = id < 4;
    const Eigen::Vector2d noise(normal(rng), normal(rng));
    addPoint(graph, id, anchor || start_noise == 0.0 ? p : Eigen::Vector2d(p + start_noise * noise), anchor);
  }
  for (int point : {4, 5, 6}) {
    for (int anchor : {0, 1, 2, 3}) {
      const bool flip = (point + anchor) % 2 == 0;
      const int i = flip ? point : anchor;
      const int j = flip ? anchor : point;
      addEdge<EdgePoint2Range>(graph, {i, j}, (problem.truth[j] - problem.truth[i]).norm());
    }
  }
  addEdge<EdgePoint2Range>(graph, {6, 4}, (problem.truth[4] - problem.truth[6]).norm());
  return problem;
}

/// Wraps the dense solver with scripted failures and counts calls.
class ScriptedSolver : public LinearSolver {
 public:
  struct Script {
    Status analyze_status;
    StatusCode solve_failure = StatusCode::kOk;  ///< every solve fails with this code
    int nan_solves = 0;                          ///< the first solves return NaN steps
  };
  struct Counts {
    int analyze = 0;
    int factorize = 0;
    int solve = 0;
  };
  ScriptedSolver(Script script, Counts* counts) : script_(std::move(script)), counts_(counts) {}
  Status analyze(const SparseMatrixView& m) override {
    ++counts_->analyze;
    if (!script_.analyze_status.ok()) return script_.analyze_status;
    return dense_.analyze(m);
  }
  Status factorize(const SparseMatrixView& m) override {
    ++counts_->factorize;
    return dense_.factorize(m);
  }
  Status solve(const double* b, double* x) override {
    ++counts_->solve;
    if (script_.solve_failure != StatusCode::kOk) return Status(script_.solve_failure, "scripted solve failure");
    DG_RETURN_IF_ERROR(dense_.solve(b, x));
    if (counts_->solve <= script_.nan_solves) x[0] = kNaN;
    return Status();
  }
  std::string name() const override { return "scripted"; }

 private:
  Script script_;
  Counts* counts_;
  DenseTestSolver dense_;
};

}  // namespace dualgraph::testing
