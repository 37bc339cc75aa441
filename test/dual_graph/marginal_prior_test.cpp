// SPDX-License-Identifier: MIT
// EdgeMarginalPrior's analytic Jacobians against central differences, and marginalizeVertex: at the
// optimum the reduced graph keeps the optimum and the remaining vertices' marginal covariances (exact
// for the Gauss–Newton model); off the optimum it lands within second-order terms; errors leave the graph
// unchanged.
#include <gtest/gtest.h>

#include "dualgraph/core/optimizer.h"
#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/marginal_prior.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/solvers/marginal_covariance.h"
#include "test/dual_graph/distillation_fixtures.h"
#include "test/testing/jacobian_check.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se2.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

VertexSE3* addPose(Graph& graph, int id, const Eigen::Isometry3d& pose) {
  auto v = std::make_unique<VertexSE3>(id);
  v->setEstimate(pose);
  VertexSE3* raw = v.get();
  EXPECT_TRUE(graph.addVertex(std::move(v)).ok());
  return raw;
}

Matrix6d information(double sigma_t, double sigma_r) {
  Vector6d d;
  d << Eigen::Vector3d::Constant(1.0 / (sigma_t * sigma_t)), Eigen::Vector3d::Constant(1.0 / (sigma_r * sigma_r));
  return d.asDiagonal();
}

/// Poses 0..n-1 on a chain (odometry edges, prior on pose 0), an SE(3) gate (id 100, map prior) and a
/// point gate (id 101, prior) seen from every pose; measurements are perturbed so χ² > 0 at the optimum.
void buildChain(Graph& graph, int n, double jitter_sigma = 0.01) {
  distillationRng().seed(11);  // every call builds the same graph
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, jitter_sigma);
  auto jitter = [&]() {
    Vector6d v;
    for (int k = 0; k < 6; ++k) v(k) = noise(rng);
    return g2oIncrement(v);
  };
  std::vector<Eigen::Isometry3d> truth;
  for (int k = 0; k < n; ++k) truth.push_back(k == 0 ? randomPose(1.0) : truth.back() * randomPose(0.7));
  const Eigen::Isometry3d gate = truth[1] * randomPose(3.0);
  const Eigen::Vector3d point = truth[2] * Eigen::Vector3d(2.0, -1.0, 0.5);
  for (int k = 0; k < n; ++k) addPose(graph, k, truth[k] * jitter());
  addPose(graph, 100, gate * jitter());
  auto p = std::make_unique<VertexPointXYZ>(101);
  p->setEstimate(point + Eigen::Vector3d(0.02, -0.01, 0.01));
  ASSERT_TRUE(graph.addVertex(std::move(p)).ok());
  ASSERT_TRUE(addPosePriorEdge(graph, 0, truth[0] * jitter(), information(0.5, 0.1)).ok());
  ASSERT_TRUE(addPosePriorEdge(graph, 100, gate * jitter(), information(0.1, 0.05)).ok());
  ASSERT_TRUE(addPointPriorEdge(graph, 101, point, Eigen::Matrix3d::Identity() * 100.0).ok());
  for (int k = 0; k + 1 < n; ++k) {
    ASSERT_TRUE(addRelativePoseEdge(graph, k, k + 1, truth[k].inverse() * truth[k + 1] * jitter(), information(0.05, 0.01)).ok());
  }
  for (int k = 0; k < n; ++k) {
    ASSERT_TRUE(addRelativePoseEdge(graph, k, 100, truth[k].inverse() * gate * jitter(), information(0.1, 0.03)).ok());
    ASSERT_TRUE(addPointObservationEdge(graph, k, 101, truth[k].inverse() * point + Eigen::Vector3d::Constant(noise(rng)),
                                        Eigen::Matrix3d::Identity() * 400.0).ok());
  }
}

SolverSummary solve(Optimizer& optimizer) {
  OptimizerParams params;
  params.relative_decrease_stop = 1e-14;
  params.step_norm_stop = 1e-13;
  return optimizer.optimize(params);
}

/// A seeded random linearisation: J (rows × cols) and e0, drawn row by row (e0(r), then J's row r).
struct RandomLinearisation {
  Eigen::MatrixXd J;
  Eigen::VectorXd e0;
};
RandomLinearisation randomLinearisation(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  RandomLinearisation out{Eigen::MatrixXd(rows, cols), Eigen::VectorXd(rows)};
  for (int r = 0; r < rows; ++r) {
    out.e0(r) = normal(rng);
    for (int c = 0; c < cols; ++c) out.J(r, c) = normal(rng);
  }
  return out;
}

TEST(EdgeMarginalPrior, FirstEstimateJacobiansAreExactAtTheLinearisationPointAndCloseNearIt) {
  Graph graph;
  addPose(graph, 0, randomPose(1.0));
  addPose(graph, 1, randomPose(2.0));
  auto p = std::make_unique<VertexPointXYZ>(2);
  p->setEstimate(Eigen::Vector3d(1.0, 2.0, 3.0));
  ASSERT_TRUE(graph.addVertex(std::move(p)).ok());
  const std::vector<VertexBase*> vertices = {graph.vertex(0), graph.vertex(1), graph.vertex(2)};
  const auto [J, e0] = randomLinearisation(10, 15, 3);
  Result<std::unique_ptr<EdgeMarginalPrior>> prior = EdgeMarginalPrior::create(vertices, J, e0);
  ASSERT_TRUE(prior.ok()) << prior.status().message();
  // At the linearisation point: error e0, Jacobians J, equal to central differences.
  (*prior)->linearize();
  EXPECT_LT((Eigen::Map<const Eigen::VectorXd>((*prior)->errorData(), 10) - e0).norm(), 1e-12);
  EXPECT_TRUE(analyticJacobiansMatchNumeric(**prior, 1e-6));
  // 1e-3 away (the size of a keyframe's correction after it left the window): within O(|δ|).
  auto move_all = [&](double scale) {
    Vector6d step;
    step << 0.3, -0.2, 0.1, 0.2, -0.1, 0.15;
    step *= scale;
    vertices[0]->plus(step.data());
    vertices[1]->plus((-step).eval().data());
    const Eigen::Vector3d point_step = scale * Eigen::Vector3d(0.5, -0.4, 0.2);
    vertices[2]->plus(point_step.data());
  };
  move_all(3e-3);
  EXPECT_TRUE(analyticJacobiansMatchNumeric(**prior, 1e-2));
  EXPECT_FALSE(analyticJacobiansMatchNumeric(**prior, 1e-6));  // first-estimate, not re-evaluated
  // Far away the error still follows the chart while the Jacobian stays J.
  move_all(1.0);
  (*prior)->linearize();
  EXPECT_GT((Eigen::Map<const Eigen::VectorXd>((*prior)->errorData(), 10) - e0).norm(), 0.1);
  EXPECT_EQ(Eigen::Map<const Eigen::MatrixXd>((*prior)->jacobianData(1), 10, 6), J.middleCols(6, 6));
}

// A fixed-lag main graph copies whole (cloneGraph): its marginal prior, first-estimate Jacobians and all, on the
// copy's vertices.
TEST(EdgeMarginalPrior, ACloneIsTheSamePriorOnTheCopysVertices) {
  Graph graph;
  addPose(graph, 0, randomPose(1.0));
  addPose(graph, 1, randomPose(2.0));
  const std::vector<VertexBase*> vertices = {graph.vertex(0), graph.vertex(1)};
  const auto [J, e0] = randomLinearisation(8, 12, 5);
  Result<std::unique_ptr<EdgeMarginalPrior>> prior = EdgeMarginalPrior::create(vertices, J, e0);
  ASSERT_TRUE(prior.ok()) << prior.status().message();
  ASSERT_TRUE(graph.addEdge(std::move(prior).value()).ok());
  Vector6d step;
  step << 0.1, -0.2, 0.05, 0.02, 0.01, -0.03;
  graph.vertex(1)->plus(step.data());  // off the linearisation point
  Graph copy;
  ASSERT_TRUE(cloneGraph(graph, copy).ok());
  EdgeBase& original = *graph.edges()[0];
  EdgeBase& cloned = *copy.edges()[0];
  EXPECT_EQ(cloned.vertex(0), copy.vertex(0));
  EXPECT_EQ(cloned.vertex(1), copy.vertex(1));
  original.linearize();
  cloned.linearize();
  EXPECT_EQ(Eigen::Map<const Eigen::VectorXd>(cloned.errorData(), 8), Eigen::Map<const Eigen::VectorXd>(original.errorData(), 8));
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(Eigen::Map<const Eigen::MatrixXd>(cloned.jacobianData(i), 8, 6),
              Eigen::Map<const Eigen::MatrixXd>(original.jacobianData(i), 8, 6));
  }
  EXPECT_EQ(copy.chi2(), graph.chi2());
  copy.vertex(0)->plus(step.data());
  EXPECT_NE(copy.chi2(), graph.chi2());
}

TEST(EdgeMarginalPrior, CreateRejectsWrongSizesAndNonFiniteValues) {
  Graph graph;
  addPose(graph, 0, Eigen::Isometry3d::Identity());
  const std::vector<VertexBase*> vertices = {graph.vertex(0)};
  EXPECT_EQ(EdgeMarginalPrior::create(vertices, Eigen::MatrixXd::Identity(6, 5), Eigen::VectorXd::Zero(6)).status().code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(EdgeMarginalPrior::create(vertices, Eigen::MatrixXd::Identity(6, 6), Eigen::VectorXd::Zero(0)).status().code(),
            StatusCode::kInvalidArgument);
  Eigen::MatrixXd nan = Eigen::MatrixXd::Identity(6, 6);
  nan(2, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(EdgeMarginalPrior::create(vertices, nan, Eigen::VectorXd::Zero(6)).status().code(), StatusCode::kNumericalError);
}

TEST(MarginalizeVertex, AtTheOptimumKeepsTheOptimumAndTheMarginalCovariances) {
  Graph graph;
  buildChain(graph, 6);
  Optimizer optimizer(graph, makeLinearSolver(LinearSolverKind::kCholmod));
  ASSERT_TRUE(solve(optimizer).usable());
  MarginalCovariance before;
  ASSERT_TRUE(before.compute(optimizer, graph).ok());
  Result<Eigen::MatrixXd> joint_before = before.jointBlock({4, 5, 100, 101});
  ASSERT_TRUE(joint_before.ok());
  std::map<int, Eigen::Isometry3d> optimum;
  for (int id : {3, 4, 5, 100}) optimum[id] = graph.vertexAs<VertexSE3>(id)->estimate();
  const Eigen::Vector3d point_optimum = graph.vertexAs<VertexPointXYZ>(101)->estimate();
  const size_t edges_before = graph.numEdges();
  int folded = 0;
  for (int id : {0, 1, 2}) {
    Result<MarginalizationOutcome> outcome = marginalizeVertex(graph, id);
    ASSERT_TRUE(outcome.ok()) << outcome.status().message();
    ASSERT_NE(outcome->prior, nullptr);
    EXPECT_TRUE(graph.vertex(id)->fixed());
    folded += outcome->edges_folded;
  }
  // pose 0: prior, odometry, 2 gate edges; poses 1 and 2: the previous prior, odometry, 2 gate edges;
  // each time one prior comes back.
  EXPECT_EQ(folded, 4 + 4 + 4);
  EXPECT_EQ(graph.numEdges(), edges_before - 3 * 3);
  EXPECT_TRUE(solve(optimizer).usable());
  for (const auto& [id, pose] : optimum) {
    EXPECT_LT(se3Log(pose.inverse() * graph.vertexAs<VertexSE3>(id)->estimate()).norm(), 1e-8) << "vertex " << id;
  }
  EXPECT_LT((graph.vertexAs<VertexPointXYZ>(101)->estimate() - point_optimum).norm(), 1e-8);
  MarginalCovariance after;
  ASSERT_TRUE(after.compute(optimizer, graph).ok());
  Result<Eigen::MatrixXd> joint_after = after.jointBlock({4, 5, 100, 101});
  ASSERT_TRUE(joint_after.ok());
  EXPECT_LT(relativeDifference(*joint_after, *joint_before), 1e-7);
}

/// Largest pose error (‖log‖) of the window {3, 4, 5, gate} after marginalising poses 0 and 1 at the batch
/// optimum displaced by η in every coordinate, then optimising, against the batch optimum.
double windowErrorAfterDisplacedMarginalisation(double measurement_sigma, double eta) {
  Graph batch;
  buildChain(batch, 6, measurement_sigma);
  Optimizer batch_optimizer(batch, makeLinearSolver(LinearSolverKind::kCholmod));
  EXPECT_TRUE(solve(batch_optimizer).usable());
  Graph windowed;
  buildChain(windowed, 6, measurement_sigma);  // the same graph again (seeded)
  Optimizer window_optimizer(windowed, makeLinearSolver(LinearSolverKind::kEigen));
  EXPECT_TRUE(solve(window_optimizer).usable());
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, eta);
  for (const auto& entry : windowed.vertices()) {
    Vector6d step;
    for (int k = 0; k < 6; ++k) step(k) = normal(rng);
    entry.second->plus(step.data());
  }
  for (int id : {0, 1}) EXPECT_TRUE(marginalizeVertex(windowed, id).ok());
  EXPECT_TRUE(solve(window_optimizer).usable());
  double worst = 0.0;
  for (int id : {3, 4, 5, 100}) {
    worst = std::max(worst, se3Log(batch.vertexAs<VertexSE3>(id)->estimate().inverse() *
                                   windowed.vertexAs<VertexSE3>(id)->estimate()).norm());
  }
  return worst;
}

TEST(MarginalizeVertex, OffTheOptimumTheErrorIsSecondOrderForConsistentMeasurements) {
  // Near-zero residuals: the Gauss–Newton model is exact to second order, so a 10× smaller displacement
  // gives a ≈ 100× smaller error (measured: 7.9e-4 and 8.8e-6).
  const double coarse = windowErrorAfterDisplacedMarginalisation(1e-5, 1e-2);
  const double fine = windowErrorAfterDisplacedMarginalisation(1e-5, 1e-3);
  EXPECT_LT(fine, 5e-5);
  EXPECT_GT(coarse / fine, 30.0);
}

TEST(MarginalizeVertex, WithResidualsTheErrorIsFirstOrderInTheDisplacementTimesTheResidual) {
  // With 1-σ residuals the Gauss–Newton Hessian misses Σ rᵢ∇²rᵢ, so the error is O(|r|·η) (measured
  // 1.9e-3 for η = 1e-3): the reason the Localizer marginalises keyframes only after they have been
  // optimised in many windows, near their optimum.
  EXPECT_LT(windowErrorAfterDisplacedMarginalisation(1e-2, 1e-3), 5e-3);
}

TEST(MarginalizeVertex, ErrorsLeaveTheGraphUnchanged) {
  Graph graph;
  buildChain(graph, 3);
  const size_t edges = graph.numEdges();
  EXPECT_EQ(marginalizeVertex(graph, 77).status().code(), StatusCode::kNotFound);
  ASSERT_TRUE(graph.setFixed(1, true).ok());
  EXPECT_EQ(marginalizeVertex(graph, 1).status().code(), StatusCode::kInvalidArgument);
  // A pose seen by one point observation only: 3 rows for 6 unknowns.
  addPose(graph, 50, Eigen::Isometry3d::Identity());
  ASSERT_TRUE(addPointObservationEdge(graph, 50, 101, Eigen::Vector3d(1, 2, 3), Eigen::Matrix3d::Identity()).ok());
  const Result<MarginalizationOutcome> undetermined = marginalizeVertex(graph, 50);
  EXPECT_EQ(undetermined.status().code(), StatusCode::kNotPositiveDefinite);
  EXPECT_NE(undetermined.status().message().find("vertex 50"), std::string::npos);
  auto se2 = std::make_unique<VertexSE2>(60);
  ASSERT_TRUE(graph.addVertex(std::move(se2)).ok());
  EXPECT_EQ(marginalizeVertex(graph, 60).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(graph.numEdges(), edges + 1);
  EXPECT_FALSE(graph.vertex(50)->fixed());
}

}  // namespace
}  // namespace dualgraph
