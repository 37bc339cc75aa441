// SPDX-License-Identifier: MIT
// read() of every type: errors name the field, the id or the problem, and quaternions are read
// the way g2o reads them.
#include <gtest/gtest.h>

#include <string>

#include "dualgraph/types/edge_se2.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/edge_se3_prior.h"
#include "dualgraph/types/parameter_se3_offset.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {
namespace {

const std::string kInformation6 = " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1";
const std::string kInformation3 = " 1 0 0 1 0 1";

::testing::AssertionResult failsWith(const Status& status, const std::string& fragment) {
  if (status.ok()) return ::testing::AssertionFailure() << "read succeeded, expected \"" << fragment << "\"";
  if (status.message().find(fragment) == std::string::npos) {
    return ::testing::AssertionFailure() << "message \"" << status.message() << "\" lacks \"" << fragment << "\"";
  }
  return ::testing::AssertionSuccess();
}

Status readVertexSE3(const std::string& fields, VertexSE3& vertex) {
  TokenReader in(fields, "graph.g2o", 5);
  return vertex.read(in);
}

template <typename E>
Status readEdge(const std::string& fields, const ParameterContainer& parameters = ParameterContainer()) {
  E edge;
  TokenReader in(fields, "graph.g2o", 9);
  return edge.read(in, parameters);
}

TEST(VertexSE3, ReadRejectsAZeroNormQuaternion) {
  VertexSE3 vertex;
  const Status status = readVertexSE3("1 2 3 0 0 0 0", vertex);
  EXPECT_TRUE(failsWith(status, "graph.g2o:5: zero-norm quaternion (qx qy qz qw)"));
  EXPECT_EQ(status.code(), StatusCode::kParseError);
  EXPECT_TRUE(failsWith(readVertexSE3("1 2 3 1e-13 0 0 1e-13", vertex), "zero-norm quaternion"));
}

TEST(VertexSE3, ReadRejectsNaNAndInfinity) {
  VertexSE3 vertex;
  EXPECT_TRUE(failsWith(readVertexSE3("1 2 3 nan 0 0 1", vertex), "field 'qx' is not finite"));
  EXPECT_TRUE(failsWith(readVertexSE3("1 2 inf 0 0 0 1", vertex), "field 'z' is not finite"));
  EXPECT_TRUE(failsWith(readVertexSE3("0 0 0 1e200 1e200 0 1", vertex), "non-finite norm"));
}

TEST(VertexSE3, ReadReportsTheFirstMissingField) {
  VertexSE3 vertex;
  EXPECT_TRUE(failsWith(readVertexSE3("1 2 3 0 0 0", vertex), "line ends before field 'qw'"));
}

TEST(VertexSE3, ReadLeavesTheEstimateUnchangedOnError) {
  VertexSE3 vertex;
  ASSERT_TRUE(readVertexSE3("1 2 3 0 0 0 1", vertex).ok());
  EXPECT_FALSE(readVertexSE3("4 5 6 0 0 0 0", vertex).ok());
  EXPECT_EQ(vertex.estimate().translation(), Eigen::Vector3d(1, 2, 3));
}

TEST(VertexSE3, ReadKeepsANearUnitQuaternionAsWrittenLikeG2o) {
  // g2o builds the rotation from the quaternion as written; normalising would change the χ² of
  // the public datasets (6-digit quaternions) by up to 2e-8 relative.
  VertexSE3 vertex;
  ASSERT_TRUE(readVertexSE3("0 0 0 0.1 0.2 0.3 0.9273623", vertex).ok());
  const Eigen::Matrix3d as_written = quatFromXyzw(0.1, 0.2, 0.3, 0.9273623).toRotationMatrix();
  EXPECT_EQ(vertex.estimate().linear(), as_written);
  const Eigen::Matrix3d normalised = quatFromXyzw(0.1, 0.2, 0.3, 0.9273623).normalized().toRotationMatrix();
  EXPECT_GT((as_written - normalised).cwiseAbs().maxCoeff(), 1e-8);  // the choice is visible
}

TEST(VertexSE3, ReadNormalisesAQuaternionFarFromUnitNorm) {
  VertexSE3 vertex;
  ASSERT_TRUE(readVertexSE3("0 0 0 0.2 0.4 0.6 1.8", vertex).ok());
  const Eigen::Matrix3d rotation = vertex.estimate().linear();
  EXPECT_LT((rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((rotation - quatFromXyzw(0.2, 0.4, 0.6, 1.8).normalized().toRotationMatrix()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(EdgeSE3, ReadNormalisesTheMeasurementQuaternionLikeG2o) {
  EdgeSE3 edge;
  const std::string line = "1 2 3 0 0 0.1 1.0" + kInformation6;  // TokenReader keeps views into it
  TokenReader in(line, "graph.g2o", 1);
  ASSERT_TRUE(edge.read(in, ParameterContainer()).ok());
  EXPECT_LT((edge.measurement().linear() - quatFromXyzw(0, 0, 0.1, 1.0).normalized().toRotationMatrix())
                .cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(edge.information(), (Eigen::Matrix<double, 6, 6>::Identity()));
}

TEST(EdgeSE3, ReadRejectsAZeroNormQuaternionAndMissingInformation) {
  EXPECT_TRUE(failsWith(readEdge<EdgeSE3>("1 2 3 0 0 0 0" + kInformation6), "zero-norm quaternion"));
  EXPECT_TRUE(failsWith(readEdge<EdgeSE3>("1 2 3 0 0 0 1 1 0 0"), "line ends before field 'information[3]'"));
  EXPECT_TRUE(failsWith(readEdge<EdgeSE3>("1 2 3 0 0 0 1 1 0 nan" + kInformation6), "'information[2]' is not finite"));
}

TEST(EdgeSE3Prior, ReadRejectsAnUnknownParameterId) {
  const Status status = readEdge<EdgeSE3Prior>("7 0 0 0 0 0 0 1" + kInformation6);
  EXPECT_TRUE(failsWith(status, "graph.g2o:9: unknown parameter id 7"));
}

TEST(EdgeSE3Prior, ReadRejectsAParameterOfAnotherType) {
  struct OtherParameter : ParameterBase {
    using ParameterBase::ParameterBase;
    Status read(TokenReader&) override { return Status(); }
    void write(std::ostream&) const override {}
  };
  ParameterContainer parameters;
  ASSERT_TRUE(parameters.add(std::make_unique<OtherParameter>(7)).ok());
  EXPECT_TRUE(failsWith(readEdge<EdgeSE3Prior>("7 0 0 0 0 0 0 1" + kInformation6, parameters),
                        "parameter id 7 is not a PARAMS_SE3OFFSET"));
}

TEST(EdgeSE3Prior, ReadCopiesTheOffsetOfItsParameter) {
  ParameterContainer parameters;
  Eigen::Isometry3d body_T_sensor = Eigen::Isometry3d::Identity();
  body_T_sensor.translation() = Eigen::Vector3d(0.1, 0.2, 0.3);
  ASSERT_TRUE(parameters.add(std::make_unique<ParameterSE3Offset>(4, body_T_sensor)).ok());
  EdgeSE3Prior edge;
  const std::string line = "4 0 0 0 0 0 0 1" + kInformation6;
  TokenReader in(line, "graph.g2o", 1);
  ASSERT_TRUE(edge.read(in, parameters).ok());
  EXPECT_EQ(edge.parameterId(), 4);
  EXPECT_EQ(edge.offset().matrix(), body_T_sensor.matrix());
}

TEST(EdgeSE3Prior, ReadKeepsANearUnitQuaternionAsWrittenLikeG2o) {
  ParameterContainer parameters;
  ASSERT_TRUE(parameters.add(std::make_unique<ParameterSE3Offset>(0)).ok());
  EdgeSE3Prior edge;
  const std::string line = "0 0 0 0 0.1 0.2 0.3 0.9273623" + kInformation6;
  TokenReader in(line, "graph.g2o", 1);
  ASSERT_TRUE(edge.read(in, parameters).ok());
  EXPECT_EQ(edge.measurement().linear(), quatFromXyzw(0.1, 0.2, 0.3, 0.9273623).toRotationMatrix());
}

TEST(EdgeSE3Prior, BuiltInCodeUsesTheIdentityOffsetWithParameterIdZero) {
  EdgeSE3Prior edge;
  EXPECT_EQ(edge.parameterId(), 0);
  EXPECT_EQ(edge.offset().matrix(), Eigen::Matrix4d::Identity());
}

TEST(EdgeSE3PointXYZ, ReadRejectsAnUnknownParameterIdAndNaN) {
  EXPECT_TRUE(failsWith(readEdge<EdgeSE3PointXYZ>("2 1 2 3" + kInformation3), "unknown parameter id 2"));
  ParameterContainer parameters;
  ASSERT_TRUE(parameters.add(std::make_unique<ParameterSE3Offset>(2)).ok());
  EXPECT_TRUE(failsWith(readEdge<EdgeSE3PointXYZ>("2 1 nan 3" + kInformation3, parameters), "field 'my' is not finite"));
  EXPECT_TRUE(readEdge<EdgeSE3PointXYZ>("2 1 2 3" + kInformation3, parameters).ok());
}

TEST(EdgeSE2, ReadRejectsNaNAndMissingFields) {
  EXPECT_TRUE(failsWith(readEdge<EdgeSE2>("1 0 nan" + kInformation3), "field 'dtheta' is not finite"));
  EXPECT_TRUE(failsWith(readEdge<EdgeSE2>("1 0"), "line ends before field 'dtheta'"));
  EXPECT_TRUE(failsWith(readEdge<EdgeSE2>("1 0 0.5 1 0 0 1 0"), "line ends before field 'information[5]'"));
}

TEST(ParameterSE3Offset, ReadRejectsAZeroNormQuaternionAndNormalisesOthers) {
  ParameterSE3Offset parameter(1);
  TokenReader bad("0 0 0 0 0 0 0", "graph.g2o", 2);
  EXPECT_TRUE(failsWith(parameter.read(bad), "zero-norm quaternion"));
  TokenReader good("0 0 0 0 0 0 2", "graph.g2o", 2);
  ASSERT_TRUE(parameter.read(good).ok());
  EXPECT_EQ(parameter.offset().matrix(), Eigen::Matrix4d::Identity());
}

}  // namespace
}  // namespace dualgraph
