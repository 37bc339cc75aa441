// SPDX-License-Identifier: MIT
// MarginalCovariance::blocks (the selected inverse of CHOLMOD's factor, supernodal and simplicial) against the
// per-vertex solve path (block(id)) and a dense inverse, on SE(2), SE(3), SE(3) + points and a user type.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "dualgraph/solvers/cholmod_solver.h"
#include "dualgraph/solvers/eigen_solver.h"
#include "dualgraph/solvers/marginal_covariance.h"
#include "test/solvers/marginal_graphs.h"

namespace dualgraph {
namespace {

using testing::allVertexIds;

enum class Factor { kSupernodal, kSimplicial, kEigen };

std::string factorName(Factor factor) {
  return factor == Factor::kSupernodal ? "supernodal" : factor == Factor::kSimplicial ? "simplicial" : "eigen";
}

void PrintTo(Factor factor, std::ostream* os) { *os << factorName(factor); }

std::unique_ptr<LinearSolver> makeSolver(Factor factor) {
  if (factor == Factor::kEigen) return std::make_unique<EigenSolver>();
  CholmodOptions options;
  options.factorization =
      factor == Factor::kSupernodal ? CholmodFactorization::kSupernodal : CholmodFactorization::kSimplicial;
  return std::make_unique<CholmodSolver>(options);
}

/// max |a − b| / max |b|
double relativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

/// blocks(every id) against block(id) for every vertex (to 1e-9 relative), exactly zero for fixed vertices,
/// and, for systems up to 1500 rows, against the dense inverse of the system's H.
void expectBlocksEqualPerVertexSolves(Graph& graph, Factor factor) {
  SCOPED_TRACE(factorName(factor));
  Optimizer optimizer(graph, makeSolver(factor));
  MarginalCovariance marginals;
  const Status computed = marginals.compute(optimizer, graph);
  ASSERT_TRUE(computed.ok()) << computed.toString();
  if (factor != Factor::kEigen) {  // the forced kind is the factor's kind
    EXPECT_EQ(optimizer.linearSolver().name(), "cholmod-" + factorName(factor));
  }
  const std::vector<int> ids = allVertexIds(graph);
  const Result<std::vector<Eigen::MatrixXd>> all = marginals.blocks(ids);
  ASSERT_TRUE(all.ok()) << all.status().toString();
  ASSERT_EQ(all->size(), ids.size());
  Eigen::MatrixXd dense_inverse;
  const SparseSystem& system = optimizer.system();
  if (system.dim() <= 1500) {
    const SparseMatrixView h = system.matrix();
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(h.n, h.n);
    for (int j = 0; j < h.n; ++j) {
      for (int p = h.col_ptr[j]; p < h.col_ptr[j + 1]; ++p) dense(h.row_index[p], j) = dense(j, h.row_index[p]) = h.values[p];
    }
    dense_inverse = dense.inverse();
  }
  double worst = 0.0;
  for (size_t k = 0; k < ids.size(); ++k) {
    const VertexBase* vertex = graph.vertex(ids[k]);
    const Eigen::MatrixXd& sigma = (*all)[k];
    ASSERT_EQ(sigma.rows(), vertex->tangentDim());
    ASSERT_EQ(sigma.cols(), vertex->tangentDim());
    if (vertex->fixed()) {
      EXPECT_TRUE(sigma.isZero(0.0)) << "fixed vertex " << ids[k];
      continue;
    }
    const Result<Eigen::MatrixXd> solved = marginals.block(ids[k]);
    ASSERT_TRUE(solved.ok()) << solved.status().toString();
    const double difference = relativeDifference(sigma, *solved);
    worst = std::max(worst, difference);
    EXPECT_LT(difference, 1e-9) << "vertex " << ids[k] << "\n" << sigma << "\nsolved\n" << *solved;
    EXPECT_TRUE(sigma.isApprox(sigma.transpose(), 0.0)) << "vertex " << ids[k] << " not symmetric";
    if (dense_inverse.size() > 0) {
      const int offset = system.offsetOf(vertex);
      const Eigen::MatrixXd expected = dense_inverse.block(offset, offset, vertex->tangentDim(), vertex->tangentDim());
      EXPECT_LT(relativeDifference(sigma, expected), 1e-8) << "vertex " << ids[k];
    }
  }
  ::testing::Test::RecordProperty("worst_relative_difference_" + factorName(factor), std::to_string(worst));
}

class SelectedInverse : public ::testing::TestWithParam<Factor> {
 protected:
  void SetUp() override { DG_SKIP_WITHOUT_SHARED("data/posegraph/smallGrid3D.g2o"); }
};

TEST_P(SelectedInverse, Se2PoseGraphIntelEqualsPerVertexSolves) {
  Graph graph;
  ASSERT_TRUE(testing::loadSharedPoseGraph("intel.g2o", graph, true).ok());
  expectBlocksEqualPerVertexSolves(graph, GetParam());
}

TEST_P(SelectedInverse, Se3PoseGraphSmallGrid3DEqualsPerVertexSolves) {
  Graph graph;
  ASSERT_TRUE(testing::loadSharedPoseGraph("smallGrid3D.g2o", graph, true).ok());
  expectBlocksEqualPerVertexSolves(graph, GetParam());
}

TEST_P(SelectedInverse, Se3PosesWithPointsAndAFixedVertexInTheMiddleEqualPerVertexSolves) {
  Graph graph;
  ASSERT_TRUE(testing::loadSharedPoseGraph("smallGrid3D.g2o", graph, false).ok());
  ASSERT_TRUE(graph.setFixed(graph.vertices().begin()->first + 40, true).ok());
  testing::addPointsSeenFromPoses(graph, 10000, 60, 7);
  expectBlocksEqualPerVertexSolves(graph, GetParam());
}

TEST_P(SelectedInverse, UserTypePoint2NetworkEqualsPerVertexSolves) {
  Graph graph;
  testing::addPoint2Network(graph, 0, 300, /*with_prior=*/true, 11);
  expectBlocksEqualPerVertexSolves(graph, GetParam());
}

TEST_P(SelectedInverse, MixedDimensionsPosesPointsAndUserTypeEqualPerVertexSolves) {
  Graph graph;  // 6-, 3- and 2-dimensional vertices in one system, the user network its own component
  ASSERT_TRUE(testing::loadSharedPoseGraph("smallGrid3D.g2o", graph, true).ok());
  testing::addPointsSeenFromPoses(graph, 10000, 20, 3);
  testing::addPoint2Network(graph, 20000, 40, /*with_prior=*/true, 5);
  expectBlocksEqualPerVertexSolves(graph, GetParam());
}

INSTANTIATE_TEST_SUITE_P(Factors, SelectedInverse,
                         ::testing::Values(Factor::kSupernodal, Factor::kSimplicial, Factor::kEigen),
                         [](const auto& info) { return factorName(info.param); });

TEST(SelectedInverse, IdsInAnyOrderRepeatedFixedAndErrors) {
  DG_SKIP_WITHOUT_SHARED("data/posegraph/smallGrid3D.g2o");
  Graph graph;
  ASSERT_TRUE(testing::loadSharedPoseGraph("smallGrid3D.g2o", graph, true).ok());
  const int first = graph.vertices().begin()->first;
  Optimizer optimizer(graph, makeSolver(Factor::kSupernodal));
  MarginalCovariance marginals;
  EXPECT_EQ(marginals.blocks({first}).status().code(), StatusCode::kFailedPrecondition) << "before compute";
  ASSERT_TRUE(marginals.compute(optimizer, graph).ok());
  int fixed_id = -1;
  for (const auto& [id, vertex] : graph.vertices()) fixed_id = vertex->fixed() ? id : fixed_id;
  const std::vector<int> ids = {first + 7, fixed_id, first + 3, first + 7};
  const Result<std::vector<Eigen::MatrixXd>> sigma = marginals.blocks(ids);
  ASSERT_TRUE(sigma.ok()) << sigma.status().toString();
  EXPECT_TRUE((*sigma)[1].isZero(0.0));
  EXPECT_EQ((*sigma)[0], (*sigma)[3]);
  EXPECT_LT(relativeDifference((*sigma)[2], marginals.block(first + 3).value()), 1e-9);
  EXPECT_EQ(marginals.blocks({first, 999999}).status().code(), StatusCode::kNotFound);
  EXPECT_TRUE(marginals.blocks({}).value().empty());
  ASSERT_TRUE(graph.setFixed(first + 3, true).ok());  // structure changed since compute
  EXPECT_EQ(marginals.blocks({first}).status().code(), StatusCode::kFailedPrecondition);
}

TEST(SelectedInverse, ARefactorisationIsReadNotAStaleInverse) {
  Graph graph;
  testing::addPoint2Network(graph, 0, 50, /*with_prior=*/true, 13);
  Optimizer optimizer(graph, makeSolver(Factor::kSupernodal));
  MarginalCovariance marginals;
  ASSERT_TRUE(marginals.compute(optimizer, graph).ok());
  const Eigen::MatrixXd before = marginals.blocks({30}).value()[0];
  for (const auto& edge : graph.edges()) {  // every information ×4: every covariance ÷4
    Eigen::Map<Eigen::MatrixXd>(edge->mutableInformationData(), edge->errorDim(), edge->errorDim()) *= 4.0;
  }
  ASSERT_TRUE(marginals.compute(optimizer, graph).ok());
  EXPECT_LT(relativeDifference(marginals.blocks({30}).value()[0], 0.25 * before), 1e-12);
}

}  // namespace
}  // namespace dualgraph
