// SPDX-License-Identifier: MIT
// Every shipped type in one graph: poses, points, a sensor offset, priors and relative edges with
// noise-free measurements generated from a known truth. From a perturbed start the optimiser must
// return to the truth (χ² → 0), with either linear solver, and the graph must survive a g2o round
// trip unchanged.
#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/types/edge_point_xyz_prior.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/edge_se3_prior.h"
#include "dualgraph/types/parameter_se3_offset.h"
#include "dualgraph/types/register_types.h"
#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

struct Truth {
  std::vector<Eigen::Isometry3d> world_T_body;
  std::vector<Eigen::Vector3d> p_world;
  Eigen::Isometry3d body_T_sensor;
};

Truth makeTruth(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Truth truth;
  for (int k = 0; k < 8; ++k) {
    Vector6d xi;
    xi << 2.0 * k, std::sin(k), 0.3 * normal(rng), 0.1 * normal(rng), 0.1 * normal(rng), 0.4 * k;
    truth.world_T_body.push_back(se3Exp(xi));
  }
  for (int k = 0; k < 5; ++k) truth.p_world.emplace_back(3.0 * k, 2.0 + normal(rng), normal(rng));
  Vector6d offset;
  offset << 0.1, -0.05, 0.2, 0.0, 0.3, -0.1;
  truth.body_T_sensor = se3Exp(offset);
  return truth;
}

/// Poses 0..7, points 100..104, estimates perturbed from the truth.
void buildGraph(const Truth& truth, std::mt19937& rng, Graph& graph) {
  std::normal_distribution<double> normal(0.0, 0.05);
  auto offset = std::make_unique<ParameterSE3Offset>(3);
  offset->setOffset(truth.body_T_sensor);
  ASSERT_TRUE(graph.parameters().add(std::move(offset)).ok());
  for (size_t k = 0; k < truth.world_T_body.size(); ++k) {
    auto v = std::make_unique<VertexSE3>(static_cast<int>(k));
    Vector6d noise;
    for (int i = 0; i < 6; ++i) noise[i] = normal(rng);
    v->setEstimate(truth.world_T_body[k] * se3Exp(noise));
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  for (size_t k = 0; k < truth.p_world.size(); ++k) {
    auto v = std::make_unique<VertexPointXYZ>(100 + static_cast<int>(k));
    v->setEstimate(truth.p_world[k] + Eigen::Vector3d(normal(rng), normal(rng), normal(rng)));
    ASSERT_TRUE(graph.addVertex(std::move(v)).ok());
  }
  auto connect = [&graph](std::unique_ptr<EdgeBase> edge, std::initializer_list<int> ids) {
    size_t slot = 0;
    for (int id : ids) ASSERT_TRUE(edge->setVertex(slot++, graph.vertex(id)).ok());
    ASSERT_TRUE(graph.addEdge(std::move(edge)).ok());
  };
  for (size_t k = 0; k + 1 < truth.world_T_body.size(); ++k) {
    auto odometry = std::make_unique<EdgeSE3>();
    odometry->setMeasurement(truth.world_T_body[k].inverse() * truth.world_T_body[k + 1]);
    odometry->setInformation(informationMetricToG2o(Matrix6d::Identity() * 100.0));
    connect(std::move(odometry), {static_cast<int>(k), static_cast<int>(k + 1)});
  }
  auto prior = std::make_unique<EdgeSE3Prior>();
  prior->setOffset(3, truth.body_T_sensor);
  prior->setMeasurement(truth.world_T_body[0] * truth.body_T_sensor);
  prior->setInformation(Matrix6d::Identity() * 1e4);
  connect(std::move(prior), {0});
  for (size_t k = 0; k < truth.world_T_body.size(); ++k) {
    for (size_t p = 0; p < truth.p_world.size(); ++p) {
      if ((k + p) % 2 != 0) continue;
      auto seen = std::make_unique<EdgeSE3PointXYZ>();
      seen->setOffset(3, truth.body_T_sensor);
      seen->setMeasurement((truth.world_T_body[k] * truth.body_T_sensor).inverse() * truth.p_world[p]);
      seen->setInformation(Eigen::Matrix3d::Identity() * 25.0);
      connect(std::move(seen), {static_cast<int>(k), 100 + static_cast<int>(p)});
    }
  }
  auto point_prior = std::make_unique<EdgePointXYZPrior>();
  point_prior->setMeasurement(truth.p_world[2]);
  point_prior->setInformation(Eigen::Matrix3d::Identity());
  connect(std::move(point_prior), {102});
}

TEST(MixedGraph, NoiseFreeMeasurementsAreRecoveredFromAPerturbedStartWithBothSolvers) {
  for (const char* linear : {"cholmod", "eigen"}) {
    SCOPED_TRACE(linear);
    std::mt19937 rng(11);
    const Truth truth = makeTruth(rng);
    Graph graph;
    buildGraph(truth, rng, graph);
    Optimizer optimizer(graph, makeLinearSolver(*parseLinearSolverKind(linear)));
    const SolverSummary summary = optimizer.optimize(OptimizerParams{});
    EXPECT_TRUE(summary.usable()) << terminationReasonName(summary.termination) << summary.message;
    EXPECT_GT(summary.initial_chi2, 1.0);
    EXPECT_LT(summary.final_chi2, 1e-12);
    for (size_t k = 0; k < truth.world_T_body.size(); ++k) {
      const auto& estimate = graph.vertexAs<VertexSE3>(static_cast<int>(k))->estimate();
      EXPECT_LT(se3Log(truth.world_T_body[k].inverse() * estimate).norm(), 1e-6) << "pose " << k;
    }
    for (size_t p = 0; p < truth.p_world.size(); ++p) {
      EXPECT_LT((graph.vertexAs<VertexPointXYZ>(100 + static_cast<int>(p))->estimate() - truth.p_world[p]).norm(), 1e-6);
    }
  }
}

TEST(MixedGraph, EveryTypeSurvivesAG2oRoundTripWithTheSameChi2) {
  std::mt19937 rng(12);
  const Truth truth = makeTruth(rng);
  Graph graph;
  buildGraph(truth, rng, graph);
  TypeRegistry registry;
  ASSERT_TRUE(registerBuiltinTypes(registry).ok());
  std::stringstream first;
  ASSERT_TRUE(writeG2o(first, registry, graph).ok());
  Graph reread;
  const auto report = readG2o(first, "mixed.g2o", registry, reread);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->parameters, 1);
  EXPECT_EQ(reread.numEdges(), graph.numEdges());
  EXPECT_NEAR(reread.chi2(), graph.chi2(), 1e-9 * graph.chi2());
  std::stringstream second;
  ASSERT_TRUE(writeG2o(second, registry, reread).ok());
  EXPECT_EQ(second.str(), first.str()) << "write→read→write is not bit-identical";
}

}  // namespace
}  // namespace dualgraph
