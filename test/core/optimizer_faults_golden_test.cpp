// SPDX-License-Identifier: MIT
// Gauge freedom on a real pose graph (../shared/data/posegraph/parking-garage.g2o, nothing fixed):
// the factorisation's round-off pivots pass, so Gauss–Newton walks off along the free gauge (χ²
// ≈ 1e15); it must end on the start estimate, bit for bit, as kNoDecrease. Levenberg–Marquardt's
// damping fixes the gauge and reaches g2o's χ² with the gauge fixed.
#include <gtest/gtest.h>

#include <string>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "test/core/optimizer_faults_fixtures.h"
#include "test/testing/shared_data.h"
#include "dualgraph/types/register_types.h"

namespace dualgraph {
namespace {

class UnfixedParkingGarage : public ::testing::TestWithParam<LinearSolverKind> {
 protected:
  void SetUp() override {
    DG_SKIP_WITHOUT_SHARED("data/posegraph/parking-garage.g2o");
    const std::string path = testing::sharedPath("data/posegraph/parking-garage.g2o");
    ASSERT_TRUE(registerBuiltinTypes(registry_).ok());
    const auto report = readG2o(path, registry_, graph_);
    ASSERT_TRUE(report.ok()) << report.status().toString();
    for (const auto& [id, vertex] : graph_.vertices()) ASSERT_FALSE(vertex->fixed()) << "the file fixes no vertex";
  }
  TypeRegistry registry_;
  Graph graph_;
};

TEST_P(UnfixedParkingGarage, GaussNewtonEndsOnTheStartEstimate) {
  const testing::StateBits start = testing::stateBits(graph_);
  OptimizerParams params;
  params.algorithm = Algorithm::kGaussNewton;
  Optimizer optimizer(graph_, makeLinearSolver(GetParam()));
  const SolverSummary summary = optimizer.optimize(params);
  EXPECT_EQ(summary.termination, TerminationReason::kNoDecrease)
      << terminationReasonName(summary.termination) << ": " << summary.message;
  EXPECT_NE(summary.message.find("above the start"), std::string::npos) << summary.message;
  EXPECT_GT(summary.iterations, 1) << "the round-off pivots passed at least once";
  EXPECT_EQ(summary.final_chi2, summary.initial_chi2);
  EXPECT_TRUE(testing::sameBits(testing::stateBits(graph_), start));
  EXPECT_EQ(graph_.chi2(), summary.initial_chi2);
}

TEST_P(UnfixedParkingGarage, LevenbergMarquardtFixesTheGaugeByDamping) {
  Optimizer optimizer(graph_, makeLinearSolver(GetParam()));
  const SolverSummary summary = optimizer.optimize(OptimizerParams{});
  EXPECT_EQ(summary.termination, TerminationReason::kConverged)
      << terminationReasonName(summary.termination) << ": " << summary.message;
  EXPECT_LE(summary.final_chi2, 1.238684 * (1 + 1e-6)) << "g2o's LM result with the gauge fixed";
}

INSTANTIATE_TEST_SUITE_P(Solvers, UnfixedParkingGarage,
                         ::testing::Values(LinearSolverKind::kCholmod, LinearSolverKind::kEigen),
                         [](const ::testing::TestParamInfo<LinearSolverKind>& info) {
                           return std::string(linearSolverKindName(info.param));
                         });

}  // namespace
}  // namespace dualgraph
