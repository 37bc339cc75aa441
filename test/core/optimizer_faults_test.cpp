// SPDX-License-Identifier: MIT
// Numeric faults in the optimiser, with both algorithms and both real linear solvers: gauge
// freedom, a disconnected unanchored component, all vertices fixed, a NaN error or Jacobian at the
// start, a system that is not positive definite at any damping level, divergent steps. Each ends
// with a stated termination reason and the estimate bit-identical to the last accepted state.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dualgraph/core/optimizer.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "test/core/optimizer_faults_fixtures.h"
#include "test/core/optimizer_fixtures.h"

namespace dualgraph {
namespace {

using namespace dualgraph::testing;

struct Config {
  Algorithm algorithm;
  LinearSolverKind linear;
};

class OptimizerFaults : public ::testing::TestWithParam<Config> {
 protected:
  bool lm() const { return GetParam().algorithm == Algorithm::kLevenbergMarquardt; }
  OptimizerParams params() const {
    OptimizerParams p;
    p.algorithm = GetParam().algorithm;
    // Records the state after every accepted iteration: the "last good state" the optimiser
    // must end at.
    p.callback = [this](const IterationSummary& it) {
      if (it.step_accepted) last_accepted_ = stateBits(*graph_);
    };
    return p;
  }
  SolverSummary optimize() { return optimize(params()); }
  SolverSummary optimize(const OptimizerParams& p) {
    last_accepted_ = stateBits(*graph_);
    Optimizer optimizer(*graph_, makeLinearSolver(GetParam().linear));
    return optimizer.optimize(p);
  }

  std::unique_ptr<Graph> graph_ = std::make_unique<Graph>();
  mutable StateBits last_accepted_;
};

std::string describe(const SolverSummary& s) {
  return std::string(terminationReasonName(s.termination)) + ": " + s.message;
}

TEST_P(OptimizerFaults, GaugeFreedomIsFixedByTheDampingOfLmAndStopsGaussNewton) {
  addSe3Ring(*graph_, 0, 12, 3, /*fix_first=*/false);
  const StateBits start = stateBits(*graph_);
  const SolverSummary summary = optimize();
  if (lm()) {
    EXPECT_EQ(summary.termination, TerminationReason::kConverged) << describe(summary);
    EXPECT_LT(summary.final_chi2, 1e-12 * summary.initial_chi2);
    EXPECT_TRUE(sameBits(stateBits(*graph_), last_accepted_));
  } else {
    EXPECT_EQ(summary.termination, TerminationReason::kNotPositiveDefinite) << describe(summary);
    EXPECT_FALSE(summary.usable());
    EXPECT_TRUE(sameBits(stateBits(*graph_), start));
    EXPECT_EQ(summary.final_chi2, summary.initial_chi2);
  }
}

TEST_P(OptimizerFaults, DisconnectedUnanchoredComponent) {
  addSe3Ring(*graph_, 0, 8, 5, /*fix_first=*/true);
  addSe3Ring(*graph_, 100, 6, 6, /*fix_first=*/false);
  const StateBits start = stateBits(*graph_);
  const SolverSummary summary = optimize();
  if (lm()) {
    EXPECT_EQ(summary.termination, TerminationReason::kConverged) << describe(summary);
    EXPECT_LT(summary.final_chi2, 1e-12 * summary.initial_chi2);
    EXPECT_TRUE(sameBits(stateBits(*graph_), last_accepted_));
  } else {
    EXPECT_EQ(summary.termination, TerminationReason::kNotPositiveDefinite) << describe(summary);
    EXPECT_TRUE(sameBits(stateBits(*graph_), start));
  }
}

TEST_P(OptimizerFaults, AllVerticesFixedIsNothingToOptimize) {
  addSe3Ring(*graph_, 0, 5, 7, /*fix_first=*/true);
  for (const auto& [id, vertex] : graph_->vertices()) vertex->setFixed(true);
  const StateBits start = stateBits(*graph_);
  const SolverSummary summary = optimize();
  EXPECT_EQ(summary.termination, TerminationReason::kNothingToOptimize) << describe(summary);
  EXPECT_FALSE(summary.usable());
  EXPECT_EQ(summary.iterations, 0);
  EXPECT_EQ(summary.factorizations, 0);
  EXPECT_GT(summary.initial_chi2, 0.0);
  EXPECT_EQ(summary.final_chi2, summary.initial_chi2);
  EXPECT_TRUE(sameBits(stateBits(*graph_), start));
}

TEST_P(OptimizerFaults, NaNErrorAtTheStartIsInvalidInput) {
  addSe3Ring(*graph_, 0, 6, 8, /*fix_first=*/true);
  auto* edge = static_cast<EdgeSE3*>(graph_->edges()[2].get());
  Eigen::Isometry3d z = edge->measurement();
  z.translation().y() = std::nan("");
  edge->setMeasurement(z);
  edge->setSourceLine(41);
  const StateBits start = stateBits(*graph_);
  const SolverSummary summary = optimize();
  EXPECT_EQ(summary.termination, TerminationReason::kInvalidInput) << describe(summary);
  EXPECT_NE(summary.message.find("vertices 2 3 (line 41)"), std::string::npos) << summary.message;
  EXPECT_EQ(summary.factorizations, 0);
  EXPECT_TRUE(sameBits(stateBits(*graph_), start));
}

TEST_P(OptimizerFaults, NaNJacobianWithAFiniteErrorIsANumericalFailureWithoutRetries) {
  addPoint(*graph_, 0, {0, 0}, true);
  addPoint(*graph_, 1, {1, 1});
  addPoint(*graph_, 2, {2, 0});
  addEdge<EdgePoint2Relative>(*graph_, {0, 1}, {1, 0});
  addEdge<EdgePoint2Relative>(*graph_, {1, 2}, {1, 0});
  addEdge<EdgeNaNJacobianPrior>(*graph_, {2}, {2, 0.5})->setSourceLine(9);
  const StateBits start = stateBits(*graph_);
  const SolverSummary summary = optimize();
  EXPECT_EQ(summary.termination, TerminationReason::kNumericalFailure) << describe(summary);
  EXPECT_FALSE(summary.usable());
  EXPECT_NE(summary.message.find("vertex 2"), std::string::npos) << summary.message;
  EXPECT_EQ(summary.factorizations, 1) << "damping cannot repair a NaN: no retries";
  EXPECT_TRUE(sameBits(stateBits(*graph_), start));
}

TEST_P(OptimizerFaults, IndefiniteSystemAtEveryDampingLevelIsNotPositiveDefinite) {
  // Ω = [[0, 1], [1, 0]] has eigenvalues ±1 and a zero diagonal: λ starts at τ·1e-12 and its
  // growth over max_trials (×2⁵⁵) never reaches 1.
  addPoint(*graph_, 0, {0.5, -0.25});
  Eigen::Matrix2d information;
  information << 0, 1, 1, 0;
  addEdge<EdgePoint2Prior>(*graph_, {0}, {1, 1}, information);
  const StateBits start = stateBits(*graph_);
  const SolverSummary summary = optimize();
  EXPECT_EQ(summary.termination, TerminationReason::kNotPositiveDefinite) << describe(summary);
  EXPECT_FALSE(summary.usable());
  EXPECT_EQ(summary.factorizations, lm() ? OptimizerParams{}.max_trials : 1);
  EXPECT_EQ(summary.final_chi2, summary.initial_chi2);
  EXPECT_TRUE(sameBits(stateBits(*graph_), start));
  expectCleanStacks(*graph_);
}

TEST_P(OptimizerFaults, StepsThatAllDivergeLeaveTheStartAsNoDecrease) {
  const Eigen::Vector2d start_point(1, 2);
  addPoint(*graph_, 0, start_point);
  auto edge = std::make_unique<EdgeNaNWhenMoved>(start_point);
  ASSERT_TRUE(edge->setVertex(0, graph_->vertex(0)).ok());
  edge->setMeasurement({0, 0});
  ASSERT_TRUE(graph_->addEdge(std::move(edge)).ok());
  const StateBits start = stateBits(*graph_);
  const SolverSummary summary = optimize();
  EXPECT_EQ(summary.termination, TerminationReason::kNoDecrease) << describe(summary);
  EXPECT_TRUE(summary.usable()) << "the start is a usable (if unimproved) estimate";
  EXPECT_EQ(summary.factorizations, lm() ? OptimizerParams{}.max_trials : 1);
  EXPECT_EQ(summary.final_chi2, summary.initial_chi2);
  EXPECT_TRUE(sameBits(stateBits(*graph_), start));
  EXPECT_TRUE(std::isfinite(graph_->edges()[0]->chi2())) << "stored errors are those of the kept estimate";
  expectCleanStacks(*graph_);
}

TEST_P(OptimizerFaults, DivergentStepEndsAtTheLastAcceptedState) {
  addPoint(*graph_, 0, {1.9, 0});
  addEdge<EdgeNaNBeyondRadius2>(*graph_, {0}, {5, 0});
  OptimizerParams p = params();
  p.initial_lambda = 1e-9;  // the first, nearly undamped step lands at |p| = 5: NaN
  const StateBits start = stateBits(*graph_);
  const SolverSummary summary = optimize(p);
  EXPECT_TRUE(summary.usable()) << describe(summary);
  EXPECT_TRUE(sameBits(stateBits(*graph_), last_accepted_));
  EXPECT_TRUE(std::isfinite(summary.final_chi2));
  EXPECT_LT(pointOf(*graph_, 0).norm(), 2.0);
  if (lm()) {
    EXPECT_GT(pointOf(*graph_, 0).x(), 1.9) << "LM retried with more damping and moved";
  } else {
    EXPECT_EQ(summary.termination, TerminationReason::kNoDecrease) << describe(summary);
    EXPECT_TRUE(sameBits(stateBits(*graph_), start));
  }
  expectCleanStacks(*graph_);
}

TEST_P(OptimizerFaults, FiniteDivergenceOfGaussNewtonKeepsThePreviousEstimate) {
  addPoint(*graph_, 0, {1.5, 0});
  addEdge<EdgeAtanPrior>(*graph_, {0}, {0, 0});
  const StateBits start = stateBits(*graph_);
  const SolverSummary summary = optimize();
  if (lm()) {
    EXPECT_TRUE(summary.usable()) << describe(summary);
    EXPECT_LT(summary.final_chi2, 1e-12);
    EXPECT_TRUE(sameBits(stateBits(*graph_), last_accepted_));
  } else {
    EXPECT_EQ(summary.termination, TerminationReason::kNoDecrease) << describe(summary);
    EXPECT_NE(summary.message.find("above the start"), std::string::npos) << summary.message;
    EXPECT_TRUE(sameBits(stateBits(*graph_), start));
    EXPECT_EQ(summary.final_chi2, summary.initial_chi2);
  }
  expectCleanStacks(*graph_);
}

INSTANTIATE_TEST_SUITE_P(
    AlgorithmsAndSolvers, OptimizerFaults,
    ::testing::Values(Config{Algorithm::kLevenbergMarquardt, LinearSolverKind::kCholmod},
                      Config{Algorithm::kLevenbergMarquardt, LinearSolverKind::kEigen},
                      Config{Algorithm::kGaussNewton, LinearSolverKind::kCholmod},
                      Config{Algorithm::kGaussNewton, LinearSolverKind::kEigen}),
    [](const ::testing::TestParamInfo<Config>& info) {
      return std::string(info.param.algorithm == Algorithm::kGaussNewton ? "GaussNewton" : "LevenbergMarquardt") +
             (info.param.linear == LinearSolverKind::kCholmod ? "Cholmod" : "Eigen");
    });

}  // namespace
}  // namespace dualgraph
