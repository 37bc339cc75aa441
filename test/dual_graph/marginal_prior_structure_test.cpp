// SPDX-License-Identifier: MIT
// The marginal prior's structure: its rows come from the pivoted Cholesky of the Schur complement (JᵀJ = Λ,
// Jᵀe₀ = β, one row per non-negligible pivot, so a rank-deficient Λ keeps its rank: Eigen's LDLT, tried first,
// met a zero pivot before a non-zero one here and lost a direction), and its constant JᵀJ
// (EdgeBase::constantHessianData) gives the optimiser the same H and b as forming it from the Jacobians.
#include <gtest/gtest.h>

#include <random>

#include "dualgraph/core/optimizer.h"
#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/marginal_prior.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

Eigen::Isometry3d structurePose(std::mt19937& rng, double scale) {
  std::normal_distribution<double> normal(0.0, scale);
  Vector6d v;
  for (int k = 0; k < 6; ++k) v(k) = normal(rng) * (k < 3 ? 1.0 : 0.3);
  return g2oIncrement(v);
}

void addStructurePose(Graph& graph, int id, const Eigen::Isometry3d& pose) {
  auto vertex = std::make_unique<VertexSE3>(id);
  vertex->setEstimate(pose);
  ASSERT_TRUE(graph.addVertex(std::move(vertex)).ok());
}

Matrix6d structureInformation(double sigma_t, double sigma_r) {
  Vector6d d;
  d << Eigen::Vector3d::Constant(1.0 / (sigma_t * sigma_t)), Eigen::Vector3d::Constant(1.0 / (sigma_r * sigma_r));
  return d.asDiagonal();
}

TEST(MarginalPriorStructure, ARankDeficientSchurComplementKeepsItsRankAndItsQuadraticModel) {
  // Pose 0 tied to pose 1 by odometry (6 rows) and to a point by one observation (3 rows): eliminating its 6
  // unknowns leaves 3 rows of information over the 9 of (pose 1, point).
  std::mt19937 rng(3);
  Graph graph;
  const Eigen::Isometry3d p0 = structurePose(rng, 1.0), p1 = p0 * structurePose(rng, 1.0);
  addStructurePose(graph, 0, p0);
  addStructurePose(graph, 1, p1 * structurePose(rng, 0.02));
  auto point = std::make_unique<VertexPointXYZ>(2);
  point->setEstimate(p0 * Eigen::Vector3d(2.0, -1.0, 0.5) + Eigen::Vector3d(0.03, 0.0, -0.02));
  ASSERT_TRUE(graph.addVertex(std::move(point)).ok());
  ASSERT_TRUE(addRelativePoseEdge(graph, 0, 1, p0.inverse() * p1, structureInformation(0.05, 0.01)).ok());
  ASSERT_TRUE(addPointObservationEdge(graph, 0, 2, Eigen::Vector3d(2.0, -1.0, 0.5), Eigen::Matrix3d::Identity() * 400.0).ok());
  // The oracle: the dense Gauss–Newton system over [pose 0; pose 1; point] and its Schur complement.
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(15, 15);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(15);
  const int offset[3] = {0, 6, 12};
  for (const auto& edge : graph.edges()) {
    edge->linearize();
    const int m = edge->errorDim();
    const Eigen::Map<const Eigen::MatrixXd> omega(edge->informationData(), m, m);
    const Eigen::Map<const Eigen::VectorXd> e(edge->errorData(), m);
    for (size_t a = 0; a < edge->numVertices(); ++a) {
      const int da = edge->vertex(a)->tangentDim(), oa = offset[edge->vertex(a)->id()];
      const Eigen::Map<const Eigen::MatrixXd> Ja(edge->jacobianData(a), m, da);
      g.segment(oa, da) += Ja.transpose() * omega * e;
      for (size_t b = 0; b < edge->numVertices(); ++b) {
        const int db = edge->vertex(b)->tangentDim(), ob = offset[edge->vertex(b)->id()];
        H.block(oa, ob, da, db) += Ja.transpose() * omega * Eigen::Map<const Eigen::MatrixXd>(edge->jacobianData(b), m, db);
      }
    }
  }
  const Eigen::MatrixXd Hmm_inv = H.topLeftCorner(6, 6).inverse();
  const Eigen::MatrixXd lambda = H.bottomRightCorner(9, 9) - H.bottomLeftCorner(9, 6) * Hmm_inv * H.topRightCorner(6, 9);
  const Eigen::VectorXd beta = g.tail(9) - H.bottomLeftCorner(9, 6) * Hmm_inv * g.head(6);

  Result<MarginalizationOutcome> outcome = marginalizeVertex(graph, 0);
  ASSERT_TRUE(outcome.ok()) << outcome.status().message();
  ASSERT_NE(outcome->prior, nullptr);
  EXPECT_EQ(outcome->prior_rows, 3);
  EdgeMarginalPrior& prior = *outcome->prior;
  prior.linearize();  // at the linearisation point: e = e₀, J as built
  Eigen::MatrixXd J(3, 9);
  J.leftCols(6) = Eigen::Map<const Eigen::MatrixXd>(prior.jacobianData(0), 3, 6);
  J.rightCols(3) = Eigen::Map<const Eigen::MatrixXd>(prior.jacobianData(1), 3, 3);
  const Eigen::Map<const Eigen::VectorXd> e0(prior.errorData(), 3);
  EXPECT_LT((J.transpose() * J - lambda).norm(), 1e-9 * lambda.norm());
  EXPECT_LT((J.transpose() * e0 - beta).norm(), 1e-9 * std::max(beta.norm(), 1.0));
  EXPECT_LT((prior.informationOfCoordinates() - lambda).norm(), 1e-9 * lambda.norm());
}

/// H's values and b after marginalising poses 0 and 1 of a 4-pose chain that sees one gate (optionally with
/// the gate fixed), assembled with the prior's constant JᵀJ (`constant`) or from its Jacobians.
struct AssembledSystem {
  std::vector<double> values;
  Eigen::VectorXd rhs;
};
AssembledSystem assembleAfterMarginalisation(bool constant, bool fix_gate) {
  std::mt19937 rng(9);
  Graph graph;
  std::vector<Eigen::Isometry3d> truth;
  for (int k = 0; k < 4; ++k) truth.push_back(k == 0 ? structurePose(rng, 1.0) : truth.back() * structurePose(rng, 0.7));
  const Eigen::Isometry3d gate = truth[1] * structurePose(rng, 3.0);
  for (int k = 0; k < 4; ++k) addStructurePose(graph, k, truth[k] * structurePose(rng, 0.01));
  addStructurePose(graph, 100, gate * structurePose(rng, 0.01));
  EXPECT_TRUE(addPosePriorEdge(graph, 0, truth[0], structureInformation(0.5, 0.1)).ok());
  EXPECT_TRUE(addPosePriorEdge(graph, 100, gate, structureInformation(0.05, 0.03)).ok());
  for (int k = 0; k + 1 < 4; ++k) {
    EXPECT_TRUE(addRelativePoseEdge(graph, k, k + 1, truth[k].inverse() * truth[k + 1], structureInformation(0.05, 0.01)).ok());
  }
  for (int k = 0; k < 4; ++k) {
    EXPECT_TRUE(addRelativePoseEdge(graph, k, 100, truth[k].inverse() * gate * structurePose(rng, 0.01),
                                    structureInformation(0.1, 0.03)).ok());
  }
  EdgeMarginalPrior* prior = nullptr;
  for (int id : {0, 1}) {
    Result<MarginalizationOutcome> outcome = marginalizeVertex(graph, id);
    EXPECT_TRUE(outcome.ok());
    if (outcome.ok()) prior = outcome->prior;
  }
  EXPECT_NE(prior, nullptr);
  if (prior == nullptr) return {};
  EXPECT_NE(prior->constantHessianData(), nullptr);
  EXPECT_LT((Eigen::Map<const Eigen::MatrixXd>(prior->constantHessianData(), 12, 12) - prior->informationOfCoordinates()).norm(),
            1e-12 * prior->informationOfCoordinates().norm());
  if (!constant) {
    (void)prior->mutableInformationData();  // handed out: formed from the Jacobians from now on
    EXPECT_EQ(prior->constantHessianData(), nullptr);
  }
  if (fix_gate) {
    EXPECT_TRUE(graph.setFixed(100, true).ok());
  }
  Optimizer optimizer(graph, makeLinearSolver(LinearSolverKind::kEigen));
  EXPECT_TRUE(optimizer.factorizeAtCurrentEstimate().ok());
  const SparseMatrixView h = optimizer.system().matrix();
  return {std::vector<double>(h.values, h.values + h.nnz()), optimizer.system().rhs()};
}

TEST(MarginalPriorStructure, TheConstantHessianGivesTheSameSystemAsTheJacobians) {
  for (bool fix_gate : {false, true}) {
    const AssembledSystem copied = assembleAfterMarginalisation(true, fix_gate);
    const AssembledSystem formed = assembleAfterMarginalisation(false, fix_gate);
    ASSERT_EQ(copied.values.size(), formed.values.size());
    ASSERT_FALSE(copied.values.empty());
    const Eigen::Map<const Eigen::VectorXd> a(copied.values.data(), static_cast<Eigen::Index>(copied.values.size()));
    const Eigen::Map<const Eigen::VectorXd> b(formed.values.data(), static_cast<Eigen::Index>(formed.values.size()));
    EXPECT_LT((a - b).norm(), 1e-12 * b.norm()) << "gate fixed: " << fix_gate;
    EXPECT_LT((copied.rhs - formed.rhs).norm(), 1e-12 * std::max(formed.rhs.norm(), 1.0)) << "gate fixed: " << fix_gate;
  }
}

}  // namespace
}  // namespace dualgraph
