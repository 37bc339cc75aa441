// SPDX-License-Identifier: MIT
// The chordal initialiser on noisy SE(3) graphs against independent references: its rotations are the SO(3)
// projections of a dense least-squares solve of the weighted relaxation over vec(R) (Kronecker form), and its
// translations zero the gradient of the edges' own χ² with the rotations held.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <memory>
#include <utility>
#include <vector>

#include "dualgraph/solvers/chordal_init.h"
#include "dualgraph/solvers/chordal_systems.h"
#include "test/types/test_states.h"
#include "dualgraph/types/edge_se3.h"

namespace dualgraph {
namespace {

using testing::Rng;
using testing::Regime;

constexpr int kNoisyPoses = 15;

/// Noisy measurements (0.2 rad, 0.3 m), block-diagonal informations with anisotropic, different blocks per
/// edge; vertex 0 fixed at its truth, the others at random poses.
void buildNoisySe3(Graph& graph, Rng& rng) {
  std::vector<Eigen::Isometry3d> truth;
  for (int k = 0; k < kNoisyPoses; ++k) {
    truth.push_back(testing::randomPose(rng, Regime::kRandom));
    auto v = std::make_unique<VertexSE3>(k);
    v->setEstimate(k == 0 ? truth.back() : testing::randomPose(rng, Regime::kRandom));
    v->setFixed(k == 0);
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  std::vector<std::pair<int, int>> pairs;
  for (int k = 1; k < kNoisyPoses; ++k) pairs.emplace_back(k - 1, k);
  for (int k = 2; k < kNoisyPoses; k += 2) pairs.emplace_back(k / 3, k);
  for (const auto& [i, j] : pairs) {
    Vector6d noise;
    for (int r = 0; r < 6; ++r) noise[r] = (r < 3 ? 0.3 : 0.2) * testing::gaussian(rng);
    auto edge = std::make_unique<EdgeSE3>();
    edge->setMeasurement(truth[i].inverse() * truth[j] * se3Exp(noise));
    Matrix6d information = Matrix6d::Zero();
    information.topLeftCorner<3, 3>() = testing::randomInformation<3>(rng, testing::uniform(rng, 1.0, 50.0));
    information.bottomRightCorner<3, 3>() = testing::randomInformation<3>(rng, testing::uniform(rng, 1.0, 500.0));
    edge->setInformation(information);
    ASSERT_TRUE(edge->setVertex(0, graph.vertex(i)).ok());
    ASSERT_TRUE(edge->setVertex(1, graph.vertex(j)).ok());
    ASSERT_TRUE(graph.addEdge(std::move(edge)).ok());
  }
}

TEST(ChordalOptimality, RotationsAreTheProjectedDenseSolutionOfTheWeightedRelaxation) {
  Rng rng(testing::kSeed + 10);
  Graph graph;
  buildNoisySe3(graph, rng);
  // Unknowns vec(R_k) (column-major, 9 per free pose k = 1..n-1); vec(R_i R_ij) = (R_ijᵀ ⊗ I₃) vec(R_i).
  const int n = 9 * (kNoisyPoses - 1);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(9 * static_cast<int>(graph.numEdges()), n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(a.rows());
  const Eigen::Matrix3d r0 = graph.vertexAs<VertexSE3>(0)->estimate().linear();
  int row = 0;
  for (const auto& base : graph.edges()) {
    const auto& edge = static_cast<const EdgeSE3&>(*base);
    const int i = edge.vertex(0)->id(), j = edge.vertex(1)->id();
    const double s = std::sqrt(edge.information().bottomRightCorner<3, 3>().trace() / 3.0);
    Eigen::Matrix<double, 9, 9> kron;
    const Eigen::Matrix3d rt = edge.measurement().linear().transpose();
    for (int p = 0; p < 3; ++p) {
      for (int q = 0; q < 3; ++q) kron.block<3, 3>(3 * p, 3 * q) = rt(p, q) * Eigen::Matrix3d::Identity();
    }
    // residual vec(R_j) − kron vec(R_i)
    if (j > 0) a.block<9, 9>(row, 9 * (j - 1)) += s * Eigen::Matrix<double, 9, 9>::Identity();
    if (i > 0) a.block<9, 9>(row, 9 * (i - 1)) -= s * kron;
    if (i == 0) b.segment<9>(row) += s * kron * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(r0.data());
    if (j == 0) b.segment<9>(row) -= s * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(r0.data());
    row += 9;
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
  ASSERT_TRUE(initializePoseGraph(graph, PoseGraphInit::kChordal, LinearSolverKind::kEigen).ok());
  for (int k = 1; k < kNoisyPoses; ++k) {
    const Eigen::Matrix3d relaxed = Eigen::Map<const Eigen::Matrix3d>(x.data() + 9 * (k - 1));
    const Eigen::Matrix3d expected = chordal::nearestRotation<3>(relaxed);
    EXPECT_LT((graph.vertexAs<VertexSE3>(k)->estimate().linear() - expected).norm(), 1e-9) << "vertex " << k;
  }
}

TEST(ChordalOptimality, TranslationsZeroTheChi2GradientWithTheRotationsHeld) {
  Rng rng(testing::kSeed + 11);
  Graph graph;
  buildNoisySe3(graph, rng);
  // Central differences of the edges' own χ² (g2o's errors) along world-axis translations of each free pose.
  const auto gradient = [&graph](int id) {
    auto* v = graph.vertexAs<VertexSE3>(id);
    const Eigen::Isometry3d start = v->estimate();
    Eigen::Vector3d g;
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Isometry3d moved = start;
      moved.translation()[axis] += 1e-5;
      v->setEstimate(moved);
      const double plus = graph.chi2();
      moved.translation()[axis] -= 2e-5;
      v->setEstimate(moved);
      g[axis] = (plus - graph.chi2()) / 2e-5;
      v->setEstimate(start);
    }
    return g;
  };
  double start_norm = 0.0;
  for (int k = 1; k < kNoisyPoses; ++k) start_norm = std::max(start_norm, gradient(k).norm());
  ASSERT_TRUE(initializePoseGraph(graph, PoseGraphInit::kChordal).ok());
  for (int k = 1; k < kNoisyPoses; ++k) EXPECT_LT(gradient(k).norm(), 1e-6 * start_norm) << "vertex " << k;
  EXPECT_GT(start_norm, 1.0);
}

}  // namespace
}  // namespace dualgraph
