// SPDX-License-Identifier: MIT
// VertexSE3 behaviours beyond the manifold laws: right increments, periodic
// re-orthonormalisation.
#include "dualgraph/types/vertex_se3.h"

#include <gtest/gtest.h>

#include "test/types/test_states.h"

namespace dualgraph {
namespace {

double orthonormalityError(const Eigen::Matrix3d& r) {
  return (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

TEST(VertexSE3, PlusAppliesTheG2oIncrementOnTheRight) {
  testing::Rng rng(testing::kSeed);
  const Eigen::Isometry3d world_T_body = testing::randomPose(rng, testing::Regime::kRandom);
  const Vector6d delta = testing::randomG2oTangent(rng, testing::Regime::kRandom);
  VertexSE3 vertex;
  vertex.setEstimate(world_T_body);
  vertex.plus(delta.data());
  EXPECT_LT((vertex.estimate().matrix() - (world_T_body * g2oIncrement(delta)).matrix()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(VertexSE3, ReorthonormalisesTheRotationEvery1000Increments) {
  Eigen::Isometry3d drifted = Eigen::Isometry3d::Identity();
  drifted.linear() = so3Exp(Eigen::Vector3d(0.3, -0.2, 0.5)) * (1.0 + 1e-6);
  VertexSE3 vertex;
  vertex.setEstimate(drifted);
  const Vector6d zero = Vector6d::Zero();
  for (int k = 1; k < VertexSE3::kOrthonormaliseEvery; ++k) vertex.plus(zero.data());
  EXPECT_GT(orthonormalityError(vertex.estimate().linear()), 1e-6);
  vertex.plus(zero.data());
  EXPECT_LT(orthonormalityError(vertex.estimate().linear()), 1e-11);
}

TEST(VertexSE3, LongRunsOfIncrementsStayOnSO3) {
  testing::Rng rng(testing::kSeed + 1);
  VertexSE3 vertex;
  for (int k = 0; k < 20000; ++k) {
    const Vector6d delta = 0.05 * testing::randomG2oTangent(rng, testing::Regime::kRandom);
    vertex.plus(delta.data());
  }
  EXPECT_LT(orthonormalityError(vertex.estimate().linear()), 1e-12);
}

}  // namespace
}  // namespace dualgraph
