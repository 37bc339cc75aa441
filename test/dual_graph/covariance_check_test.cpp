// SPDX-License-Identifier: MIT
// checkCovariance decides exactly as its eigenvalue criterion (λ_min > 1e-12 · λ_max, λ_max > 0) whether the
// cheap norm bound settles it or the eigenvalues are computed: random symmetric matrices with condition
// numbers on both sides of the bound (1e11) and of the criterion (1e12), and indefinite ones.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <cmath>
#include <random>

#include "dual_graph/measurements.h"

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

}  // namespace
}  // namespace dualgraph
