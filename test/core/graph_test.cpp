// SPDX-License-Identifier: MIT
// Graph ownership and invariants, the structure version, the gauge choice, ParameterContainer.
#include <gtest/gtest.h>

#include <memory>

#include "dualgraph/core/graph.h"
#include "test/core/test_fixtures.h"

namespace dualgraph {
namespace {

using testing::addEdge;
using testing::addPoint;
using testing::EdgePoint2Prior;
using testing::EdgePoint2Range;
using testing::EdgePoint2Relative;
using testing::VertexPoint2;
using testing::VertexVector;

TEST(Graph, AddVertexStoresItUnderItsId) {
  Graph graph;
  EXPECT_EQ(graph.numVertices(), 0u);
  auto owned = std::make_unique<VertexPoint2>(5);
  VertexPoint2* raw = owned.get();
  ASSERT_TRUE(graph.addVertex(std::move(owned)).ok());
  EXPECT_EQ(graph.numVertices(), 1u);
  EXPECT_EQ(graph.vertex(5), raw);
  EXPECT_EQ(graph.vertexAs<VertexPoint2>(5), raw);
  EXPECT_EQ(graph.vertex(6), nullptr);
  EXPECT_EQ(graph.vertexAs<VertexPoint2>(6), nullptr);
  EXPECT_EQ(graph.vertexAs<VertexVector<3>>(5), nullptr) << "wrong type";
}

TEST(Graph, AddVertexRejectsDuplicateNegativeAndNullWithoutChangingTheGraph) {
  Graph graph;
  VertexPoint2* first = addPoint(graph, 3, {1, 2});
  const uint64_t version = graph.structureVersion();

  const Status duplicate = graph.addVertex(std::make_unique<VertexPoint2>(3));
  EXPECT_EQ(duplicate.code(), StatusCode::kAlreadyExists);
  EXPECT_TRUE(testing::contains(duplicate.message(), "3"));
  EXPECT_EQ(graph.vertex(3), first) << "the original vertex is kept";

  const Status negative = graph.addVertex(std::make_unique<VertexPoint2>(-1));
  EXPECT_EQ(negative.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(testing::contains(negative.message(), "-1"));

  EXPECT_EQ(graph.addVertex(nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(graph.numVertices(), 1u);
  EXPECT_EQ(graph.structureVersion(), version) << "failed mutations leave the version alone";
}

TEST(Graph, VerticesIterateInIncreasingIdOrderAndEdgesInInsertionOrder) {
  Graph graph;
  for (int id : {7, 2, 9, 0, 4}) addPoint(graph, id, {0, 0});
  int previous = -1;
  for (const auto& [id, vertex] : graph.vertices()) {
    EXPECT_GT(id, previous);
    EXPECT_EQ(vertex->id(), id);
    previous = id;
  }
  EdgeBase* a = addEdge<EdgePoint2Relative>(graph, {9, 2}, {0, 0});
  EdgeBase* b = addEdge<EdgePoint2Prior>(graph, {0}, {0, 0});
  EdgeBase* c = addEdge<EdgePoint2Range>(graph, {4, 7}, 1.0);
  ASSERT_EQ(graph.numEdges(), 3u);
  EXPECT_EQ(graph.edges()[0].get(), a);
  EXPECT_EQ(graph.edges()[1].get(), b);
  EXPECT_EQ(graph.edges()[2].get(), c);
}

TEST(Graph, AddEdgeReturnsTheStoredEdge) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  addPoint(graph, 1, {1, 0});
  auto edge = std::make_unique<EdgePoint2Relative>();
  EdgePoint2Relative* raw = edge.get();
  ASSERT_TRUE(edge->setVertex(0, graph.vertex(0)).ok());
  ASSERT_TRUE(edge->setVertex(1, graph.vertex(1)).ok());
  auto added = graph.addEdge(std::move(edge));
  ASSERT_TRUE(added.ok());
  EXPECT_EQ(*added, raw);
  EXPECT_EQ(graph.numEdges(), 1u);
}

TEST(Graph, AddEdgeToAVertexNotInTheGraphIsNotFound) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  addPoint(graph, 1, {1, 0});
  const uint64_t version = graph.structureVersion();

  VertexPoint2 stranger(7);  // never added
  auto edge = std::make_unique<EdgePoint2Relative>();
  ASSERT_TRUE(edge->setVertex(0, graph.vertex(0)).ok());
  ASSERT_TRUE(edge->setVertex(1, &stranger).ok());
  auto added = graph.addEdge(std::move(edge));
  ASSERT_FALSE(added.ok());
  EXPECT_EQ(added.status().code(), StatusCode::kNotFound);
  EXPECT_TRUE(testing::contains(added.status().message(), "7"));

  VertexPoint2 impostor(1);  // same id as a vertex of the graph, but a different object
  auto edge2 = std::make_unique<EdgePoint2Relative>();
  ASSERT_TRUE(edge2->setVertex(0, graph.vertex(0)).ok());
  ASSERT_TRUE(edge2->setVertex(1, &impostor).ok());
  EXPECT_EQ(graph.addEdge(std::move(edge2)).status().code(), StatusCode::kNotFound);

  EXPECT_EQ(graph.numEdges(), 0u);
  EXPECT_EQ(graph.structureVersion(), version);
}

TEST(Graph, AddEdgeRejectsSelfLoopEmptySlotAndNull) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  auto loop = std::make_unique<EdgePoint2Relative>();
  ASSERT_TRUE(loop->setVertex(0, graph.vertex(0)).ok());
  ASSERT_TRUE(loop->setVertex(1, graph.vertex(0)).ok());
  auto added = graph.addEdge(std::move(loop));
  ASSERT_FALSE(added.ok());
  EXPECT_EQ(added.status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(testing::contains(added.status().message(), "itself"));

  auto half = std::make_unique<EdgePoint2Relative>();
  ASSERT_TRUE(half->setVertex(0, graph.vertex(0)).ok());
  EXPECT_EQ(graph.addEdge(std::move(half)).status().code(), StatusCode::kInvalidArgument);

  EXPECT_EQ(graph.addEdge(nullptr).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(graph.numEdges(), 0u);
}

TEST(Graph, RemoveVertexRemovesExactlyItsIncidentEdges) {
  Graph graph;
  for (int id = 0; id < 4; ++id) addPoint(graph, id, {static_cast<double>(id), 0.0});
  EdgeBase* e01 = addEdge<EdgePoint2Relative>(graph, {0, 1}, {1, 0});
  addEdge<EdgePoint2Relative>(graph, {2, 1}, {1, 0});
  EdgeBase* e23 = addEdge<EdgePoint2Range>(graph, {2, 3}, 1.0);
  addEdge<EdgePoint2Prior>(graph, {1}, {1, 0});
  EdgeBase* e30 = addEdge<EdgePoint2Relative>(graph, {3, 0}, {1, 0});
  const uint64_t version = graph.structureVersion();

  ASSERT_TRUE(graph.removeVertex(1).ok());
  EXPECT_EQ(graph.vertex(1), nullptr);
  EXPECT_EQ(graph.numVertices(), 3u);
  ASSERT_EQ(graph.numEdges(), 2u);  // e01, e21 and the prior on 1 are gone
  EXPECT_NE(graph.structureVersion(), version);
  (void)e01;
  EXPECT_EQ(graph.edges()[0].get(), e23);
  EXPECT_EQ(graph.edges()[1].get(), e30);
  EXPECT_TRUE(std::isfinite(graph.chi2())) << "remaining edges point at live vertices";

  EXPECT_EQ(graph.removeVertex(1).code(), StatusCode::kNotFound);
  EXPECT_EQ(graph.removeVertex(42).code(), StatusCode::kNotFound);
}

TEST(Graph, RemoveEdgeRemovesOnlyThatEdge) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  addPoint(graph, 1, {1, 0});
  EdgeBase* a = addEdge<EdgePoint2Relative>(graph, {0, 1}, {1, 0});
  EdgeBase* b = addEdge<EdgePoint2Prior>(graph, {0}, {0, 0});
  ASSERT_TRUE(graph.removeEdge(a).ok());
  ASSERT_EQ(graph.numEdges(), 1u);
  EXPECT_EQ(graph.edges()[0].get(), b);
  EXPECT_EQ(graph.numVertices(), 2u);

  EdgePoint2Prior foreign;
  EXPECT_EQ(graph.removeEdge(&foreign).code(), StatusCode::kNotFound);
  EXPECT_EQ(graph.removeEdge(nullptr).code(), StatusCode::kNotFound);
}

TEST(Graph, StructureVersionChangesOnEveryStructuralMutation) {
  Graph graph;
  uint64_t version = graph.structureVersion();
  auto changed = [&graph, &version] {
    const bool different = graph.structureVersion() != version;
    version = graph.structureVersion();
    return different;
  };
  addPoint(graph, 0, {0, 0});
  EXPECT_TRUE(changed()) << "addVertex";
  addPoint(graph, 1, {1, 0});
  EXPECT_TRUE(changed());
  EdgeBase* edge = addEdge<EdgePoint2Relative>(graph, {0, 1}, {1, 0});
  EXPECT_TRUE(changed()) << "addEdge";
  ASSERT_TRUE(graph.setFixed(0, true).ok());
  EXPECT_TRUE(changed()) << "setFixed true";
  ASSERT_TRUE(graph.setFixed(0, true).ok());
  EXPECT_FALSE(changed()) << "setFixed to the same value";
  ASSERT_TRUE(graph.setFixed(0, false).ok());
  EXPECT_TRUE(changed()) << "setFixed false";
  graph.vertexAs<VertexPoint2>(1)->setEstimate({5, 5});
  (void)graph.chi2();
  EXPECT_FALSE(changed()) << "values are not structure";
  ASSERT_TRUE(graph.removeEdge(edge).ok());
  EXPECT_TRUE(changed()) << "removeEdge";
  ASSERT_TRUE(graph.removeVertex(1).ok());
  EXPECT_TRUE(changed()) << "removeVertex";
  graph.clear();
  EXPECT_TRUE(changed()) << "clear";
  EXPECT_EQ(graph.numVertices(), 0u);
}

TEST(Graph, SetFixedOnAnUnknownIdIsNotFound) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  const Status status = graph.setFixed(3, true);
  EXPECT_EQ(status.code(), StatusCode::kNotFound);
  EXPECT_TRUE(testing::contains(status.message(), "3"));
  ASSERT_TRUE(graph.setFixed(0, true).ok());
  EXPECT_TRUE(graph.vertex(0)->fixed());
}

TEST(Graph, ClearEmptiesVerticesEdgesAndParameters) {
  Graph graph;
  testing::buildRandomPointGraph(graph, 1);
  ASSERT_GT(graph.numEdges(), 0u);
  graph.clear();
  EXPECT_EQ(graph.numVertices(), 0u);
  EXPECT_EQ(graph.numEdges(), 0u);
  EXPECT_TRUE(graph.parameters().all().empty());
}

TEST(Graph, Chi2SumsEdgesWithAndWithoutRobustKernel) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  addPoint(graph, 1, {3, 4});
  Eigen::Matrix2d information;
  information << 2, 0.5, 0.5, 1;
  auto* rel = addEdge<EdgePoint2Relative>(graph, {0, 1}, {0, 0}, information);  // e = (3, 4)
  addEdge<EdgePoint2Range>(graph, {0, 1}, 4.0);                                  // e = 1
  const double s = Eigen::Vector2d(3, 4).dot(information * Eigen::Vector2d(3, 4));
  EXPECT_DOUBLE_EQ(graph.chi2(), s + 1.0);
  EXPECT_DOUBLE_EQ(graph.chi2(true), s + 1.0) << "no kernel: robust = plain";
  rel->setRobustKernel(*makeRobustKernel("huber:2"));
  EXPECT_DOUBLE_EQ(graph.chi2(), s + 1.0);
  EXPECT_DOUBLE_EQ(graph.chi2(true), 2.0 * 2.0 * std::sqrt(s) - 4.0 + 1.0);
}

TEST(Graph, ChooseGaugeVertexPicksTheLargestDimensionAttachedVertex) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  for (int id : {1, 5, 8}) ASSERT_TRUE(graph.addVertex(std::make_unique<VertexVector<3>>(id)).ok());
  addPoint(graph, 9, {0, 0});
  auto edge31 = std::make_unique<testing::EdgeLinear<3, VertexVector<3>, VertexPoint2>>();
  ASSERT_TRUE(edge31->setVertex(0, graph.vertex(5)).ok());
  ASSERT_TRUE(edge31->setVertex(1, graph.vertex(0)).ok());
  ASSERT_TRUE(graph.addEdge(std::move(edge31)).ok());
  auto edge33 = std::make_unique<testing::EdgeLinear<3, VertexVector<3>, VertexVector<3>>>();
  ASSERT_TRUE(edge33->setVertex(0, graph.vertex(8)).ok());
  ASSERT_TRUE(edge33->setVertex(1, graph.vertex(5)).ok());
  ASSERT_TRUE(graph.addEdge(std::move(edge33)).ok());
  addEdge<EdgePoint2Prior>(graph, {9}, {0, 0});
  // Vertex 1 is 3-D but attached to no edge: never the gauge.
  ASSERT_NE(chooseGaugeVertex(graph), nullptr);
  EXPECT_EQ(chooseGaugeVertex(graph)->id(), 5);
  EXPECT_EQ(chooseGaugeVertex(graph, GaugeChoice::kLowestId)->id(), 5);
  EXPECT_EQ(chooseGaugeVertex(graph, GaugeChoice::kHighestId)->id(), 8);
}

TEST(Graph, ChooseGaugeVertexAmongEqualDimensionsFollowsTheChoice) {
  Graph graph;
  for (int id : {3, 1, 4}) addPoint(graph, id, {0, 0});
  addEdge<EdgePoint2Relative>(graph, {4, 3}, {0, 0});
  addEdge<EdgePoint2Relative>(graph, {3, 1}, {0, 0});
  EXPECT_EQ(chooseGaugeVertex(graph, GaugeChoice::kLowestId)->id(), 1);
  EXPECT_EQ(chooseGaugeVertex(graph, GaugeChoice::kHighestId)->id(), 4);
}

TEST(Graph, ChooseGaugeVertexIsNullWhenSomethingIsFixedOrThereAreNoEdges) {
  Graph graph;
  EXPECT_EQ(chooseGaugeVertex(graph), nullptr) << "empty graph";
  addPoint(graph, 0, {0, 0});
  addPoint(graph, 1, {0, 0});
  EXPECT_EQ(chooseGaugeVertex(graph), nullptr) << "no edges";
  addEdge<EdgePoint2Relative>(graph, {0, 1}, {0, 0});
  EXPECT_EQ(chooseGaugeVertex(graph)->id(), 0);
  addPoint(graph, 2, {0, 0}, /*fixed=*/true);  // fixed, even though attached to nothing
  EXPECT_EQ(chooseGaugeVertex(graph), nullptr);
  EXPECT_EQ(chooseGaugeVertex(graph, GaugeChoice::kHighestId), nullptr);
}

/// A parameter holding one number (test-local).
class ParameterScale : public ParameterBase {
 public:
  using ParameterBase::ParameterBase;
  Status read(TokenReader& in) override { return in.readDouble(scale_, "scale"); }
  void write(std::ostream& out) const override { out << scale_; }

 private:
  double scale_ = 1.0;
};

TEST(ParameterContainer, AddsFindsAndRejectsNullAndDuplicateIds) {
  ParameterContainer parameters;
  auto owned = std::make_unique<ParameterScale>(2);
  ParameterBase* raw = owned.get();
  ASSERT_TRUE(parameters.add(std::move(owned)).ok());
  EXPECT_EQ(parameters.find(2), raw);
  EXPECT_EQ(parameters.find(3), nullptr);
  const Status duplicate = parameters.add(std::make_unique<ParameterScale>(2));
  EXPECT_EQ(duplicate.code(), StatusCode::kAlreadyExists);
  EXPECT_TRUE(testing::contains(duplicate.message(), "2"));
  EXPECT_EQ(parameters.find(2), raw);
  EXPECT_EQ(parameters.add(nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(parameters.all().size(), 1u);
  parameters.clear();
  EXPECT_TRUE(parameters.all().empty());
}

}  // namespace
}  // namespace dualgraph
