// SPDX-License-Identifier: MIT
// checkCovariance decides exactly as its eigenvalue criterion (λ_min > 1e-12 · λ_max, λ_max > 0) whether the
// cheap norm bound settles it or the eigenvalues are computed: random symmetric matrices with condition
// numbers on both sides of the bound (1e11) and of the criterion (1e12), and indefinite ones. The
// fixed-size fast path (informationFromWellConditionedCovariance) gives informationFromCovariance's Ω bit for
// bit whenever it decides, and leaves every other matrix to it.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <cmath>
#include <random>

#include "dualgraph/dual_graph/measurements.h"
#include "dualgraph/types/se3_covariance.h"

namespace dualgraph {
namespace {

/// Q · diag(λ) · Qᵀ with a random orthogonal Q and eigenvalues spread log-uniformly from `smallest` to 1,
/// one of them exactly `smallest` (negative `smallest`: one eigenvalue of that value, the rest positive).
Eigen::MatrixXd withEigenvalues(int n, double smallest, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd random(n, n);
  for (int i = 0; i < random.size(); ++i) random.data()[i] = normal(rng);
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(random).householderQ();
  Eigen::VectorXd values(n);
  values[0] = 1.0;
  values[n - 1] = smallest;
  std::uniform_real_distribution<double> exponent(std::log10(std::fabs(smallest)), 0.0);
  for (int i = 1; i + 1 < n; ++i) values[i] = std::pow(10.0, exponent(rng));
  const Eigen::MatrixXd m = q * values.asDiagonal() * q.transpose();
  return 0.5 * (m + m.transpose());
}

bool exactCriterion(const Eigen::MatrixXd& m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(m, Eigen::EigenvaluesOnly);
  const double largest = eigen.eigenvalues().maxCoeff();
  return largest > 0.0 && eigen.eigenvalues().minCoeff() > 1e-12 * largest;
}

TEST(CheckCovariance, DecidesAsTheEigenvalueCriterionOnBothSidesOfTheBound) {
  std::mt19937 rng(7);
  // Condition numbers 1 … 1e14, away from the criterion's 1e12 by ≥ 10^0.3 so that round-off in the
  // test's own eigenvalues cannot flip the expectation; 10^11.5 and 10^11.7 are accepted but only after
  // the eigenvalues (the norm bound cannot decide them).
  const double log_conditions[] = {0.0, 1.0, 4.0, 8.0, 10.0, 10.8, 11.5, 11.7, 12.3, 13.0, 14.0};
  int accepted = 0, rejected = 0;
  for (int n : {3, 6}) {
    for (double log_condition : log_conditions) {
      for (int trial = 0; trial < 20; ++trial) {
        const Eigen::MatrixXd m = withEigenvalues(n, std::pow(10.0, -log_condition), rng);
        const bool expected = exactCriterion(m);
        ASSERT_EQ(expected, log_condition < 12.0) << "test matrix, n " << n << " log κ " << log_condition;
        const Status status = checkCovariance(m, "test covariance");
        EXPECT_EQ(status.ok(), expected) << "n " << n << " log κ " << log_condition << ": " << status.message();
        if (!status.ok()) {
          EXPECT_EQ(status.code(), StatusCode::kNotPositiveDefinite);
          EXPECT_NE(status.message().find("test covariance is not positive definite (eigenvalues from"), std::string::npos);
        }
        (expected ? accepted : rejected) += 1;
      }
    }
  }
  EXPECT_EQ(accepted, 2 * 20 * 8);
  EXPECT_EQ(rejected, 2 * 20 * 3);
}

TEST(CheckCovariance, RejectsIndefiniteAndNegativeDefiniteMatrices) {
  std::mt19937 rng(11);
  for (int n : {3, 6}) {
    for (double smallest : {-1e-3, -0.5, -1.0}) {
      const Eigen::MatrixXd m = withEigenvalues(n, smallest, rng);
      const Status status = checkCovariance(m, "indefinite");
      EXPECT_EQ(status.code(), StatusCode::kNotPositiveDefinite) << n << " " << smallest;
    }
    const Eigen::MatrixXd negative = -withEigenvalues(n, 1e-2, rng);
    EXPECT_EQ(checkCovariance(negative, "negative").code(), StatusCode::kNotPositiveDefinite);
    EXPECT_EQ(checkCovariance(Eigen::MatrixXd::Zero(n, n), "zero").code(), StatusCode::kNotPositiveDefinite);
  }
}

template <int N>
void expectFastPathAgrees(const Eigen::MatrixXd& m, bool expect_decided, const std::string& label) {
  using Matrix = Eigen::Matrix<double, N, N>;
  Matrix fast = Matrix::Constant(-7.0);
  const bool decided = informationFromWellConditionedCovariance<N>(Matrix(m), fast);
  EXPECT_EQ(decided, expect_decided) << label;
  const Result<Eigen::MatrixXd> checked = informationFromCovariance(m, "covariance");
  if (!decided) {
    EXPECT_TRUE((fast.array() == -7.0).all()) << label << ": output written without a decision";
    return;
  }
  ASSERT_TRUE(checked.ok()) << label << ": " << checked.status().message();
  EXPECT_TRUE((fast.array() == checked->array()).all()) << label << "\nfast:\n" << fast << "\nchecked:\n" << *checked;
}

TEST(InformationFromWellConditionedCovariance, EqualsTheCheckedPathOrLeavesTheMatrixToIt) {
  std::mt19937 rng(13);
  // κ up to 1e8 is decided by the norm bound (‖S‖∞‖S⁻¹‖∞ ≤ n κ); κ = 1e13 fails the criterion itself.
  for (double log_condition : {0.0, 3.0, 8.0, 13.0}) {
    const bool decided = log_condition < 12.0;
    for (int trial = 0; trial < 10; ++trial) {
      const std::string label = "log κ " + std::to_string(log_condition);
      // Scaled like a covariance (σ² ≈ 1e-4), and unsymmetric at round-off, as a computed marginal is.
      Eigen::MatrixXd m6 = 1e-4 * withEigenvalues(6, std::pow(10.0, -log_condition), rng);
      m6(0, 1) += 1e-20;
      expectFastPathAgrees<6>(m6, decided, label);
      expectFastPathAgrees<3>(1e-4 * withEigenvalues(3, std::pow(10.0, -log_condition), rng), decided, label);
    }
  }
  Eigen::MatrixXd nan = withEigenvalues(6, 0.1, rng);
  nan(2, 2) = std::nan("");
  expectFastPathAgrees<6>(nan, false, "NaN");
  expectFastPathAgrees<3>(-withEigenvalues(3, 0.1, rng), false, "negative definite");
  expectFastPathAgrees<6>(withEigenvalues(6, -1e-3, rng), false, "indefinite");
}

}  // namespace
}  // namespace dualgraph
