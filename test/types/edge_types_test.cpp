// SPDX-License-Identifier: MIT
// Every edge type in one typed suite: analytic Jacobians against central differences at random
// states, near the identity and near π rotations; zero error when the measurement is generated
// from the state; a write→read→write round trip through the type's own write()/read().
// Adding a type = one EdgeTraits specialisation + one entry in EdgeTypes.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "test/testing/jacobian_check.h"
#include "test/types/test_states.h"
#include "dualgraph/types/edge_point_xyz_prior.h"
#include "dualgraph/types/edge_se2.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_corner_projection.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/edge_se3_prior.h"
#include "dualgraph/types/parameter_se3_offset.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

using testing::Regime;
using testing::Rng;

/// An edge with the vertices and parameters it needs.
template <typename E>
struct EdgeCase {
  std::vector<std::unique_ptr<VertexBase>> vertices;
  ParameterContainer parameters;
  std::unique_ptr<E> edge = std::make_unique<E>();

  template <typename V>
  V& addVertex(const typename V::Estimate& estimate) {
    auto vertex = std::make_unique<V>(static_cast<int>(vertices.size()));
    vertex->setEstimate(estimate);
    V& ref = *vertex;
    if (!edge->setVertex(vertices.size(), vertex.get()).ok()) throw std::logic_error("setVertex failed");
    vertices.push_back(std::move(vertex));
    return ref;
  }
};

Vector6d noiseVector(Rng& rng, double noise) {
  Vector6d v;
  for (int k = 0; k < 6; ++k) v[k] = noise * testing::gaussian(rng);
  return v;
}

Eigen::Isometry3d noisePose(Rng& rng, double noise) { return se3Exp(noiseVector(rng, noise)); }

Eigen::Vector3d noisePoint(Rng& rng, double noise) { return noiseVector(rng, noise).head<3>(); }

constexpr int kOffsetId = 3;

/// EdgeTraits<E>::build(c, rng, regime, noise): vertices drawn in the regime, the measurement
/// generated from them and then perturbed by `noise`, a random SPD information.
template <typename E>
struct EdgeTraits;

template <>
struct EdgeTraits<EdgeSE3> {
  static constexpr const char* kName = "EdgeSE3";
  static void build(EdgeCase<EdgeSE3>& c, Rng& rng, Regime regime, double noise) {
    const auto& world_T_i = c.addVertex<VertexSE3>(testing::randomPose(rng, regime)).estimate();
    const auto& world_T_j = c.addVertex<VertexSE3>(testing::randomPose(rng, regime)).estimate();
    c.edge->setMeasurement(world_T_i.inverse() * world_T_j * noisePose(rng, noise));
    c.edge->setInformation(testing::randomInformation<6>(rng));
  }
};

template <>
struct EdgeTraits<EdgeSE3Prior> {
  static constexpr const char* kName = "EdgeSE3Prior";
  static void build(EdgeCase<EdgeSE3Prior>& c, Rng& rng, Regime regime, double noise) {
    const auto& world_T_body = c.addVertex<VertexSE3>(testing::randomPose(rng, regime)).estimate();
    const Eigen::Isometry3d body_T_sensor = testing::randomPose(rng, regime);
    (void)c.parameters.add(std::make_unique<ParameterSE3Offset>(kOffsetId, body_T_sensor));
    c.edge->setOffset(kOffsetId, body_T_sensor);
    c.edge->setMeasurement(world_T_body * body_T_sensor * noisePose(rng, noise));
    c.edge->setInformation(testing::randomInformation<6>(rng));
  }
};

template <>
struct EdgeTraits<EdgeSE3PointXYZ> {
  static constexpr const char* kName = "EdgeSE3PointXYZ";
  static void build(EdgeCase<EdgeSE3PointXYZ>& c, Rng& rng, Regime regime, double noise) {
    const auto& world_T_body = c.addVertex<VertexSE3>(testing::randomPose(rng, regime)).estimate();
    const auto& p_world = c.addVertex<VertexPointXYZ>(testing::randomPoint(rng, Regime::kRandom)).estimate();
    const Eigen::Isometry3d body_T_sensor = testing::randomPose(rng, regime);
    (void)c.parameters.add(std::make_unique<ParameterSE3Offset>(kOffsetId, body_T_sensor));
    c.edge->setOffset(kOffsetId, body_T_sensor);
    c.edge->setMeasurement((world_T_body * body_T_sensor).inverse() * p_world + noisePoint(rng, noise));
    c.edge->setInformation(testing::randomInformation<3>(rng));
  }
};

template <>
struct EdgeTraits<EdgeSE3CornerProjection> {
  static constexpr const char* kName = "EdgeSE3CornerProjection";
  static void build(EdgeCase<EdgeSE3CornerProjection>& c, Rng& rng, Regime regime, double noise) {
    const auto& world_T_body = c.addVertex<VertexSE3>(testing::randomPose(rng, regime)).estimate();
    const Eigen::Isometry3d body_T_camera = testing::randomPose(rng, regime);
    // A point 1–5 m in front of the camera, on an object pose drawn in the regime.
    const Eigen::Vector3d p_camera(testing::gaussian(rng), testing::gaussian(rng), 3.0 + 2.0 * std::tanh(testing::gaussian(rng)));
    const Eigen::Vector3d p_object = testing::randomPoint(rng, Regime::kRandom);
    Eigen::Isometry3d world_T_object = testing::randomPose(rng, regime);
    world_T_object.translation() += world_T_body * body_T_camera * p_camera - world_T_object * p_object;
    c.template addVertex<VertexSE3>(world_T_object);
    (void)c.parameters.add(std::make_unique<ParameterSE3Offset>(kOffsetId, body_T_camera));
    c.edge->setCamera(kOffsetId, body_T_camera);
    c.edge->setPoint(p_object);
    c.edge->setMeasurement(p_camera.head<2>() / p_camera.z() + noise * noisePoint(rng, 0.1).head<2>());
    c.edge->setInformation(testing::randomInformation<2>(rng));
  }
};

template <>
struct EdgeTraits<EdgePointXYZPrior> {
  static constexpr const char* kName = "EdgePointXYZPrior";
  static void build(EdgeCase<EdgePointXYZPrior>& c, Rng& rng, Regime regime, double noise) {
    const auto& p_world = c.addVertex<VertexPointXYZ>(testing::randomPoint(rng, regime)).estimate();
    c.edge->setMeasurement(p_world + noisePoint(rng, noise));
    c.edge->setInformation(testing::randomInformation<3>(rng));
  }
};

template <>
struct EdgeTraits<EdgeSE2> {
  static constexpr const char* kName = "EdgeSE2";
  static void build(EdgeCase<EdgeSE2>& c, Rng& rng, Regime regime, double noise) {
    const SE2& world_T_i = c.addVertex<VertexSE2>(testing::randomSE2(rng, regime)).estimate();
    const SE2& world_T_j = c.addVertex<VertexSE2>(testing::randomSE2(rng, regime)).estimate();
    const Vector6d n = noiseVector(rng, noise);
    c.edge->setMeasurement(world_T_i.inverse() * world_T_j * SE2(n[0], n[1], n[2]));
    c.edge->setInformation(testing::randomInformation<3>(rng));
  }
};

template <typename E>
EdgeCase<E> makeEdgeCase(Rng& rng, Regime regime, double noise) {
  EdgeCase<E> c;
  EdgeTraits<E>::build(c, rng, regime, noise);
  return c;
}

template <typename E>
class EdgeTypes : public ::testing::Test {
 protected:
  /// Jacobians at `samples` states of the regime, measurements perturbed by `noise`.
  static void expectJacobiansMatch(Regime regime, double noise, int samples, unsigned seed) {
    Rng rng(seed);
    for (int k = 0; k < samples; ++k) {
      EdgeCase<E> c = makeEdgeCase<E>(rng, regime, noise);
      ASSERT_TRUE(testing::analyticJacobiansMatchNumeric(*c.edge)) << "sample " << k;
    }
  }
};

struct EdgeNames {
  template <typename E>
  static std::string GetName(int) { return EdgeTraits<E>::kName; }
};

using AllEdgeTypes =
    ::testing::Types<EdgeSE3, EdgeSE3Prior, EdgeSE3PointXYZ, EdgeSE3CornerProjection, EdgePointXYZPrior, EdgeSE2>;
TYPED_TEST_SUITE(EdgeTypes, AllEdgeTypes, EdgeNames);

TYPED_TEST(EdgeTypes, AnalyticJacobianMatchesNumericAtRandomStates) {
  TestFixture::expectJacobiansMatch(Regime::kRandom, 0.5, 200, testing::kSeed);
}

TYPED_TEST(EdgeTypes, AnalyticJacobianMatchesNumericNearIdentity) {
  TestFixture::expectJacobiansMatch(Regime::kIdentity, 0.0, 20, testing::kSeed + 1);
  TestFixture::expectJacobiansMatch(Regime::kIdentity, 1e-3, 50, testing::kSeed + 2);
  TestFixture::expectJacobiansMatch(Regime::kTinyAngle, 1e-8, 50, testing::kSeed + 3);
}

TYPED_TEST(EdgeTypes, AnalyticJacobianMatchesNumericNearPi) {
  TestFixture::expectJacobiansMatch(Regime::kNearPi, 0.0, 50, testing::kSeed + 4);
  TestFixture::expectJacobiansMatch(Regime::kNearPi, 0.1, 100, testing::kSeed + 5);
}

TYPED_TEST(EdgeTypes, ErrorIsZeroWhenTheMeasurementIsGeneratedFromTheState) {
  Rng rng(testing::kSeed + 6);
  for (const Regime regime : {Regime::kRandom, Regime::kIdentity, Regime::kTinyAngle, Regime::kNearPi}) {
    for (int k = 0; k < 100; ++k) {
      EdgeCase<TypeParam> c = makeEdgeCase<TypeParam>(rng, regime, 0.0);
      c.edge->computeError();
      ASSERT_LT(c.edge->error().cwiseAbs().maxCoeff(), 1e-12)
          << "regime " << static_cast<int>(regime) << ": " << c.edge->error().transpose();
      EXPECT_LT(c.edge->chi2(), 1e-20);
    }
  }
}

TYPED_TEST(EdgeTypes, ErrorIsNonZeroWhenTheMeasurementIsPerturbed) {
  Rng rng(testing::kSeed + 7);
  EdgeCase<TypeParam> c = makeEdgeCase<TypeParam>(rng, Regime::kRandom, 0.1);
  c.edge->computeError();
  EXPECT_GT(c.edge->error().norm(), 1e-3);
}

TYPED_TEST(EdgeTypes, WriteReadWriteIsBitIdentical) {
  Rng rng(testing::kSeed + 8);
  for (const Regime regime : {Regime::kRandom, Regime::kIdentity, Regime::kTinyAngle, Regime::kNearPi}) {
    for (int k = 0; k < 50; ++k) {
      EdgeCase<TypeParam> c = makeEdgeCase<TypeParam>(rng, regime, 0.3);
      std::ostringstream first;
      c.edge->write(first);

      TypeParam reread;
      for (size_t slot = 0; slot < c.vertices.size(); ++slot) {
        ASSERT_TRUE(reread.setVertex(slot, c.vertices[slot].get()).ok());
      }
      const std::string line = first.str();  // TokenReader keeps views into the line
      TokenReader in(line, "<test>", 1);
      const Status status = reread.read(in, c.parameters);
      ASSERT_TRUE(status.ok()) << status.toString() << "\n" << first.str();
      ASSERT_TRUE(in.finish().ok()) << first.str();
      std::ostringstream second;
      reread.write(second);
      ASSERT_EQ(first.str(), second.str());

      EXPECT_EQ(reread.information(), c.edge->information());
      c.edge->computeError();
      reread.computeError();
      EXPECT_LT((reread.error() - c.edge->error()).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Regimes specific to one type.
// ---------------------------------------------------------------------------------------------

TEST(EdgeSE3, AnalyticJacobianMatchesNumericWhenTheErrorRotationIsNearPi) {
  // g2o's chart is smooth while the error quaternion's w stays positive; here w ≈ sin(0.01).
  Rng rng(testing::kSeed + 9);
  for (int k = 0; k < 50; ++k) {
    EdgeCase<EdgeSE3> c = makeEdgeCase<EdgeSE3>(rng, Regime::kRandom, 0.0);
    Eigen::Isometry3d error_pose = Eigen::Isometry3d::Identity();
    error_pose.linear() = so3Exp((testing::kPi - 0.02) * testing::randomUnitVector(rng));
    error_pose.translation() = testing::randomPoint(rng, Regime::kRandom);
    c.edge->setMeasurement(c.edge->measurement() * error_pose.inverse());
    c.edge->computeError();
    ASSERT_GT(c.edge->error().tail<3>().norm(), 0.999);
    ASSERT_TRUE(testing::analyticJacobiansMatchNumeric(*c.edge)) << "sample " << k;
  }
}

TEST(EdgeSE3, ErrorIsTheG2oChartOfTheErrorPoseWithWNonNegative) {
  Rng rng(testing::kSeed + 10);
  EdgeCase<EdgeSE3> c = makeEdgeCase<EdgeSE3>(rng, Regime::kRandom, 0.5);
  c.edge->computeError();
  const Eigen::Isometry3d& world_T_i = static_cast<VertexSE3*>(c.vertices[0].get())->estimate();
  const Eigen::Isometry3d& world_T_j = static_cast<VertexSE3*>(c.vertices[1].get())->estimate();
  const Eigen::Isometry3d error_pose = c.edge->measurement().inverse() * world_T_i.inverse() * world_T_j;
  Eigen::Quaterniond q(error_pose.linear());
  if (q.w() < 0.0) q.coeffs() *= -1.0;
  EXPECT_LT((c.edge->error().head<3>() - error_pose.translation()).norm(), 1e-12);
  EXPECT_LT((c.edge->error().tail<3>() - q.vec()).norm(), 1e-12);
}

TEST(EdgeSE2, ErrorAngleIsWrappedAcrossPi) {
  EdgeCase<EdgeSE2> c;
  c.addVertex<VertexSE2>(SE2(0.0, 0.0, 3.1));
  c.addVertex<VertexSE2>(SE2(0.0, 0.0, -3.1));
  c.edge->setMeasurement(SE2(0.0, 0.0, 0.0));
  c.edge->computeError();
  EXPECT_NEAR(c.edge->error()[2], 2.0 * testing::kPi - 6.2, 1e-12);
}

}  // namespace
}  // namespace dualgraph
