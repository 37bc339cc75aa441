// SPDX-License-Identifier: MIT
// cloneGraph and clone(): a graph of every built-in type copied whole, independent of its source, and a type
// without clone() refused by name.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/graph.h"
#include "dualgraph/core/robust_kernel.h"
#include "dualgraph/types/edge_se3_corner_projection.h"
#include "dualgraph/types/register_types.h"
#include "dualgraph/types/vertex_se3.h"
#include "test/core/user_types.h"
#include "test/types/every_type_g2o.h"

namespace dualgraph {
namespace {

/// Every built-in vertex, edge and parameter type (the corner projection built in code), one with a kernel.
void buildEveryType(const TypeRegistry& registry, Graph& graph) {
  std::istringstream in(testing::everyTypeG2oText());
  ASSERT_TRUE(readG2o(in, "every_type.g2o", registry, graph).ok());
  auto gate = std::make_unique<VertexSE3>(5);  // the corner's object
  gate->setEstimate(Eigen::Isometry3d(Eigen::Translation3d(4.0, 0.2, 0.1)));
  ASSERT_TRUE(graph.addVertex(std::move(gate)).ok());
  auto corner = std::make_unique<EdgeSE3CornerProjection>();
  corner->setCamera(0, Eigen::Isometry3d(Eigen::Translation3d(0.1, 0.0, 0.2)));
  corner->setPoint(Eigen::Vector3d(0.0, 0.7, 0.7));
  corner->setMeasurement(Eigen::Vector2d(0.2, 0.1));
  corner->setInformation(Eigen::Matrix2d::Identity() * 400.0);
  ASSERT_TRUE(corner->setVertex(0, graph.vertex(1)).ok());
  ASSERT_TRUE(corner->setVertex(1, graph.vertex(5)).ok());
  auto kernel = makeRobustKernel("huber:1.5");
  ASSERT_TRUE(kernel.ok());
  corner->setRobustKernel(*kernel);
  ASSERT_TRUE(graph.addEdge(std::move(corner)).ok());
}

std::string g2oText(const TypeRegistry& registry, const Graph& graph) {
  std::ostringstream out;
  EXPECT_TRUE(writeG2o(out, registry, graph).ok());
  return out.str();
}

TEST(CloneGraph, CopiesEveryBuiltInTypeWholeAndIndependentOfItsSource) {
  TypeRegistry registry;
  ASSERT_TRUE(registerBuiltinTypes(registry).ok());
  Graph source;
  buildEveryType(registry, source);
  ASSERT_EQ(source.numEdges(), 6u);
  Graph copy;
  ASSERT_TRUE(cloneGraph(source, copy).ok());
  ASSERT_EQ(copy.numVertices(), source.numVertices());
  ASSERT_EQ(copy.numEdges(), source.numEdges());
  EXPECT_EQ(g2oText(registry, copy), g2oText(registry, source));  // parameters, estimates, fixed, measurements, Ω
  EXPECT_EQ(copy.chi2(true), source.chi2(true));                   // the kernel too
  for (size_t e = 0; e < copy.numEdges(); ++e) {
    for (size_t i = 0; i < copy.edges()[e]->numVertices(); ++i) {
      EXPECT_EQ(copy.edges()[e]->vertex(i), copy.vertex(source.edges()[e]->vertex(i)->id())) << "edge " << e;
    }
  }
  // Moving the copy's vertices leaves the source as it was; an undo stack is not copied.
  const std::string before = g2oText(registry, source);
  const double delta[6] = {0.1, -0.2, 0.05, 0.01, 0.02, -0.03};
  for (const auto& [id, vertex] : copy.vertices()) vertex->plus(delta);
  EXPECT_NE(g2oText(registry, copy), before);
  EXPECT_EQ(g2oText(registry, source), before);
  source.vertex(1)->push();
  Graph again;
  ASSERT_TRUE(cloneGraph(source, again).ok());
  EXPECT_EQ(again.vertex(1)->stackSize(), 0u);
}

TEST(CloneGraph, RefusesATypeWithoutCloneByNameAndANonEmptyTarget) {
  Graph source;
  ASSERT_TRUE(source.addVertex(std::make_unique<testing::VertexPoint2>(0)).ok());
  ASSERT_TRUE(source.addVertex(std::make_unique<testing::VertexPoint2>(1)).ok());
  Graph copy;
  const Status refused = cloneGraph(source, copy);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.message().find("vertex 0: its type does not implement clone()"), std::string::npos)
      << refused.message();
  EXPECT_EQ(copy.numVertices(), 0u);
  Graph full;
  ASSERT_TRUE(full.addVertex(std::make_unique<VertexSE3>(7)).ok());
  Graph empty;
  EXPECT_EQ(cloneGraph(empty, full).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(full.numVertices(), 1u);
}

}  // namespace
}  // namespace dualgraph
