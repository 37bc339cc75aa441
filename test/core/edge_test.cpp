// SPDX-License-Identifier: MIT
// VertexBase/BaseVertex (increment, estimate stack) and EdgeBase/BaseEdge (χ², numeric
// Jacobians, information validity and repair, slot typing).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "dualgraph/core/edge.h"
#include "test/core/test_fixtures.h"
#include "test/testing/jacobian_check.h"

namespace dualgraph {
namespace {

using testing::EdgePoint2Prior;
using testing::EdgePoint2Range;
using testing::EdgePoint2Relative;
using testing::VertexPoint2;
using testing::VertexVector;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(BaseVertex, PlusAddsTheIncrementAndTheStackRestoresEstimates) {
  VertexPoint2 v(3);
  EXPECT_EQ(v.id(), 3);
  EXPECT_EQ(v.tangentDim(), 2);
  EXPECT_FALSE(v.fixed());
  v.setEstimate({1, 2});
  const double delta[] = {0.5, -1.0};
  v.push();
  v.plus(delta);
  EXPECT_EQ(v.estimate(), Eigen::Vector2d(1.5, 1.0));
  v.push();
  v.plus(delta);
  EXPECT_EQ(v.stackSize(), 2u);
  v.pop();
  EXPECT_EQ(v.estimate(), Eigen::Vector2d(1.5, 1.0));
  v.discardTop();
  EXPECT_EQ(v.estimate(), Eigen::Vector2d(1.5, 1.0)) << "discardTop keeps the current estimate";
  EXPECT_EQ(v.stackSize(), 0u);
}

TEST(BaseVertex, PopOrDiscardOnAnEmptyStackIsAContractViolation) {
  VertexPoint2 v(0);
  EXPECT_THROW(v.pop(), ContractViolation);
  EXPECT_THROW(v.discardTop(), ContractViolation);
}

TEST(BaseEdge, SetVertexChecksTheSlotAndTheVertexType) {
  EdgePoint2Relative edge;
  VertexPoint2 p(1);
  VertexVector<2> wrong(2);  // same tangent dimension, different type
  EXPECT_EQ(edge.numVertices(), 2u);
  EXPECT_EQ(edge.errorDim(), 2);
  EXPECT_TRUE(edge.setVertex(0, &p).ok());
  EXPECT_EQ(edge.vertex(0), &p);
  const Status wrong_type = edge.setVertex(1, &wrong);
  EXPECT_EQ(wrong_type.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(testing::contains(wrong_type.message(), "vertex 2"));
  EXPECT_EQ(edge.vertex(1), nullptr);
  EXPECT_EQ(edge.setVertex(2, &p).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(edge.setVertex(0, nullptr).ok()) << "a slot can be cleared";
  EXPECT_EQ(edge.vertex(0), nullptr);
  EXPECT_THROW((void)edge.vertex(2), std::out_of_range);
}

TEST(EdgeBase, Chi2IsErrorTransposeInformationError) {
  VertexPoint2 a(0);
  VertexPoint2 b(1);
  a.setEstimate({0.5, -1.0});
  b.setEstimate({2.0, 3.0});
  EdgePoint2Relative edge;
  ASSERT_TRUE(edge.setVertex(0, &a).ok());
  ASSERT_TRUE(edge.setVertex(1, &b).ok());
  edge.setMeasurement({1.0, 1.0});
  Eigen::Matrix2d information;
  information << 3.0, -0.7, -0.7, 2.0;
  edge.setInformation(information);
  edge.computeError();
  const Eigen::Vector2d e(0.5, 3.0);  // (b − a) − z
  EXPECT_EQ(edge.error(), e);
  const double expected = e.transpose() * information * e;
  EXPECT_DOUBLE_EQ(edge.chi2(), expected);
  const EdgeBase& as_base = edge;
  EXPECT_DOUBLE_EQ(as_base.chi2(), expected);
  EXPECT_DOUBLE_EQ(as_base.EdgeBase::chi2(), expected) << "the generic and the fixed-size χ² agree";
  EXPECT_DOUBLE_EQ(edge.robustChi2(), expected) << "no kernel";
  edge.setRobustKernel(*makeRobustKernel("cauchy:1"));
  EXPECT_DOUBLE_EQ(edge.robustChi2(), std::log1p(expected));
  EXPECT_DOUBLE_EQ(edge.chi2(), expected) << "chi2() ignores the kernel";
}

/// Relative and prior edges at random states: analytic blocks equal central differences.
TEST(EdgePoint2Relative, AnalyticJacobianMatchesNumeric) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 5.0);
  for (int trial = 0; trial < 100; ++trial) {
    VertexPoint2 a(0);
    VertexPoint2 b(1);
    a.setEstimate({normal(rng), normal(rng)});
    b.setEstimate({normal(rng), normal(rng)});
    EdgePoint2Relative edge;
    ASSERT_TRUE(edge.setVertex(0, &a).ok());
    ASSERT_TRUE(edge.setVertex(1, &b).ok());
    edge.setMeasurement({normal(rng), normal(rng)});
    edge.linearize();
    Eigen::Matrix2d numeric;
    for (size_t slot = 0; slot < 2; ++slot) {
      edge.numericJacobian(slot, numeric.data());
      const Eigen::Map<const Eigen::Matrix2d> analytic(edge.jacobianData(slot));
      EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff(), 1e-8)
          << "slot " << slot << "\nanalytic\n" << analytic << "\nnumeric\n" << numeric;
    }
    EXPECT_EQ(edge.jacobianOplus<0>(), -Eigen::Matrix2d::Identity());
    EXPECT_EQ(edge.jacobianOplus<1>(), Eigen::Matrix2d::Identity());
    EXPECT_TRUE(testing::analyticJacobiansMatchNumeric(edge));
  }
}

TEST(EdgePoint2Prior, AnalyticJacobianMatchesNumeric) {
  VertexPoint2 a(0);
  a.setEstimate({-3.0, 7.5});
  EdgePoint2Prior edge;
  ASSERT_TRUE(edge.setVertex(0, &a).ok());
  edge.setMeasurement({1, 1});
  EXPECT_TRUE(testing::analyticJacobiansMatchNumeric(edge));
  EXPECT_EQ(edge.jacobianOplus<0>(), Eigen::Matrix2d::Identity());
}

TEST(EdgePoint2Range, NumericFallbackEqualsTheClosedFormJacobian) {
  std::mt19937 rng(12);
  std::normal_distribution<double> normal(0.0, 3.0);
  for (int trial = 0; trial < 100; ++trial) {
    VertexPoint2 a(0);
    VertexPoint2 b(1);
    a.setEstimate({normal(rng), normal(rng)});
    b.setEstimate({normal(rng), normal(rng)});
    EdgePoint2Range edge;
    ASSERT_TRUE(edge.setVertex(0, &a).ok());
    ASSERT_TRUE(edge.setVertex(1, &b).ok());
    edge.setMeasurement(2.0);
    edge.linearize();  // no linearizeOplus override: central differences
    const Eigen::Vector2d d = b.estimate() - a.estimate();
    EXPECT_NEAR(edge.error()[0], d.norm() - 2.0, 1e-15 * (1 + d.norm()));
    const Eigen::RowVector2d u = d.normalized().transpose();
    const Eigen::Map<const Eigen::RowVector2d> j0(edge.jacobianData(0));
    const Eigen::Map<const Eigen::RowVector2d> j1(edge.jacobianData(1));
    EXPECT_LT((j0 + u).cwiseAbs().maxCoeff(), 1e-7) << j0 << " vs " << -u;
    EXPECT_LT((j1 - u).cwiseAbs().maxCoeff(), 1e-7) << j1 << " vs " << u;
  }
}

TEST(EdgeBase, NumericJacobianLeavesEstimatesErrorAndStacksUntouched) {
  VertexPoint2 a(0);
  VertexPoint2 b(1);
  a.setEstimate({0.1, 0.2});
  b.setEstimate({1.3, -0.4});
  EdgePoint2Range edge;
  ASSERT_TRUE(edge.setVertex(0, &a).ok());
  ASSERT_TRUE(edge.setVertex(1, &b).ok());
  edge.setMeasurement(0.5);
  edge.computeError();
  const double error_before = edge.error()[0];
  Eigen::RowVector2d jacobian;
  edge.numericJacobian(1, jacobian.data(), 1e-4);
  EXPECT_EQ(a.estimate(), Eigen::Vector2d(0.1, 0.2));
  EXPECT_EQ(b.estimate(), Eigen::Vector2d(1.3, -0.4));
  EXPECT_EQ(a.stackSize(), 0u);
  EXPECT_EQ(b.stackSize(), 0u);
  EXPECT_EQ(edge.error()[0], error_before);
}

Eigen::Matrix2d matrix2(double a, double b, double c, double d) {
  Eigen::Matrix2d m;
  m << a, b, c, d;
  return m;
}

TEST(EdgeBase, InformationIsValidOnlyForFiniteSymmetricPositiveDefinite) {
  EdgePoint2Prior edge;
  struct Case {
    const char* what;
    Eigen::Matrix2d information;
    bool valid;
  };
  const Case cases[] = {
      {"identity", Eigen::Matrix2d::Identity(), true},
      {"correlated SPD", matrix2(4, 1.9, 1.9, 1), true},
      {"tiny but SPD", 1e-200 * Eigen::Matrix2d::Identity(), true},
      {"NaN", matrix2(1, 0, 0, kNaN), false},
      {"NaN off-diagonal", matrix2(1, kNaN, kNaN, 1), false},
      {"Inf", matrix2(kInf, 0, 0, 1), false},
      {"non-symmetric", matrix2(2, 0.5, 0.4, 2), false},
      {"indefinite", matrix2(1, 0, 0, -1), false},
      {"indefinite, positive diagonal", matrix2(1, 2, 2, 1), false},
      {"negative definite", -Eigen::Matrix2d::Identity(), false},
      {"semidefinite", matrix2(1, 1, 1, 1), false},
      {"zero", Eigen::Matrix2d::Zero(), false},
  };
  for (const Case& c : cases) {
    edge.setInformation(c.information);
    EXPECT_EQ(edge.informationIsValid(), c.valid) << c.what << "\n" << c.information;
  }
}

TEST(EdgeBase, RepairInformationMakesInvalidMatricesValid) {
  EdgePoint2Prior edge;
  const std::vector<Eigen::Matrix2d> invalid = {matrix2(2, 0.5, 0.4, 2), matrix2(1, 0, 0, -1),
                                                matrix2(1, 2, 2, 1),        -Eigen::Matrix2d::Identity(),
                                                matrix2(1, 1, 1, 1),        Eigen::Matrix2d::Zero()};
  for (const Eigen::Matrix2d& bad : invalid) {
    edge.setInformation(bad);
    ASSERT_FALSE(edge.informationIsValid());
    EXPECT_TRUE(edge.repairInformation()) << bad;
    EXPECT_TRUE(edge.informationIsValid()) << "repaired from\n" << bad << "\nto\n" << edge.information();
    EXPECT_EQ(edge.information(), edge.information().transpose()) << "exactly symmetric";
    EXPECT_TRUE(edge.information().allFinite());
  }
}

TEST(EdgeBase, RepairInformationKeepsThePositiveEigenDirections) {
  EdgePoint2Prior edge;
  edge.setInformation(matrix2(1, 0, 0, -1));
  ASSERT_TRUE(edge.repairInformation(1e-6));
  EXPECT_NEAR(edge.information()(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(edge.information()(0, 1), 0.0, 1e-12);
  EXPECT_NEAR(edge.information()(1, 1), 1e-6, 1e-12) << "clamped to the relative floor";

  edge.setInformation(matrix2(2, 0.6, 0.4, 3));  // symmetric part SPD: repair symmetrises only
  ASSERT_TRUE(edge.repairInformation());
  EXPECT_LT((edge.information() - matrix2(2, 0.5, 0.5, 3)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(EdgeBase, RepairInformationLeavesAValidMatrixBitIdentical) {
  std::mt19937 rng(13);
  EdgePoint2Relative edge;
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix2d information = testing::randomInformation<2>(rng, 3.0);
    edge.setInformation(information);
    ASSERT_TRUE(edge.informationIsValid());
    EXPECT_FALSE(edge.repairInformation());
    EXPECT_EQ(edge.information(), information);
  }
}

TEST(EdgeBase, RepairInformationCannotRepairNonFiniteMatrices) {
  EdgePoint2Prior edge;
  edge.setInformation(matrix2(1, 0, 0, kNaN));
  EXPECT_FALSE(edge.repairInformation());
  EXPECT_FALSE(edge.informationIsValid());
}

TEST(EdgeBase, SourceLineDefaultsToZero) {
  EdgePoint2Prior edge;
  EXPECT_EQ(edge.sourceLine(), 0);
  edge.setSourceLine(17);
  EXPECT_EQ(edge.sourceLine(), 17);
}

}  // namespace
}  // namespace dualgraph
