// SPDX-License-Identifier: MIT
// The block solver (temp_solver: block, the default) against the generic Optimizer path (temp_solver:
// graph), its oracle: the same distilled edges on seeded keyframe intervals with pose and point gates,
// the Localizer's robust kernel, an outlier, a gate seen only at the keyframe instant and one seen by one
// node only; and the same skipped count when a gate's marginal is not positive definite. The block solver
// with the AVX2 + FMA kernels against itself with the baseline ones.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <random>
#include <vector>

#include "dualgraph/core/optimizer.h"
#include "dualgraph/dual_graph/edge_factories.h"
#include "dualgraph/dual_graph/temporary_graph.h"
#include "dualgraph/solvers/block/block_lm_solver.h"
#include "dualgraph/solvers/block/block_kernels_avx2.h"
#include "dualgraph/solvers/eigen_solver.h"
#include "dualgraph/solvers/marginal_covariance.h"
#include "test/dual_graph/distillation_fixtures.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

struct Interval {
  OdometryHistory history;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> odom_T_body;  // per sample
  std::vector<GateObservation> observations;  // time order
  std::vector<size_t> sample_of;              // per observation
  double t_keyframe = 0.0;
};

/// `samples` VIO samples 0.3 m apart along a gentle curve, drifting; gates 0..`gates`-1 ahead of the path,
/// each seen from a sliding window of samples with 3 cm / 0.01 rad noise (seeded). Gate `gates` (extra) is
/// seen only at the keyframe instant, gate `gates`+1 by one sample only, and one observation of gate 1 is
/// an outlier (1.5 m off). The last sample is the keyframe.
Interval makeInterval(int samples, int gates, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Interval interval;
  std::vector<Matrix6d> covariances;
  for (int k = 0; k < samples; ++k) {
    Vector6d xi;
    xi << 0.3 * k, 0.02 * k * k / samples, 0.01 * normal(rng), 0.01 * normal(rng), 0.01 * normal(rng), 0.2 * k / samples;
    interval.odom_T_body.push_back(se3Exp(xi));
    covariances.push_back(randomCovariance<6>(1e-4));
  }
  interval.history = makeHistory({interval.odom_T_body.begin(), interval.odom_T_body.end()}, covariances);
  interval.t_keyframe = samples - 1;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> odom_T_gate;
  for (int g = 0; g < gates + 2; ++g) {
    Vector6d xi;
    xi << 1.0 + 0.3 * samples * g / gates, (g % 2 == 0 ? 1.5 : -1.5), 1.0, 0.1 * g, 0.0, 0.3;
    odom_T_gate.push_back(se3Exp(xi));
  }
  const Matrix6d detection_covariance = randomCovariance<6>(1e-3);
  auto observe = [&](size_t k, int g, double offset) {
    Vector6d noise;
    for (int i = 0; i < 6; ++i) noise[i] = normal(rng) * (i < 3 ? 0.03 : 0.01);
    noise[0] += offset;
    const Eigen::Isometry3d body_T_gate = interval.odom_T_body[k].inverse() * odom_T_gate[g] * se3Exp(noise);
    interval.observations.push_back(GateObservation::pose(static_cast<double>(k), g, body_T_gate, detection_covariance));
    interval.sample_of.push_back(k);
  };
  for (int k = 0; k + 1 < samples; ++k) {
    const int first = k * gates / samples;
    for (int g = first; g < std::min(gates, first + 3); ++g) observe(k, g, g == 1 && k == 2 * samples / gates ? 1.5 : 0.0);
    if (k == samples / 2) observe(k, gates + 1, 0.0);  // one node only
  }
  observe(samples - 1, gates, 0.0);  // at the keyframe instant only
  observe(samples - 1, gates - 1, 0.0);
  return interval;
}

DistillationResult distil(const Interval& interval, LocalizerParams params, TemporarySolverKind kind) {
  params.temp_solver = kind;
  Result<std::shared_ptr<const RobustKernel>> kernel =
      params.robust_kernel == "none" ? Result<std::shared_ptr<const RobustKernel>>(nullptr) : makeRobustKernel(params.robust_kernel);
  EXPECT_TRUE(kernel.ok());
  TemporaryGraph temporary(params, *kernel);
  for (size_t i = 0; i < interval.observations.size(); ++i) {
    const Status added = temporary.addObservation(interval.observations[i], interval.odom_T_body[interval.sample_of[i]],
                                                  interval.history);
    EXPECT_TRUE(added.ok()) << added.message();
  }
  return temporary.distil(interval.t_keyframe, interval.odom_T_body.back(), interval.history);
}

void expectSameDistillation(const DistillationResult& block, const DistillationResult& graph, LandmarkModel model) {
  EXPECT_EQ(block.skipped_gates, graph.skipped_gates) << block.skip_reason << " | " << graph.skip_reason;
  EXPECT_EQ(block.nodes, graph.nodes);
  EXPECT_EQ(block.edges, graph.edges);
  EXPECT_EQ(block.iterations, graph.iterations);
  ASSERT_EQ(block.gates.size(), graph.gates.size());
  for (size_t g = 0; g < graph.gates.size(); ++g) {
    const GateEdgeMeasurement& a = block.gates[g];
    const GateEdgeMeasurement& b = graph.gates[g];
    SCOPED_TRACE("gate " + std::to_string(b.gate_id));
    EXPECT_EQ(a.gate_id, b.gate_id);
    EXPECT_EQ(a.observations, b.observations);
    if (model == LandmarkModel::kPose) {
      EXPECT_LE(relativeDifference(a.node_T_gate.matrix(), b.node_T_gate.matrix()), 1e-6);
      EXPECT_LE(relativeDifference(a.pose_information, b.pose_information), 1e-6)
          << "block:\n" << a.pose_information << "\ngraph:\n" << b.pose_information;
    } else {
      EXPECT_LE(relativeDifference(a.p_node, b.p_node), 1e-6);
      EXPECT_LE(relativeDifference(a.point_information, b.point_information), 1e-6)
          << "block:\n" << a.point_information << "\ngraph:\n" << b.point_information;
    }
  }
}

class TemporarySolverAgreement : public ::testing::TestWithParam<std::tuple<LandmarkModel, unsigned>> {};

TEST_P(TemporarySolverAgreement, BlockAndGraphGiveTheSameDistilledEdges) {
  const auto [model, seed] = GetParam();
  LocalizerParams params;  // the Localizer's defaults: huber:3, diagonal damping, 1e-4 stop
  params.landmark = model;
  const Interval interval = makeInterval(40, 6, seed);
  const DistillationResult block = distil(interval, params, TemporarySolverKind::kBlock);
  const DistillationResult graph = distil(interval, params, TemporarySolverKind::kGraph);
  EXPECT_EQ(graph.skipped_gates, 0) << graph.skip_reason;
  EXPECT_EQ(graph.gates.size(), 8u);  // 6 + the keyframe-only gate + the one-node gate
  expectSameDistillation(block, graph, model);
}

TEST_P(TemporarySolverAgreement, SameEdgesWithG2oDampingAndTukey) {
  const auto [model, seed] = GetParam();
  LocalizerParams params;
  params.landmark = model;
  params.lm_damping = LmDamping::kIdentity;
  params.robust_kernel = "tukey:4";
  params.d_temp = 0.5;  // several detections re-expressed in one node (motion compensation)
  const Interval interval = makeInterval(30, 5, seed + 100);
  expectSameDistillation(distil(interval, params, TemporarySolverKind::kBlock),
                         distil(interval, params, TemporarySolverKind::kGraph), model);
}

TEST_P(TemporarySolverAgreement, BaselineAndAvx2KernelsGiveTheSameDistilledEdges) {
  const auto [model, seed] = GetParam();
  if (!block_kernels_avx2::setEnabled(true)) GTEST_SKIP() << "this CPU has no AVX2 + FMA";
  LocalizerParams params;
  params.landmark = model;
  const Interval interval = makeInterval(40, 6, seed + 200);
  const DistillationResult avx2 = distil(interval, params, TemporarySolverKind::kBlock);
  block_kernels_avx2::setEnabled(false);
  const DistillationResult baseline = distil(interval, params, TemporarySolverKind::kBlock);
  block_kernels_avx2::setEnabled(true);
  EXPECT_EQ(baseline.skipped_gates, 0) << baseline.skip_reason;
  expectSameDistillation(avx2, baseline, model);
}

INSTANTIATE_TEST_SUITE_P(PoseAndPoint, TemporarySolverAgreement,
                         ::testing::Combine(::testing::Values(LandmarkModel::kPose, LandmarkModel::kPoint),
                                            ::testing::Values(1u, 2u, 3u)));

TEST(BlockLmSolver, NotPositiveDefiniteMarginalIsSkippedAsByTheGraphPath) {
  // The keyframe-only gate's one detection has a rotation variance 2e-12 of its translation's: the input
  // check (smallest eigenvalue > 1e-12 · largest) accepts it, but in the distilled edge's g2o units
  // (q.vec ≈ θ/2) the ratio is 5e-13, so that gate's marginal is refused and counted as skipped; the
  // other gates are distilled.
  LocalizerParams params;
  Interval interval = makeInterval(20, 4, 9);
  Matrix6d covariance = Matrix6d::Identity();
  covariance(4, 4) = 2e-12;
  for (GateObservation& observation : interval.observations) {
    if (observation.gate_id == 4) observation.pose_covariance = covariance;  // the keyframe-only gate
  }
  const DistillationResult graph = distil(interval, params, TemporarySolverKind::kGraph);
  const DistillationResult block = distil(interval, params, TemporarySolverKind::kBlock);
  EXPECT_EQ(graph.skipped_gates, 1) << graph.skip_reason;
  EXPECT_NE(graph.skip_reason.find("distilled covariance of gate 4 is not positive definite"), std::string::npos)
      << graph.skip_reason;
  EXPECT_EQ(block.skip_reason, graph.skip_reason);
  expectSameDistillation(block, graph, LandmarkModel::kPose);
}

TEST(BlockLmSolver, CholmodAlwaysTakesTheGraphPath) {
  // linear_solver: cholmod with temp_solver: block still runs the generic optimiser: same result as graph.
  LocalizerParams params;
  params.linear_solver = LinearSolverKind::kCholmod;
  const Interval interval = makeInterval(20, 4, 4);
  const DistillationResult block = distil(interval, params, TemporarySolverKind::kBlock);
  const DistillationResult graph = distil(interval, params, TemporarySolverKind::kGraph);
  ASSERT_EQ(block.gates.size(), graph.gates.size());
  for (size_t g = 0; g < graph.gates.size(); ++g) {
    EXPECT_EQ(block.gates[g].pose_information, graph.gates[g].pose_information);  // bit for bit: one path
  }
}

/// A small pose graph: a chain 0..5 with odometry, loop closures and a noisy start, vertex 6 fixed.
void buildChain(Graph& graph, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> truth;
  for (int k = 0; k < 7; ++k) {
    Vector6d xi;
    xi << k, 0.3 * k, 0.0, 0.0, 0.0, 0.4 * k;
    truth.push_back(se3Exp(xi));
    Vector6d noise;
    for (int i = 0; i < 6; ++i) noise[i] = 0.1 * normal(rng);
    auto vertex = std::make_unique<VertexSE3>(k);
    vertex->setEstimate(k == 6 ? truth[k] : truth[k] * se3Exp(noise));
    vertex->setFixed(k == 6);
    ASSERT_TRUE(graph.addVertex(std::move(vertex)).ok());
  }
  // Noisy measurements: χ² ends well above its round-off, so accepting or rejecting a step is decided by
  // the model, not by round-off (on a zero-residual problem the last steps are a coin toss).
  auto noisy = [&](const Eigen::Isometry3d& pose) {
    Vector6d noise;
    for (int i = 0; i < 6; ++i) noise[i] = 0.05 * normal(rng);
    return Eigen::Isometry3d(pose * se3Exp(noise));
  };
  for (int k = 0; k < 6; ++k) {
    ASSERT_TRUE(addRelativePoseEdge(graph, k, k + 1, noisy(truth[k].inverse() * truth[k + 1]), 100.0 * Matrix6d::Identity()).ok());
    if (k + 3 >= 7) continue;
    Matrix6d a;  // a loop closure with a full information matrix, from this seed only
    for (int i = 0; i < 36; ++i) a.data()[i] = normal(rng);
    const Matrix6d information = 50.0 * (a * a.transpose() / 6.0 + 0.3 * Matrix6d::Identity());
    ASSERT_TRUE(addRelativePoseEdge(graph, k, k + 3, noisy(truth[k].inverse() * truth[k + 3]), information).ok());
  }
}

TEST(BlockLmSolver, TakesTheGenericOptimizersStepsAndMarginals) {
  for (const LmDamping damping : {LmDamping::kIdentity, LmDamping::kDiagonal}) {
    Graph block_graph, generic_graph;
    buildChain(block_graph, 5);
    buildChain(generic_graph, 5);
    OptimizerParams params;
    params.damping = damping;
    params.max_iterations = 30;
    BlockLmSolver solver;
    ASSERT_TRUE(solver.setGraph(block_graph).ok());
    const SolverSummary block = solver.optimize(params);
    Optimizer optimizer(generic_graph, std::make_unique<EigenSolver>(EigenOrdering::kNatural));
    const SolverSummary generic = optimizer.optimize(params);
    SCOPED_TRACE(lmDampingName(damping));
    EXPECT_EQ(block.termination, generic.termination) << block.message << " | " << generic.message;
    EXPECT_EQ(block.iterations, generic.iterations);
    EXPECT_EQ(block.factorizations, generic.factorizations);
    EXPECT_LE(std::abs(block.initial_chi2 - generic.initial_chi2), 1e-12 * generic.initial_chi2);
    EXPECT_LE(std::abs(block.final_chi2 - generic.final_chi2), 1e-9 * generic.initial_chi2);
    ASSERT_TRUE(solver.computeMarginals().ok());
    MarginalCovariance marginals;
    ASSERT_TRUE(marginals.compute(optimizer, generic_graph).ok());
    for (int id = 0; id < 6; ++id) {
      EXPECT_LE(relativeDifference(*solver.marginal(id), *marginals.block(id)), 1e-8) << "vertex " << id;
    }
    EXPECT_EQ(solver.marginal(6).status().code(), StatusCode::kFailedPrecondition);  // fixed: not in the system
  }
}

// computeMarginals(ids): the chain's elimination tree is the path 0 → 1 → … → 5, so vertex 3's marginal
// needs Σ of 3, 4 and 5 only; those equal the full computation's bit for bit, the others are not there.
TEST(BlockLmSolver, MarginalsOfChosenVerticesEqualTheFullOnesAndSkipTheRest) {
  Graph reference_graph, graph;  // the subset on a solver that never computed the rest
  buildChain(reference_graph, 5);
  buildChain(graph, 5);
  BlockLmSolver reference, solver;
  ASSERT_TRUE(reference.setGraph(reference_graph).ok());
  ASSERT_TRUE(solver.setGraph(graph).ok());
  OptimizerParams params;
  params.max_iterations = 30;
  ASSERT_TRUE(reference.optimize(params).usable());
  ASSERT_TRUE(solver.optimize(params).usable());
  ASSERT_TRUE(reference.computeMarginals().ok());
  std::vector<Eigen::MatrixXd> full;
  for (int id = 0; id < 6; ++id) full.push_back(*reference.marginal(id));
  ASSERT_TRUE(solver.computeMarginals({3}).ok());
  for (int id = 0; id < 6; ++id) {
    SCOPED_TRACE("vertex " + std::to_string(id));
    const Result<Eigen::MatrixXd> marginal = solver.marginal(id);
    if (id < 3) {
      EXPECT_EQ(marginal.status().code(), StatusCode::kFailedPrecondition);
      continue;
    }
    ASSERT_TRUE(marginal.ok()) << marginal.status().message();
    EXPECT_TRUE((marginal->array() == full[id].array()).all()) << *marginal << "\nfull:\n" << full[id];
  }
  for (const int bad : {6, 7, -1}) {  // fixed, unknown, negative: a status, and no marginals left
    EXPECT_EQ(solver.computeMarginals({3, bad}).code(), StatusCode::kFailedPrecondition) << bad;
    EXPECT_EQ(solver.marginal(3).status().code(), StatusCode::kFailedPrecondition) << bad;
  }
}

// OptimizerParams::model_decrease_stop: the run ends one iteration earlier, at the estimate before the
// confirming step, in both solvers alike; the block solver's marginals then reuse the undamped factor the
// check left, and equal a fresh linearisation's at the same estimate.
TEST(BlockLmSolver, ModelDecreaseStopSavesTheConfirmingIterationAndReusesItsFactor) {
  for (const LmDamping damping : {LmDamping::kIdentity, LmDamping::kDiagonal}) {
    SCOPED_TRACE(lmDampingName(damping));
    OptimizerParams params;
    params.damping = damping;
    params.max_iterations = 30;
    params.relative_decrease_stop = 1e-4;
    Graph reference_graph, block_graph, generic_graph;
    buildChain(reference_graph, 5);
    buildChain(block_graph, 5);
    buildChain(generic_graph, 5);
    BlockLmSolver reference_solver;
    ASSERT_TRUE(reference_solver.setGraph(reference_graph).ok());
    const SolverSummary reference = reference_solver.optimize(params);  // the relative rule alone
    params.model_decrease_stop = 1e-4;
    BlockLmSolver solver;
    ASSERT_TRUE(solver.setGraph(block_graph).ok());
    const SolverSummary block = solver.optimize(params);
    Optimizer optimizer(generic_graph, std::make_unique<EigenSolver>(EigenOrdering::kNatural));
    const SolverSummary generic = optimizer.optimize(params);
    std::printf("[ INFO ] %s: %d iterations, %d factorisations, chi2 %.9g (relative rule alone: %d, %d, %.9g)\n",
                lmDampingName(damping), block.iterations, block.factorizations, block.final_chi2, reference.iterations,
                reference.factorizations, reference.final_chi2);
    EXPECT_EQ(block.termination, TerminationReason::kConverged) << block.message;
    EXPECT_EQ(block.iterations + 1, reference.iterations);
    EXPECT_EQ(block.iterations, generic.iterations);
    EXPECT_EQ(block.factorizations, generic.factorizations);
    EXPECT_LE(std::abs(block.final_chi2 - generic.final_chi2), 1e-9 * generic.initial_chi2);
    // χ² one step short of the relative rule's end, by less than the threshold's share of it.
    EXPECT_GE(block.final_chi2, reference.final_chi2);
    EXPECT_LE(block.final_chi2 - reference.final_chi2, 2 * params.model_decrease_stop * block.final_chi2);
    ASSERT_TRUE(solver.computeMarginals().ok());  // reuses the check's factor
    std::vector<Eigen::MatrixXd> reused;
    for (int id = 0; id < 6; ++id) reused.push_back(*solver.marginal(id));
    ASSERT_TRUE(solver.computeMarginals().ok());  // linearises and factorises again at the same estimate
    MarginalCovariance marginals;
    ASSERT_TRUE(marginals.compute(optimizer, generic_graph).ok());
    for (int id = 0; id < 6; ++id) {
      EXPECT_LE(relativeDifference(reused[id], *solver.marginal(id)), 1e-12) << "vertex " << id;
      EXPECT_LE(relativeDifference(reused[id], *marginals.block(id)), 1e-8) << "vertex " << id;
    }
  }
}

TEST(BlockLmSolver, FaultsAreTerminationsAndStatuses) {
  BlockLmSolver solver;
  EXPECT_EQ(solver.optimize(OptimizerParams{}).termination, TerminationReason::kLinearSolverFailure);  // no graph
  EXPECT_EQ(solver.computeMarginals().code(), StatusCode::kFailedPrecondition);
  Graph graph;
  buildChain(graph, 6);
  ASSERT_TRUE(solver.setGraph(graph).ok());
  EXPECT_EQ(solver.marginal(0).status().code(), StatusCode::kFailedPrecondition);  // not computed yet
  double& information_00 = graph.edges().front()->mutableInformationData()[0];
  const double saved = information_00;
  information_00 = std::nan("");
  const SolverSummary nan = solver.optimize(OptimizerParams{});
  EXPECT_EQ(nan.termination, TerminationReason::kInvalidInput);
  EXPECT_NE(nan.message.find("edge between vertices 0 1"), std::string::npos) << nan.message;
  information_00 = saved;
  for (const auto& [id, vertex] : graph.vertices()) vertex->setFixed(true);
  ASSERT_TRUE(solver.setGraph(graph).ok());
  EXPECT_EQ(solver.optimize(OptimizerParams{}).termination, TerminationReason::kNothingToOptimize);
}

// setProblem's preconditions: vertices in increasing id, and every vertex an edge uses among them
// (also when its id is below the largest one given).
TEST(BlockLmSolver, SetProblemRejectsVerticesOutOfOrderOrNotGiven) {
  Graph graph;
  buildChain(graph, 4);
  std::vector<VertexBase*> vertices;
  std::vector<EdgeBase*> edges;
  for (const auto& [id, vertex] : graph.vertices()) vertices.push_back(vertex.get());
  for (const auto& edge : graph.edges()) edges.push_back(edge.get());
  BlockLmSolver solver;
  ASSERT_TRUE(solver.setProblem(vertices, edges).ok());
  std::vector<VertexBase*> swapped = vertices;
  std::swap(swapped[1], swapped[2]);
  EXPECT_EQ(solver.setProblem(swapped, edges).code(), StatusCode::kFailedPrecondition);
  std::vector<VertexBase*> missing_inside = vertices;
  ASSERT_FALSE(missing_inside[1]->fixed());
  missing_inside[1] = nullptr;  // an edge uses it, its id is below the largest given
  const Status inside = solver.setProblem(missing_inside, edges);
  EXPECT_EQ(inside.code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(inside.message().find("not given"), std::string::npos) << inside.message();
  // Only a fixed vertex given (no block at all) while the edges use free ones below its id.
  std::vector<VertexBase*> only_fixed(vertices.size(), nullptr);
  only_fixed.back() = vertices.back();
  ASSERT_TRUE(only_fixed.back()->fixed());
  EXPECT_EQ(solver.setProblem(only_fixed, edges).code(), StatusCode::kFailedPrecondition);
  std::vector<VertexBase*> missing_last(vertices.begin(), vertices.end() - 1);
  EXPECT_EQ(solver.setProblem(missing_last, edges).code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(solver.optimize(OptimizerParams{}).termination, TerminationReason::kLinearSolverFailure);  // none kept
  // An edge from a free vertex to itself: refused (a fixed one would be harmless, and is accepted).
  EdgeSE3 loop;
  ASSERT_TRUE(loop.setVertex(0, vertices[2]).ok());
  ASSERT_TRUE(loop.setVertex(1, vertices[2]).ok());
  std::vector<EdgeBase*> with_loop = edges;
  with_loop.push_back(&loop);
  const Status twice = solver.setProblem(vertices, with_loop);
  EXPECT_EQ(twice.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(twice.message().find("uses free vertex 2 in two slots"), std::string::npos) << twice.message();
  ASSERT_TRUE(loop.setVertex(0, vertices.back()).ok());
  ASSERT_TRUE(loop.setVertex(1, vertices.back()).ok());
  EXPECT_TRUE(solver.setProblem(vertices, with_loop).ok());
}

}  // namespace
}  // namespace dualgraph
