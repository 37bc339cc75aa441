// SPDX-License-Identifier: MIT
// SO(3)/SE(3) exponential maps, Jacobians, adjoint, quaternion helpers, g2o's chart and the
// θ/2 unit conversion (types/se3_math.h).
#include "dualgraph/types/se3_math.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "test/types/test_states.h"

namespace dualgraph {
namespace {

using testing::kPi;
using testing::Regime;
using testing::Rng;

constexpr int kSamples = 1000;
const Regime kAllRegimes[] = {Regime::kRandom, Regime::kIdentity, Regime::kTinyAngle, Regime::kNearPi};

double maxAbs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

// exp/log laws on SE(3): plus(x, d) = x · exp(d), minus(y, x) = log(x⁻¹ · y).
TEST(Se3ExpLog, ManifoldLawsHoldOnSeededSamplesInEveryRegime) {
  Rng rng(testing::kSeed);
  for (const Regime regime : kAllRegimes) {
    SCOPED_TRACE(static_cast<int>(regime));
    for (int k = 0; k < kSamples; ++k) {
      const Eigen::Isometry3d x = testing::randomPose(rng, regime);
      Vector6d d;
      d.head<3>() = testing::randomPoint(rng, regime == Regime::kIdentity ? Regime::kRandom : regime);
      d.tail<3>() = testing::randomRotationVector(rng, regime == Regime::kIdentity ? Regime::kRandom : regime);
      const Eigen::Isometry3d y = testing::randomPose(rng, regime);

      EXPECT_LT(maxAbs((x * se3Exp(Vector6d::Zero())).matrix() - x.matrix()), 1e-15);
      const Vector6d d_back = se3Log(x.inverse() * (x * se3Exp(d)));
      ASSERT_LT(maxAbs(d_back - d), 1e-9 * std::max(1.0, d.norm())) << d.transpose() << "\n" << d_back.transpose();
      const Eigen::Isometry3d y_back = x * se3Exp(se3Log(x.inverse() * y));
      ASSERT_LT(maxAbs(y_back.matrix() - y.matrix()), 1e-9);
    }
  }
}

TEST(So3ExpLog, ManifoldLawsHoldOnSeededSamplesInEveryRegime) {
  Rng rng(testing::kSeed + 1);
  for (const Regime regime : kAllRegimes) {
    SCOPED_TRACE(static_cast<int>(regime));
    for (int k = 0; k < kSamples; ++k) {
      const Eigen::Matrix3d x = so3Exp(testing::randomRotationVector(rng, regime));
      const Eigen::Vector3d d =
          testing::randomRotationVector(rng, regime == Regime::kIdentity ? Regime::kRandom : regime);
      const Eigen::Matrix3d y = so3Exp(testing::randomRotationVector(rng, regime));
      EXPECT_LT(maxAbs(x * so3Exp(Eigen::Vector3d::Zero()) - x), 1e-15);
      ASSERT_LT(maxAbs(so3Log(x.transpose() * x * so3Exp(d)) - d), 1e-9) << d.transpose();
      ASSERT_LT(maxAbs(x * so3Exp(so3Log(x.transpose() * y)) - y), 1e-9);
    }
  }
}

TEST(So3ExpLog, ExpOfLogReturnsTheRotationNearAndAtPi) {
  Rng rng(testing::kSeed + 2);
  for (const double gap : {0.0, 1e-12, 1e-9, 1e-6, 1e-3}) {
    for (int k = 0; k < 100; ++k) {
      const Eigen::Vector3d axis = testing::randomUnitVector(rng);
      const Eigen::Matrix3d rotation = Eigen::AngleAxisd(kPi - gap, axis).toRotationMatrix();
      const Eigen::Vector3d theta = so3Log(rotation);
      EXPECT_NEAR(theta.norm(), kPi - gap, 1e-9);
      EXPECT_LT(maxAbs(so3Exp(theta) - rotation), 1e-12) << "gap " << gap;
    }
  }
}

TEST(So3ExpLog, LogAngleIsAtMostPiAndExactNearZero) {
  const Eigen::Vector3d tiny(3e-9, -4e-9, 1e-9);
  EXPECT_LT(maxAbs(so3Log(so3Exp(tiny)) - tiny), 1e-22);
  EXPECT_LT(maxAbs(so3Log(Eigen::Matrix3d::Identity())), 1e-300);
  const Eigen::Vector3d beyond_pi = (kPi + 0.5) * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(so3Log(so3Exp(beyond_pi)).z(), -(kPi - 0.5), 1e-12);
}

TEST(So3Exp, MatchesEigenAngleAxis) {
  Rng rng(testing::kSeed + 3);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d theta = testing::randomRotationVector(rng, Regime::kRandom);
    const Eigen::Matrix3d expected = Eigen::AngleAxisd(theta.norm(), theta.normalized()).toRotationMatrix();
    EXPECT_LT(maxAbs(so3Exp(theta) - expected), 1e-14);
  }
}

TEST(So3RightJacobian, TimesItsInverseIsIdentity) {
  Rng rng(testing::kSeed + 4);
  for (const Regime regime : kAllRegimes) {
    for (int k = 0; k < 200; ++k) {
      const Eigen::Vector3d theta = testing::randomRotationVector(rng, regime, 1e-3);
      EXPECT_LT(maxAbs(so3RightJacobian(theta) * so3RightJacobianInverse(theta) - Eigen::Matrix3d::Identity()), 1e-10)
          << theta.transpose();
      EXPECT_LT(maxAbs(so3LeftJacobian(theta) * so3LeftJacobianInverse(theta) - Eigen::Matrix3d::Identity()), 1e-10);
    }
  }
}

TEST(So3RightJacobian, MatchesNumericDerivativeOfExp) {
  // exp(θ + δ) ≈ exp(θ) · exp(Jr(θ) δ)  ⇒  Jr e_k ≈ log(exp(θ)ᵀ exp(θ + h e_k)) / h.
  Rng rng(testing::kSeed + 5);
  const double h = 1e-6;
  for (const Regime regime : {Regime::kRandom, Regime::kTinyAngle, Regime::kNearPi}) {
    for (int k = 0; k < 100; ++k) {
      const Eigen::Vector3d theta = testing::randomRotationVector(rng, regime, 1e-2);
      Eigen::Matrix3d numeric;
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(c);
        numeric.col(c) = (so3Log(so3Exp(theta).transpose() * so3Exp(theta + step)) -
                          so3Log(so3Exp(theta).transpose() * so3Exp(theta - step))) / (2.0 * h);
      }
      EXPECT_LT(maxAbs(so3RightJacobian(theta) - numeric), 1e-7) << theta.transpose();
    }
  }
}

TEST(Se3Adjoint, ConjugatesTheExponential) {
  Rng rng(testing::kSeed + 6);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Isometry3d pose = testing::randomPose(rng, Regime::kRandom);
    Vector6d xi;
    xi.head<3>() = testing::randomPoint(rng, Regime::kRandom);
    xi.tail<3>() = testing::randomRotationVector(rng, Regime::kRandom);
    const Eigen::Isometry3d left = pose * se3Exp(xi) * pose.inverse();
    EXPECT_LT(maxAbs(left.matrix() - se3Exp(se3Adjoint(pose) * xi).matrix()), 1e-12);
  }
}

// The edges' chart: box-minus inverts box-plus, agrees with the g2o chart of a⁻¹ b (metric units), and
// equals T · exp(ξ) to first order only (second order in |θ|·|ρ|).
TEST(Se3BoxPlusMinus, InverseOfEachOtherAndTheEdgesChartInMetricUnits) {
  Rng rng(testing::kSeed + 7);
  for (const Regime regime : kAllRegimes) {
    SCOPED_TRACE(static_cast<int>(regime));
    for (int k = 0; k < kSamples; ++k) {
      const Eigen::Isometry3d a = testing::randomPose(rng, regime);
      const Eigen::Isometry3d b = testing::randomPose(rng, regime);
      const Vector6d xi = se3BoxMinus(a, b);
      ASSERT_LT(maxAbs(se3BoxPlus(a, xi).matrix() - b.matrix()), 1e-9);
      EXPECT_LT(maxAbs(xi.head<3>() - g2oChart(a.inverse() * b).head<3>()), 1e-9);
      const Vector6d chart = g2oChart(a.inverse() * b);  // rotation part q.vec = sin(|θ|/2) θ/|θ|, w ≥ 0
      EXPECT_NEAR(xi.tail<3>().norm(), 2.0 * std::asin(std::min(1.0, chart.tail<3>().norm())), 1e-6);
    }
  }
  Vector6d xi;
  xi << 1.0, -2.0, 0.5, 0.3, -0.2, 0.4;
  const Eigen::Isometry3d pose = testing::randomPose(rng, Regime::kRandom);
  for (const double scale : {1e-3, 1e-4}) {
    const Eigen::Matrix4d gap = se3BoxPlus(pose, scale * xi).matrix() - (pose * se3Exp(scale * xi)).matrix();
    EXPECT_LT(maxAbs(gap), 2.0 * scale * scale * xi.squaredNorm()) << scale;  // second order
    EXPECT_GT(maxAbs(gap), 0.01 * scale * scale);                              // but not zero
  }
}

TEST(QuaternionHelpers, NameTheCoefficientOrderExplicitly) {
  const Eigen::Quaterniond a = quatFromXyzw(0.1, 0.2, 0.3, 0.9);
  const Eigen::Quaterniond b = quatFromWxyz(0.9, 0.1, 0.2, 0.3);
  EXPECT_EQ(a.x(), 0.1);
  EXPECT_EQ(a.y(), 0.2);
  EXPECT_EQ(a.z(), 0.3);
  EXPECT_EQ(a.w(), 0.9);
  EXPECT_EQ(a.coeffs(), b.coeffs());
}

TEST(QuaternionHelpers, ProductMatricesReproduceTheHamiltonProduct) {
  Rng rng(testing::kSeed + 7);
  for (int k = 0; k < 50; ++k) {
    const Eigen::Quaterniond a(so3Exp(testing::randomRotationVector(rng, Regime::kRandom)));
    const Eigen::Quaterniond b(so3Exp(testing::randomRotationVector(rng, Regime::kRandom)));
    const Eigen::Quaterniond ab = a * b;
    const Eigen::Vector4d expected(ab.w(), ab.x(), ab.y(), ab.z());
    const Eigen::Vector4d a_wxyz(a.w(), a.x(), a.y(), a.z());
    const Eigen::Vector4d b_wxyz(b.w(), b.x(), b.y(), b.z());
    EXPECT_LT(maxAbs(quatLeftMatrix(a) * b_wxyz - expected), 1e-15);
    EXPECT_LT(maxAbs(quatRightMatrix(b) * a_wxyz - expected), 1e-15);
  }
}

TEST(G2oChart, IncrementAndChartAreInverseWithWNonNegative) {
  Rng rng(testing::kSeed + 8);
  for (const Regime regime : kAllRegimes) {
    for (int k = 0; k < kSamples; ++k) {
      const Vector6d v = testing::randomG2oTangent(rng, regime);
      const Eigen::Isometry3d pose = g2oIncrement(v);
      ASSERT_LT(maxAbs(g2oChart(pose) - v), 1e-12) << v.transpose();
      const Eigen::Quaterniond q(pose.linear());
      const double w = std::sqrt(std::max(0.0, 1.0 - g2oChart(pose).tail<3>().squaredNorm()));
      EXPECT_NEAR(std::fabs(q.w()), w, 1e-9);
    }
  }
}

TEST(QuatFromRotation, MatchesEigensConstructionInEveryBranchUpToSign) {
  // Each branch: positive trace, and the largest diagonal entry at x, y or z (angles near π about
  // axes near each coordinate axis, including exactly π), plus random rotations of every size.
  std::vector<Eigen::Matrix3d> rotations;
  const std::vector<Eigen::Vector3d> axes = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(),
                                             Eigen::Vector3d(1.0, 0.2, -0.1).normalized(), Eigen::Vector3d(0.1, -1.0, 0.3).normalized(),
                                             Eigen::Vector3d(-0.2, 0.1, 1.0).normalized()};
  for (const Eigen::Vector3d& axis : axes) {
    for (double angle : {0.0, 1e-9, 0.3, 2.0, 3.0, M_PI - 1e-7, M_PI}) {
      rotations.push_back(Eigen::AngleAxisd(angle, axis).toRotationMatrix());
    }
  }
  Rng rng(testing::kSeed + 31);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d axis = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)).normalized();
    rotations.push_back(Eigen::AngleAxisd(M_PI * std::fabs(uniform(rng)), axis).toRotationMatrix());
  }
  for (const Eigen::Matrix3d& r : rotations) {
    const Eigen::Quaterniond q = quatFromRotation(r);
    const Eigen::Quaterniond eigen = Eigen::Quaterniond(r).normalized();
    const double sign = q.coeffs().dot(eigen.coeffs()) < 0.0 ? -1.0 : 1.0;
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    EXPECT_LT((q.coeffs() - sign * eigen.coeffs()).lpNorm<Eigen::Infinity>(), 1e-14) << r;
    EXPECT_LT((q.toRotationMatrix() - r).lpNorm<Eigen::Infinity>(), 1e-14) << r;
  }
}

TEST(G2oChart, FlipsTheQuaternionSoThatWIsNonNegative) {
  // −3 rad about z has the unit quaternions ±(cos 1.5, 0, 0, −sin 1.5) (Eigen extracts the one
  // with w < 0 here); the chart must pick w ≥ 0, i.e. the vector part (0, 0, −sin 1.5).
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = so3Exp(Eigen::Vector3d(0.0, 0.0, -3.0));
  const Eigen::Quaterniond extracted(pose.linear());
  const Vector6d v = g2oChart(pose);
  EXPECT_NEAR(v[5], -std::sin(1.5), 1e-14) << "Eigen extracted w = " << extracted.w();
  // Same rotation written with the opposite quaternion sign: same chart value.
  Eigen::Isometry3d same = Eigen::Isometry3d::Identity();
  same.linear() = quatFromWxyz(-std::cos(1.5), 0.0, 0.0, std::sin(1.5)).toRotationMatrix();
  EXPECT_LT(maxAbs(g2oChart(same) - v), 1e-14);
}

TEST(G2oChart, IncrementWithVectorPartLongerThanOneHasIdentityRotation) {
  Vector6d v;
  v << 1.0, 2.0, 3.0, 0.8, 0.8, 0.0;
  const Eigen::Isometry3d pose = g2oIncrement(v);
  EXPECT_EQ(pose.linear(), Eigen::Matrix3d::Identity());
  EXPECT_EQ(pose.translation(), Eigen::Vector3d(1.0, 2.0, 3.0));
}

TEST(G2oChart, RotationPartIsHalfTheRotationVectorForSmallAngles) {
  const Eigen::Vector3d theta(1e-4, -2e-4, 3e-4);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = so3Exp(theta);
  EXPECT_LT(maxAbs(g2oChart(pose).tail<3>() - 0.5 * theta), 1e-12);
}

TEST(G2oChart, JacobianOfProductMatchesNumericDerivative) {
  Rng rng(testing::kSeed + 9);
  const double h = 1e-6;
  for (const Regime regime : {Regime::kRandom, Regime::kIdentity, Regime::kTinyAngle, Regime::kNearPi}) {
    for (int k = 0; k < 100; ++k) {
      const Eigen::Isometry3d a = testing::randomPose(rng, regime, 1e-3);
      const Eigen::Isometry3d b = testing::randomPose(rng, regime, 1e-3);
      if (g2oChart(a * b).tail<3>().norm() > 1.0 - 1e-6) continue;  // the chart jumps at w = 0
      Matrix6d numeric;
      for (int c = 0; c < 6; ++c) {
        const Vector6d step = h * Vector6d::Unit(c);
        numeric.col(c) = (g2oChart(a * g2oIncrement(step) * b) - g2oChart(a * g2oIncrement(-step) * b)) / (2.0 * h);
      }
      const Matrix6d analytic = g2oChartJacobianOfProduct(a, b);
      EXPECT_LT(maxAbs(analytic - numeric), 1e-7 * std::max(1.0, maxAbs(numeric)))
          << "analytic\n" << analytic << "\nnumeric\n" << numeric;
    }
  }
}

TEST(ApproximateNearestRotation, ShrinksTheOrthonormalityErrorQuadratically) {
  Rng rng(testing::kSeed + 10);
  Eigen::Matrix3d rotation = so3Exp(testing::randomRotationVector(rng, Regime::kRandom));
  rotation += 1e-5 * Eigen::Matrix3d::Random();
  const auto error = [](const Eigen::Matrix3d& r) {
    return maxAbs(r.transpose() * r - Eigen::Matrix3d::Identity());
  };
  ASSERT_GT(error(rotation), 1e-6);
  approximateNearestRotation(rotation);
  EXPECT_LT(error(rotation), 1e-9);
}

// ---------------------------------------------------------------------------------------------
// The θ/2 unit trap.
// ---------------------------------------------------------------------------------------------

TEST(G2oUnits, InformationScalesRotationRowsAndColumnsByTwo) {
  Rng rng(testing::kSeed + 11);
  const Matrix6d metric = testing::randomInformation<6>(rng);
  const Matrix6d g2o = informationMetricToG2o(metric);
  EXPECT_LT(maxAbs(g2o.topLeftCorner<3, 3>() - metric.topLeftCorner<3, 3>()), 1e-15);
  EXPECT_LT(maxAbs(g2o.topRightCorner<3, 3>() - 2.0 * metric.topRightCorner<3, 3>()), 1e-13);
  EXPECT_LT(maxAbs(g2o.bottomLeftCorner<3, 3>() - 2.0 * metric.bottomLeftCorner<3, 3>()), 1e-13);
  EXPECT_LT(maxAbs(g2o.bottomRightCorner<3, 3>() - 4.0 * metric.bottomRightCorner<3, 3>()), 1e-13);
  EXPECT_LT(maxAbs(informationG2oToMetric(g2o) - metric), 1e-13);
}

TEST(G2oUnits, CovarianceConversionIsTheInverseOfTheInformationConversion) {
  Rng rng(testing::kSeed + 12);
  const Matrix6d covariance_metric = testing::randomInformation<6>(rng, 0.1);
  const Matrix6d covariance_g2o = covarianceMetricToG2o(covariance_metric);
  EXPECT_LT(maxAbs(covariance_g2o.bottomRightCorner<3, 3>() - 0.25 * covariance_metric.bottomRightCorner<3, 3>()), 1e-15);
  const Matrix6d via_information = informationMetricToG2o(covariance_metric.inverse()).inverse();
  EXPECT_LT(maxAbs(covariance_g2o - via_information), 1e-12);
  EXPECT_LT(maxAbs(covarianceG2oToMetric(covariance_g2o) - covariance_metric), 1e-15);
}

TEST(G2oUnits, ConvertedInformationGivesTheMetricChi2ForSmallErrors) {
  // A small pose error measured metrically ([t; θ]) and in g2o's chart ([t; θ/2]) must give the
  // same χ² once the information has been converted.
  Rng rng(testing::kSeed + 13);
  const Matrix6d information_metric = testing::randomInformation<6>(rng);
  Vector6d xi;
  xi << 1e-3, -2e-3, 5e-4, 2e-4, -1e-4, 3e-4;
  const Eigen::Isometry3d error_pose = se3Exp(xi);
  const Vector6d e_metric = se3Log(error_pose);
  const Vector6d e_g2o = g2oChart(error_pose);
  const double chi2_metric = e_metric.dot(information_metric * e_metric);
  const double chi2_g2o = e_g2o.dot(informationMetricToG2o(information_metric) * e_g2o);
  EXPECT_NEAR(chi2_g2o / chi2_metric, 1.0, 1e-3);
  // The trap: with the metric information used unconverted, a pure rotation error counts ¼.
  Vector6d rotation_only = Vector6d::Zero();
  rotation_only.tail<3>() = xi.tail<3>();
  const Vector6d r_metric = se3Log(se3Exp(rotation_only));
  const Vector6d r_g2o = g2oChart(se3Exp(rotation_only));
  EXPECT_NEAR(r_g2o.dot(information_metric * r_g2o) / r_metric.dot(information_metric * r_metric), 0.25, 1e-6);
}

}  // namespace
}  // namespace dualgraph
