// SPDX-License-Identifier: MIT
// registerBuiltinTypes and a graph with every type through the g2o reader and writer.
#include "dualgraph/types/register_types.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "dualgraph/core/g2o_io.h"
#include "test/types/every_type_g2o.h"

namespace dualgraph {
namespace {

const std::vector<std::string> kVertexTags = {"VERTEX_SE2", "VERTEX_SE3:QUAT", "VERTEX_TRACKXYZ"};
const std::vector<std::string> kEdgeTags = {"EDGE_POINTXYZ_PRIOR", "EDGE_SE2", "EDGE_SE3:QUAT",
                                            "EDGE_SE3_CORNER_PROJECTION", "EDGE_SE3_PRIOR", "EDGE_SE3_TRACKXYZ"};
const std::vector<std::string> kParameterTags = {"PARAMS_SE3OFFSET"};

TEST(RegisterBuiltinTypes, RegistersEveryG2oTag) {
  TypeRegistry registry;
  ASSERT_TRUE(registerBuiltinTypes(registry).ok());
  EXPECT_EQ(registry.tags(TypeRegistry::Kind::kVertex), kVertexTags);
  EXPECT_EQ(registry.tags(TypeRegistry::Kind::kEdge), kEdgeTags);
  EXPECT_EQ(registry.tags(TypeRegistry::Kind::kParameter), kParameterTags);
}

TEST(RegisterBuiltinTypes, CreatedObjectsMapBackToTheirTag) {
  TypeRegistry registry;
  ASSERT_TRUE(registerBuiltinTypes(registry).ok());
  for (const std::string& tag : kVertexTags) EXPECT_EQ(*registry.tagOf(*registry.createVertex(tag)), tag);
  for (const std::string& tag : kEdgeTags) EXPECT_EQ(*registry.tagOf(*registry.createEdge(tag)), tag);
  for (const std::string& tag : kParameterTags) EXPECT_EQ(*registry.tagOf(*registry.createParameter(tag)), tag);
}

TEST(RegisterBuiltinTypes, SecondRegistrationReportsAlreadyExists) {
  TypeRegistry registry;
  ASSERT_TRUE(registerBuiltinTypes(registry).ok());
  const Status again = registerBuiltinTypes(registry);
  EXPECT_EQ(again.code(), StatusCode::kAlreadyExists);
}

TEST(RegisterBuiltinTypes, GraphWithEveryTypeRoundTripsThroughG2oText) {
  const std::string text = testing::everyTypeG2oText();
  TypeRegistry registry;
  ASSERT_TRUE(registerBuiltinTypes(registry).ok());
  Graph graph;
  std::istringstream in(text);
  const auto report = readG2o(in, "every_type.g2o", registry, graph);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->vertices, 5);
  EXPECT_EQ(report->edges, 5);
  EXPECT_EQ(report->parameters, 1);
  const double chi2 = graph.chi2();
  EXPECT_GT(chi2, 0.0);

  std::stringstream first;
  ASSERT_TRUE(writeG2o(first, registry, graph).ok());
  Graph reread;
  ASSERT_TRUE(readG2o(first, "first", registry, reread).ok());
  std::stringstream second;
  ASSERT_TRUE(writeG2o(second, registry, reread).ok());
  EXPECT_EQ(first.str(), second.str());
  EXPECT_DOUBLE_EQ(reread.chi2(), chi2);
  EXPECT_TRUE(reread.vertex(0)->fixed());
}

}  // namespace
}  // namespace dualgraph
