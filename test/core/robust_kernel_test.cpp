// SPDX-License-Identifier: MIT
// Robust kernels on s = eᵀΩe: derivatives against numeric differentiation, continuity at the
// thresholds, DCS weights, and the "NAME:DELTA" parser.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "dualgraph/core/robust_kernel.h"
#include "test/core/test_fixtures.h"

namespace dualgraph {
namespace {

std::shared_ptr<const RobustKernel> kernel(const std::string& spec) {
  auto made = makeRobustKernel(spec);
  EXPECT_TRUE(made.ok()) << made.status().toString();
  return made.ok() ? *made : nullptr;
}

/// Central differences of ρ and ρ' at s with a step relative to s.
struct NumericDerivatives {
  double first;
  double second;
};
NumericDerivatives numericDerivatives(const RobustKernel& k, double s) {
  const double h = 1e-5 * std::max(s, 1e-3);
  return {(k.robustify(s + h)[0] - k.robustify(s - h)[0]) / (2 * h),
          (k.robustify(s + h)[1] - k.robustify(s - h)[1]) / (2 * h)};
}

class SmoothKernel : public ::testing::TestWithParam<const char*> {};

TEST_P(SmoothKernel, FirstAndSecondDerivativesMatchNumericDifferentiationAwayFromKinks) {
  const auto k = kernel(GetParam());
  ASSERT_NE(k, nullptr);
  const double d2 = k->delta() * k->delta();
  // Both sides of the threshold δ², staying clear of it (Huber's ρ'' and Tukey's ρ' jump there).
  for (double ratio : {0.01, 0.2, 0.5, 0.9, 1.1, 2.0, 7.5, 40.0, 1e3}) {
    const double s = ratio * d2;
    const Eigen::Vector3d rho = k->robustify(s);
    const NumericDerivatives numeric = numericDerivatives(*k, s);
    EXPECT_NEAR(rho[1], numeric.first, 1e-7 * std::max(1.0, std::fabs(numeric.first)))
        << GetParam() << " ρ' at s = " << s;
    EXPECT_NEAR(rho[2], numeric.second, 1e-6 * std::max(1.0 / d2, std::fabs(numeric.second)))
        << GetParam() << " ρ'' at s = " << s;
  }
}

TEST_P(SmoothKernel, IsQuadraticAtZeroAndNonDecreasing) {
  const auto k = kernel(GetParam());
  ASSERT_NE(k, nullptr);
  EXPECT_EQ(k->robustify(0.0)[0], 0.0);
  EXPECT_DOUBLE_EQ(k->robustify(0.0)[1], 1.0);
  double previous = 0.0;
  for (double s = 0.01; s < 100.0; s *= 1.7) {
    const Eigen::Vector3d rho = k->robustify(s);
    EXPECT_GE(rho[0], previous) << "s = " << s;
    EXPECT_GE(rho[1], 0.0);
    EXPECT_LE(rho[1], 1.0);
    EXPECT_LE(rho[0], s + 1e-12) << "a robust cost never exceeds the squared error";
    previous = rho[0];
  }
}

INSTANTIATE_TEST_SUITE_P(HuberCauchyTukey, SmoothKernel,
                         ::testing::Values("huber:1", "huber:0.3", "cauchy:1", "cauchy:2.5", "tukey:1",
                                           "tukey:4.685"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (c == ':' || c == '.') c = '_';
                           }
                           return name;
                         });

TEST(RobustKernel, HuberIsQuadraticInsideAndLinearInTheErrorOutside) {
  const auto k = kernel("huber:2");
  EXPECT_EQ(k->robustify(3.0), Eigen::Vector3d(3.0, 1.0, 0.0));
  const Eigen::Vector3d outside = k->robustify(25.0);  // |e| = 5
  EXPECT_DOUBLE_EQ(outside[0], 2.0 * 2.0 * 5.0 - 4.0);
  EXPECT_DOUBLE_EQ(outside[1], 2.0 / 5.0);
}

TEST(RobustKernel, HuberValueAndSlopeAreContinuousAtTheThreshold) {
  for (double delta : {0.1, 1.0, 3.0}) {
    const HuberKernel k(delta);
    const double d2 = delta * delta;
    const Eigen::Vector3d below = k.robustify(d2 * (1 - 1e-12));
    const Eigen::Vector3d at = k.robustify(d2);
    const Eigen::Vector3d above = k.robustify(d2 * (1 + 1e-12));
    EXPECT_NEAR(below[0], above[0], 1e-9 * d2);
    EXPECT_NEAR(at[0], above[0], 1e-9 * d2);
    EXPECT_NEAR(below[1], above[1], 1e-9);
    EXPECT_NEAR(at[1], above[1], 1e-9);
  }
}

TEST(RobustKernel, TukeyIsContinuousAtTheThresholdAndFlatBeyond) {
  for (double delta : {0.5, 1.0, 4.685}) {
    const TukeyKernel k(delta);
    const double d2 = delta * delta;
    const Eigen::Vector3d below = k.robustify(d2 * (1 - 1e-9));
    const Eigen::Vector3d above = k.robustify(d2 * (1 + 1e-9));
    EXPECT_NEAR(below[0], d2 / 3.0, 1e-9 * d2);
    EXPECT_NEAR(above[0], d2 / 3.0, 1e-15 * d2);
    EXPECT_NEAR(below[1], 0.0, 1e-9);
    EXPECT_EQ(above[1], 0.0);
    EXPECT_EQ(k.robustify(100.0 * d2), Eigen::Vector3d(d2 / 3.0, 0.0, 0.0)) << "outliers get zero weight";
  }
}

TEST(RobustKernel, CauchyMatchesItsClosedForm) {
  const CauchyKernel k(2.0);
  const double s = 3.0;
  EXPECT_DOUBLE_EQ(k.robustify(s)[0], 4.0 * std::log(1.0 + s / 4.0));
  EXPECT_DOUBLE_EQ(k.robustify(s)[1], 1.0 / (1.0 + s / 4.0));
}

TEST(RobustKernel, DcsWeightIsAtMostOneAndOneForSmallErrors) {
  for (double phi : {0.5, 1.0, 5.0}) {
    const DcsKernel k(phi);
    for (double s = 0.0; s <= phi; s += phi / 16) {
      const Eigen::Vector3d rho = k.robustify(s);
      EXPECT_EQ(rho[1], 1.0) << "s = " << s << " ≤ Φ = " << phi;
      EXPECT_DOUBLE_EQ(rho[0], s);
    }
    double previous_weight = 1.0;
    for (double s = phi * 1.01; s < 1e4; s *= 1.5) {
      const Eigen::Vector3d rho = k.robustify(s);
      const double w = std::min(1.0, 2.0 * phi / (phi + s));
      EXPECT_LE(rho[1], 1.0);
      EXPECT_LE(rho[1], previous_weight) << "weights fall with the error";
      EXPECT_DOUBLE_EQ(rho[1], w * w);
      EXPECT_DOUBLE_EQ(rho[0], w * w * s);
      previous_weight = rho[1];
    }
  }
}

TEST(MakeRobustKernel, ParsesNameAndDelta) {
  struct Case {
    const char* spec;
    const char* name;
    double delta;
  };
  for (const Case& c : {Case{"huber:1.5", "huber", 1.5}, Case{"cauchy:1", "cauchy", 1.0},
                        Case{"tukey:4.685", "tukey", 4.685}, Case{"dcs:2e-1", "dcs", 0.2}}) {
    const auto k = kernel(c.spec);
    ASSERT_NE(k, nullptr) << c.spec;
    EXPECT_STREQ(k->name(), c.name);
    EXPECT_DOUBLE_EQ(k->delta(), c.delta);
  }
  EXPECT_NE(dynamic_cast<const HuberKernel*>(kernel("huber:1").get()), nullptr);
  EXPECT_NE(dynamic_cast<const CauchyKernel*>(kernel("cauchy:1").get()), nullptr);
  EXPECT_NE(dynamic_cast<const TukeyKernel*>(kernel("tukey:1").get()), nullptr);
  EXPECT_NE(dynamic_cast<const DcsKernel*>(kernel("dcs:1").get()), nullptr);
}

class MakeRobustKernelRejects : public ::testing::TestWithParam<const char*> {};

TEST_P(MakeRobustKernelRejects, WithInvalidArgumentQuotingTheSpec) {
  const std::string spec = GetParam();
  const auto made = makeRobustKernel(spec);
  ASSERT_FALSE(made.ok()) << spec;
  EXPECT_EQ(made.status().code(), StatusCode::kInvalidArgument);
  // Malformed specs are quoted whole; a well-formed spec with an unknown name quotes the name.
  const std::string& message = made.status().message();
  const std::string name = spec.substr(0, spec.find(':'));
  EXPECT_TRUE(message.find("'" + spec + "'") != std::string::npos ||
              message.find("unknown robust kernel '" + name + "'") != std::string::npos)
      << message;
}

INSTANTIATE_TEST_SUITE_P(BadSpecs, MakeRobustKernelRejects,
                         ::testing::Values("huber", "huber:-1", "huber:0", "huber:x", "huber:",
                                           "huber:1x", "huber:nan", "huber:inf", "huber:1e400", "foo:1",
                                           "", ":1", "Huber:1"));

}  // namespace
}  // namespace dualgraph
