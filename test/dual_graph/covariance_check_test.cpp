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

// The per-sample checks without a message: true only where the checked path says OK, for every kind of matrix and
// pose the checked path refuses; and validateOdometrySample's verdict is the checked path's.
TEST(SurelyValidCovariance, TrueOnlyWhereCheckCovarianceIsOk) {
  std::mt19937 rng(17);
  int decided = 0;
  for (double log_condition : {0.0, 4.0, 8.0, 11.7, 13.0}) {
    for (double smallest_sign : {1.0, -1.0}) {
      for (int trial = 0; trial < 10; ++trial) {
        Eigen::MatrixXd m = 1e-4 * withEigenvalues(6, smallest_sign * std::pow(10.0, -log_condition), rng);
        if (trial == 1) m(0, 5) += 1e-9;         // not symmetric
        if (trial == 2) m(3, 3) = std::nan("");  // not finite
        const bool fast = surelyValidCovariance<6>(Matrix6d(m));
        const Status checked = checkCovariance(m, "m");
        if (fast) {
          EXPECT_TRUE(checked.ok()) << "log κ " << log_condition << ": " << checked.message();
          ++decided;
        }
        if (trial >= 3 && smallest_sign > 0 && log_condition <= 8.0) {
          EXPECT_TRUE(fast) << log_condition;
        }
        if (surelyValidCovariance<3>(Eigen::Matrix3d(m.topLeftCorner<3, 3>()))) {
          EXPECT_TRUE(checkCovariance(Eigen::MatrixXd(m.topLeftCorner<3, 3>()), "m3").ok());
        }
      }
    }
  }
  EXPECT_GE(decided, 3 * 7);
  EXPECT_FALSE(surelyValidCovariance<6>(Matrix6d::Zero()));
}

TEST(IsRigidTransform, AgreesWithTheCheckedPathAndValidateOdometrySampleKeepsItsMessages) {
  Eigen::Isometry3d rigid = Eigen::Isometry3d::Identity();
  rigid.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  rigid.translation() << 1, -2, 3;
  Eigen::Isometry3d scaled = rigid;
  scaled.linear() *= 1.01;
  Eigen::Isometry3d mirrored = rigid;
  mirrored.linear().col(0) *= -1.0;
  Eigen::Isometry3d nan = rigid;
  nan.translation().y() = std::nan("");
  for (const Eigen::Isometry3d& pose : {rigid, scaled, mirrored, nan}) {
    EXPECT_EQ(isRigidTransform(pose), checkRigidTransform(pose, "pose").ok());
  }
  EXPECT_TRUE(isRigidTransform(rigid));
  OdometrySample sample{1.7e9 + 0.25, rigid, std::nullopt};
  EXPECT_TRUE(validateOdometrySample(sample).ok());
  sample.relative_covariance = Matrix6d::Identity() * 1e-4;
  EXPECT_TRUE(validateOdometrySample(sample).ok());
  sample.relative_covariance->coeffRef(2, 2) = -1e-4;
  Status refused = validateOdometrySample(sample);
  EXPECT_EQ(refused.code(), StatusCode::kNotPositiveDefinite);
  EXPECT_NE(refused.message().find("odometry sample at t=1700000000.25: relative_covariance"), std::string::npos)
      << refused.message();
  sample.relative_covariance.reset();
  sample.odom_T_body = mirrored;
  refused = validateOdometrySample(sample);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.message().find("odom_T_body has a rotation that is not orthonormal"), std::string::npos)
      << refused.message();
}

}  // namespace
}  // namespace dualgraph
