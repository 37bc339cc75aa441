// SPDX-License-Identifier: MIT
// TemporaryPool (the temporary graph's reusable vertices and edges): its copy as a Graph is the same
// graph, reused objects start as new ones would, and a TemporaryGraph that distils one interval after
// another gives, bit for bit, what a fresh one gives for the later interval.
#include "dualgraph/dual_graph/temporary_pool.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "dualgraph/dual_graph/temporary_graph.h"
#include "dualgraph/solvers/block/block_lm_solver.h"
#include "dualgraph/types/edge_point_xyz_prior.h"
#include "test/dual_graph/distillation_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

GateEdgeMeasurement randomPoseMeasurement(int gate) {
  GateEdgeMeasurement measurement;
  measurement.gate_id = gate;
  measurement.node_T_gate = randomPose(2.0);
  measurement.pose_information = randomCovariance<6>(10.0);
  return measurement;
}

GateEdgeMeasurement fixedPointMeasurement(int gate) {
  GateEdgeMeasurement measurement;
  measurement.gate_id = gate;
  measurement.model = LandmarkModel::kPoint;
  measurement.p_node = Eigen::Vector3d(1.0, 2.0, 3.0);
  measurement.point_information = randomCovariance<3>(5.0);
  return measurement;
}

TEST(TemporaryPool, CopyToBuildsTheSameGraph) {
  const auto kernel = std::shared_ptr<const RobustKernel>(*makeRobustKernel("huber:3"));
  TemporaryPool problem;
  ASSERT_TRUE(problem.addPose(0, randomPose(1.0), false).ok());
  ASSERT_TRUE(problem.addGate(1, LandmarkModel::kPose, randomPose(3.0)).ok());
  ASSERT_TRUE(problem.addGate(2, LandmarkModel::kPoint, randomPose(3.0)).ok());
  ASSERT_TRUE(problem.addPose(3, randomPose(1.0), true).ok());
  ASSERT_TRUE(problem.addPoseEdge(0, 3, randomPose(1.0), randomCovariance<6>(1.0)).ok());
  ASSERT_TRUE(problem.addGateEdge(0, 1, randomPoseMeasurement(7), kernel).ok());
  ASSERT_TRUE(problem.addGateEdge(3, 2, fixedPointMeasurement(8), kernel).ok());
  Graph graph;
  ASSERT_TRUE(problem.copyTo(graph, kernel).ok());
  ASSERT_EQ(graph.numVertices(), 4u);
  ASSERT_EQ(graph.numEdges(), 3u);
  for (int id = 0; id < 4; ++id) {
    EXPECT_EQ(graph.vertex(id)->fixed(), problem.vertices()[id]->fixed());
    EXPECT_EQ(graph.vertex(id)->tangentDim(), problem.vertices()[id]->tangentDim());
  }
  EXPECT_TRUE(graph.vertexAs<VertexSE3>(1)->estimate().isApprox(problem.gateEstimate(1), 0.0));
  EXPECT_EQ(graph.vertexAs<VertexPointXYZ>(2)->estimate(), problem.gateEstimate(2).translation());
  for (size_t e = 0; e < 3; ++e) {
    const EdgeBase& copy = *graph.edges()[e];
    const EdgeBase& original = *problem.edges()[e];
    EXPECT_EQ(copy.robustKernel(), original.robustKernel());
    EXPECT_EQ(copy.vertex(0)->id(), original.vertex(0)->id());
    EXPECT_EQ(copy.vertex(1)->id(), original.vertex(1)->id());
    const int m = copy.errorDim();
    EXPECT_EQ(Eigen::Map<const Eigen::MatrixXd>(copy.informationData(), m, m),
              Eigen::Map<const Eigen::MatrixXd>(original.informationData(), m, m));
  }
  EXPECT_EQ(graph.edges()[0]->robustKernel(), nullptr);
  Graph other;
  const auto another = std::shared_ptr<const RobustKernel>(*makeRobustKernel("huber:3"));
  EXPECT_EQ(problem.copyTo(other, another).code(), StatusCode::kInvalidArgument);
}

TEST(TemporaryPool, ReusedObjectsStartAsNewOnes) {
  const auto kernel = std::shared_ptr<const RobustKernel>(*makeRobustKernel("huber:3"));
  TemporaryPool problem;
  ASSERT_TRUE(problem.addPose(0, randomPose(1.0), true).ok());
  ASSERT_TRUE(problem.addGate(1, LandmarkModel::kPose, randomPose(3.0)).ok());
  ASSERT_TRUE(problem.addGateEdge(0, 1, randomPoseMeasurement(4), kernel).ok());
  problem.clear();
  EXPECT_TRUE(problem.vertices().empty());
  EXPECT_TRUE(problem.edges().empty());
  ASSERT_TRUE(problem.addPose(1, randomPose(1.0), false).ok());  // the first pose object, now id 1 and free
  ASSERT_TRUE(problem.addPose(0, randomPose(1.0), false).ok());
  ASSERT_TRUE(problem.addPoseEdge(1, 0, randomPose(1.0), randomCovariance<6>(1.0)).ok());  // the gate edge's object
  ASSERT_EQ(problem.vertices().size(), 2u);
  EXPECT_EQ(problem.vertices()[1]->id(), 1);
  EXPECT_FALSE(problem.vertices()[1]->fixed());
  EXPECT_EQ(problem.edges()[0]->robustKernel(), nullptr);
  EXPECT_EQ(problem.edges()[0]->vertex(0), problem.vertices()[1]);
  EXPECT_EQ(problem.addPose(1, randomPose(1.0), false).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(problem.addPose(-1, randomPose(1.0), false).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(problem.addPoseEdge(0, 0, randomPose(1.0), Matrix6d::Identity()).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(problem.addPoseEdge(0, 5, randomPose(1.0), Matrix6d::Identity()).code(), StatusCode::kNotFound);
}

TEST(TemporaryPool, AnEdgeTypeWithoutASlotIsPooledAndSolvedButNotCopied) {
  // EdgePointXYZPrior stands for a new detection type's edge: the pool has no slot of its own for it.
  TemporaryPool problem;
  ASSERT_TRUE(problem.addGate(0, LandmarkModel::kPoint, randomPose(3.0)).ok());
  Result<EdgePointXYZPrior*> prior = problem.addEdgeOfType<EdgePointXYZPrior>({0}, nullptr);
  ASSERT_TRUE(prior.ok()) << prior.status().message();
  (*prior)->setMeasurement(Eigen::Vector3d(1.0, -2.0, 0.5));
  (*prior)->setInformation(Eigen::Matrix3d::Identity() * 4.0);
  ASSERT_EQ(problem.edges().size(), 1u);
  BlockLmSolver solver;
  ASSERT_TRUE(solver.setProblem(problem.vertices(), problem.edges()).ok());
  OptimizerParams lm;
  ASSERT_TRUE(solver.optimize(lm).usable());
  EXPECT_LT((problem.gateEstimate(0).translation() - Eigen::Vector3d(1.0, -2.0, 0.5)).norm(), 1e-9);
  ASSERT_TRUE(solver.computeMarginals({0}).ok());
  Result<Eigen::MatrixXd> marginal = solver.marginal(0);
  ASSERT_TRUE(marginal.ok());
  EXPECT_LT((*marginal - Eigen::Matrix3d::Identity() * 0.25).norm(), 1e-9);
  Graph graph;  // the oracle path says it cannot copy it, never copies something else
  const Status copied = problem.copyTo(graph, nullptr);
  EXPECT_EQ(copied.code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(copied.message().find("temp_solver: block"), std::string::npos) << copied.message();
  // Reused after clear, checked like every slot.
  problem.clear();
  ASSERT_TRUE(problem.addPose(0, randomPose(1.0), false).ok());
  EXPECT_EQ(problem.addEdgeOfType<EdgePointXYZPrior>({0}, nullptr).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(problem.addEdgeOfType<EdgePointXYZPrior>({4}, nullptr).status().code(), StatusCode::kNotFound);
  EXPECT_EQ(problem.addEdgeOfType<EdgePointXYZPrior>({0, 0}, nullptr).status().code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(problem.addGate(1, LandmarkModel::kPoint, randomPose(3.0)).ok());
  Result<EdgePointXYZPrior*> reused = problem.addEdgeOfType<EdgePointXYZPrior>({1}, nullptr);
  ASSERT_TRUE(reused.ok());
  EXPECT_EQ(problem.edges().size(), 1u);
}

/// `samples` VIO samples 0.3 m apart, gates 0..2 ahead, every sample sees two of them (seeded noise).
struct ReuseInterval {
  OdometryHistory history;
  std::vector<Eigen::Isometry3d> odom_T_body;
  std::vector<std::vector<GateObservation>> observations;  // per sample
};

ReuseInterval makeReuseInterval(int samples, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  ReuseInterval interval;
  std::vector<Matrix6d> covariances;
  for (int k = 0; k < samples; ++k) {
    Vector6d xi;
    xi << 0.3 * k, 0.01 * k * k, 0.01 * normal(rng), 0.0, 0.0, 0.05 * k;
    interval.odom_T_body.push_back(se3Exp(xi));
    covariances.push_back(randomCovariance<6>(1e-4));
  }
  interval.history = makeHistory(interval.odom_T_body, covariances);
  interval.observations.resize(samples);
  for (int k = 0; k + 1 < samples; ++k) {
    for (int g = k * 2 / samples; g < k * 2 / samples + 2; ++g) {
      Vector6d xi, noise;
      xi << 1.0 + 0.3 * samples * g / 2.0, (g % 2 == 0 ? 1.5 : -1.5), 1.0, 0.1 * g, 0.0, 0.3;
      for (int i = 0; i < 6; ++i) noise[i] = normal(rng) * (i < 3 ? 0.03 : 0.01);
      const Eigen::Isometry3d body_T_gate = interval.odom_T_body[k].inverse() * se3Exp(xi) * se3Exp(noise);
      interval.observations[k].push_back(GateObservation::pose(k, g, body_T_gate, randomCovariance<6>(1e-3)));
    }
  }
  return interval;
}

DistillationResult distilInto(TemporaryGraph& temporary, const ReuseInterval& interval) {
  for (size_t k = 0; k < interval.observations.size(); ++k) {
    for (const GateObservation& observation : interval.observations[k]) {
      const Status added = temporary.addObservation(observation, interval.odom_T_body[k], interval.history);
      EXPECT_TRUE(added.ok()) << added.message();
    }
  }
  return temporary.distil(interval.odom_T_body.size() - 1.0, interval.odom_T_body.back(), interval.history);
}

TEST(TemporaryGraphReuse, DistilsALaterIntervalAsAFreshGraphDoes) {
  for (TemporarySolverKind kind : {TemporarySolverKind::kBlock, TemporarySolverKind::kGraph}) {
    LocalizerParams params;
    params.temp_solver = kind;
    const auto kernel = std::shared_ptr<const RobustKernel>(*makeRobustKernel(params.robust_kernel));
    TemporaryGraph reused(params, kernel);
    const DistillationResult first = distilInto(reused, makeReuseInterval(14, 1));  // larger: objects left over
    ASSERT_EQ(first.skipped_gates, 0) << first.skip_reason;
    const ReuseInterval later = makeReuseInterval(9, 2);
    const DistillationResult again = distilInto(reused, later);
    TemporaryGraph fresh(params, kernel);
    const DistillationResult expected = distilInto(fresh, later);
    EXPECT_EQ(again.nodes, expected.nodes);
    EXPECT_EQ(again.edges, expected.edges);
    EXPECT_EQ(again.iterations, expected.iterations);
    ASSERT_EQ(again.gates.size(), expected.gates.size());
    ASSERT_FALSE(expected.gates.empty());
    for (size_t g = 0; g < expected.gates.size(); ++g) {
      EXPECT_EQ(again.gates[g].gate_id, expected.gates[g].gate_id);
      EXPECT_EQ(again.gates[g].node_T_gate.matrix(), expected.gates[g].node_T_gate.matrix());
      EXPECT_EQ(again.gates[g].pose_information, expected.gates[g].pose_information);
    }
  }
}

}  // namespace
}  // namespace dualgraph
