// SPDX-License-Identifier: MIT
// Manifold laws and text round trips for every vertex type, one typed suite:
//   plus(x, 0) = x,  minus(plus(x, d), x) = d,  plus(x, minus(y, x)) = y
// on 1000 seeded samples in each regime (generic, at the identity, |θ| ≈ 1e-8, |θ| ≈ π), through
// the vertex's own plus. `minus` is the inverse chart the vertex's plus implies.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "test/types/test_states.h"
#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se2.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

using testing::Regime;
using testing::Rng;

template <typename V>
struct VertexTraits;

template <>
struct VertexTraits<VertexSE3> {
  static constexpr const char* kName = "VertexSE3";
  static Eigen::Isometry3d randomEstimate(Rng& rng, Regime regime) { return testing::randomPose(rng, regime, 1e-3); }
  static Vector6d randomTangent(Rng& rng, Regime regime) { return testing::randomG2oTangent(rng, regime); }
  static Vector6d minus(const Eigen::Isometry3d& y, const Eigen::Isometry3d& x) { return g2oChart(x.inverse() * y); }
  static double distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff();
  }
};

template <>
struct VertexTraits<VertexSE2> {
  static constexpr const char* kName = "VertexSE2";
  static SE2 randomEstimate(Rng& rng, Regime regime) { return testing::randomSE2(rng, regime); }
  static Eigen::Vector3d randomTangent(Rng& rng, Regime regime) {
    const SE2 d = testing::randomSE2(rng, regime == Regime::kIdentity ? Regime::kRandom : regime);
    return d.toVector();
  }
  static Eigen::Vector3d minus(const SE2& y, const SE2& x) {
    return Eigen::Vector3d(y.x() - x.x(), y.y() - x.y(), normalizeAngle(y.angle() - x.angle()));
  }
  static double distance(const SE2& a, const SE2& b) { return minus(a, b).cwiseAbs().maxCoeff(); }
};

template <>
struct VertexTraits<VertexPointXYZ> {
  static constexpr const char* kName = "VertexPointXYZ";
  static Eigen::Vector3d randomEstimate(Rng& rng, Regime regime) { return testing::randomPoint(rng, regime); }
  static Eigen::Vector3d randomTangent(Rng& rng, Regime regime) {
    return testing::randomPoint(rng, regime == Regime::kIdentity ? Regime::kRandom : regime);
  }
  static Eigen::Vector3d minus(const Eigen::Vector3d& y, const Eigen::Vector3d& x) { return y - x; }
  static double distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).cwiseAbs().maxCoeff(); }
};

template <typename V>
class VertexManifold : public ::testing::Test {
 protected:
  using Traits = VertexTraits<V>;
  using Estimate = typename V::Estimate;
  using Tangent = typename V::Tangent;

  static Estimate plus(const Estimate& x, const Tangent& d) {
    V vertex;
    vertex.setEstimate(x);
    vertex.plus(d.data());
    return vertex.estimate();
  }

  static constexpr int kSamples = 1000;
  static constexpr Regime kRegimes[] = {Regime::kRandom, Regime::kIdentity, Regime::kTinyAngle, Regime::kNearPi};
};

struct VertexNames {
  template <typename V>
  static std::string GetName(int) { return VertexTraits<V>::kName; }
};

using VertexTypes = ::testing::Types<VertexSE3, VertexSE2, VertexPointXYZ>;
TYPED_TEST_SUITE(VertexManifold, VertexTypes, VertexNames);

TYPED_TEST(VertexManifold, PlusZeroIsIdentity) {
  using Traits = typename TestFixture::Traits;
  Rng rng(testing::kSeed);
  for (const Regime regime : TestFixture::kRegimes) {
    for (int k = 0; k < TestFixture::kSamples; ++k) {
      const auto x = Traits::randomEstimate(rng, regime);
      const typename TestFixture::Tangent zero = TestFixture::Tangent::Zero();
      ASSERT_LE(Traits::distance(TestFixture::plus(x, zero), x), 1e-15) << "regime " << static_cast<int>(regime);
    }
  }
}

TYPED_TEST(VertexManifold, MinusOfPlusReturnsTheIncrement) {
  using Traits = typename TestFixture::Traits;
  Rng rng(testing::kSeed + 1);
  for (const Regime regime : TestFixture::kRegimes) {
    for (int k = 0; k < TestFixture::kSamples; ++k) {
      const auto x = Traits::randomEstimate(rng, regime);
      const auto d = Traits::randomTangent(rng, regime);
      const auto back = Traits::minus(TestFixture::plus(x, d), x);
      ASSERT_LE((back - d).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, d.norm()))
          << "regime " << static_cast<int>(regime) << "\nd    = " << d.transpose() << "\nback = " << back.transpose();
    }
  }
}

TYPED_TEST(VertexManifold, PlusOfMinusReachesTheTarget) {
  using Traits = typename TestFixture::Traits;
  Rng rng(testing::kSeed + 2);
  for (const Regime regime : TestFixture::kRegimes) {
    for (int k = 0; k < TestFixture::kSamples; ++k) {
      const auto x = Traits::randomEstimate(rng, regime);
      const auto y = Traits::randomEstimate(rng, regime);
      ASSERT_LE(Traits::distance(TestFixture::plus(x, Traits::minus(y, x)), y), 1e-9)
          << "regime " << static_cast<int>(regime);
    }
  }
}

TYPED_TEST(VertexManifold, WriteReadWriteIsBitIdentical) {
  using Traits = typename TestFixture::Traits;
  Rng rng(testing::kSeed + 3);
  for (const Regime regime : TestFixture::kRegimes) {
    for (int k = 0; k < 200; ++k) {
      TypeParam original;
      original.setEstimate(Traits::randomEstimate(rng, regime));
      std::ostringstream first;
      original.write(first);
      TypeParam reread;
      const std::string line = first.str();  // TokenReader keeps views into the line
      TokenReader in(line, "<test>", 1);
      ASSERT_TRUE(reread.read(in).ok()) << first.str();
      ASSERT_TRUE(in.finish().ok()) << first.str();
      std::ostringstream second;
      reread.write(second);
      ASSERT_EQ(first.str(), second.str());
      EXPECT_LE(Traits::distance(reread.estimate(), original.estimate()), 1e-14);
    }
  }
}

TYPED_TEST(VertexManifold, ReadReportsAMissingField) {
  TypeParam vertex;
  TokenReader in("1", "graph.g2o", 7);
  const Status status = vertex.read(in);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kParseError);
  EXPECT_NE(status.message().find("graph.g2o:7: line ends before field 'y'"), std::string::npos) << status.message();
}

TYPED_TEST(VertexManifold, ReadRejectsNotANumber) {
  TypeParam vertex;
  TokenReader in("1 nan 2 0 0 0 1", "graph.g2o", 3);
  const Status status = vertex.read(in);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("field 'y' is not finite"), std::string::npos) << status.message();
}

TYPED_TEST(VertexManifold, WriteLeavesTheStreamPrecisionUnchanged) {
  TypeParam vertex;
  std::ostringstream out;
  out.precision(3);
  vertex.write(out);
  EXPECT_EQ(out.precision(), 3);
}

}  // namespace
}  // namespace dualgraph
