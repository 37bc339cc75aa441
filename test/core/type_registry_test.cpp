// SPDX-License-Identifier: MIT
// TypeRegistry: tags ↔ factories, duplicates, kinds, invalid tags.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dualgraph/core/type_registry.h"
#include "test/core/test_fixtures.h"

namespace dualgraph {
namespace {

using testing::EdgePoint2Prior;
using testing::EdgePoint2Range;
using testing::EdgePoint2Relative;
using testing::VertexPoint2;
using testing::VertexVector;

class ParameterNothing : public ParameterBase {
 public:
  Status read(TokenReader&) override { return Status(); }
  void write(std::ostream&) const override {}
};

TEST(TypeRegistry, CreatesFreshObjectsOfTheRegisteredTypes) {
  TypeRegistry registry;
  ASSERT_TRUE(testing::registerUserTypes(registry).ok());
  ASSERT_TRUE(registry.registerParameter<ParameterNothing>("PARAMS_NOTHING").ok());

  auto v1 = registry.createVertex("VERTEX_P2");
  auto v2 = registry.createVertex("VERTEX_P2");
  ASSERT_NE(v1, nullptr);
  ASSERT_NE(v2, nullptr);
  EXPECT_NE(v1.get(), v2.get());
  EXPECT_NE(dynamic_cast<VertexPoint2*>(v1.get()), nullptr);
  EXPECT_NE(dynamic_cast<EdgePoint2Relative*>(registry.createEdge("EDGE_P2_REL").get()), nullptr);
  EXPECT_NE(dynamic_cast<EdgePoint2Range*>(registry.createEdge("EDGE_P2_RANGE").get()), nullptr);
  EXPECT_NE(dynamic_cast<EdgePoint2Prior*>(registry.createEdge("EDGE_P2_PRIOR").get()), nullptr);
  EXPECT_NE(dynamic_cast<ParameterNothing*>(registry.createParameter("PARAMS_NOTHING").get()), nullptr);
}

TEST(TypeRegistry, DuplicateTagIsRejectedWhateverTheKind) {
  TypeRegistry registry;
  ASSERT_TRUE(registry.registerVertex<VertexPoint2>("VERTEX_P2").ok());
  const Status again = registry.registerVertex<VertexVector<2>>("VERTEX_P2");
  EXPECT_EQ(again.code(), StatusCode::kAlreadyExists);
  EXPECT_TRUE(testing::contains(again.message(), "VERTEX_P2"));
  EXPECT_EQ(registry.registerEdge<EdgePoint2Prior>("VERTEX_P2").code(), StatusCode::kAlreadyExists);
  // The first registration is intact and the rejected types are still free to register.
  EXPECT_NE(dynamic_cast<VertexPoint2*>(registry.createVertex("VERTEX_P2").get()), nullptr);
  EXPECT_TRUE(registry.registerVertex<VertexVector<2>>("VERTEX_V2").ok());
  EXPECT_TRUE(registry.registerEdge<EdgePoint2Prior>("EDGE_P2_PRIOR").ok());
}

TEST(TypeRegistry, DuplicateTypeIsRejectedNamingItsTag) {
  TypeRegistry registry;
  ASSERT_TRUE(registry.registerEdge<EdgePoint2Relative>("EDGE_P2_REL").ok());
  const Status again = registry.registerEdge<EdgePoint2Relative>("EDGE_P2_REL_AGAIN");
  EXPECT_EQ(again.code(), StatusCode::kAlreadyExists);
  EXPECT_TRUE(testing::contains(again.message(), "EDGE_P2_REL"));
  EXPECT_EQ(registry.kindOf("EDGE_P2_REL_AGAIN"), nullptr) << "nothing half-registered";
  EXPECT_EQ(registry.createEdge("EDGE_P2_REL_AGAIN"), nullptr);
  EdgePoint2Relative edge;
  ASSERT_NE(registry.tagOf(edge), nullptr);
  EXPECT_EQ(*registry.tagOf(edge), "EDGE_P2_REL");
}

TEST(TypeRegistry, CreatingATagOfTheWrongKindGivesNull) {
  TypeRegistry registry;
  ASSERT_TRUE(testing::registerUserTypes(registry).ok());
  ASSERT_TRUE(registry.registerParameter<ParameterNothing>("PARAMS_NOTHING").ok());
  EXPECT_EQ(registry.createVertex("EDGE_P2_REL"), nullptr);
  EXPECT_EQ(registry.createVertex("PARAMS_NOTHING"), nullptr);
  EXPECT_EQ(registry.createEdge("VERTEX_P2"), nullptr);
  EXPECT_EQ(registry.createEdge("PARAMS_NOTHING"), nullptr);
  EXPECT_EQ(registry.createParameter("VERTEX_P2"), nullptr);
  EXPECT_EQ(registry.createParameter("EDGE_P2_PRIOR"), nullptr);
  EXPECT_EQ(registry.createVertex("NO_SUCH_TAG"), nullptr);
  EXPECT_EQ(registry.createEdge(""), nullptr);
  EXPECT_EQ(registry.createVertex("vertex_p2"), nullptr) << "tags are case-sensitive";
}

TEST(TypeRegistry, KindOfNamesTheKindOfEveryTag) {
  TypeRegistry registry;
  ASSERT_TRUE(testing::registerUserTypes(registry).ok());
  ASSERT_TRUE(registry.registerParameter<ParameterNothing>("PARAMS_NOTHING").ok());
  ASSERT_NE(registry.kindOf("VERTEX_P2"), nullptr);
  EXPECT_EQ(*registry.kindOf("VERTEX_P2"), TypeRegistry::Kind::kVertex);
  EXPECT_EQ(*registry.kindOf("EDGE_P2_RANGE"), TypeRegistry::Kind::kEdge);
  EXPECT_EQ(*registry.kindOf("PARAMS_NOTHING"), TypeRegistry::Kind::kParameter);
  EXPECT_EQ(registry.kindOf("FIX"), nullptr);
}

TEST(TypeRegistry, TagOfGivesTheTagOfTheDynamicTypeOrNull) {
  TypeRegistry registry;
  ASSERT_TRUE(testing::registerUserTypes(registry).ok());
  VertexPoint2 point;
  const VertexBase& as_base = point;
  ASSERT_NE(registry.tagOf(as_base), nullptr);
  EXPECT_EQ(*registry.tagOf(as_base), "VERTEX_P2");
  EdgePoint2Range range;
  const EdgeBase& edge_base = range;
  EXPECT_EQ(*registry.tagOf(edge_base), "EDGE_P2_RANGE");
  VertexVector<3> unregistered;
  EXPECT_EQ(registry.tagOf(unregistered), nullptr);
  ParameterNothing parameter;
  EXPECT_EQ(registry.tagOf(parameter), nullptr);
}

TEST(TypeRegistry, TagsAreListedSortedPerKind) {
  TypeRegistry registry;
  ASSERT_TRUE(registry.registerEdge<EdgePoint2Relative>("EDGE_Z").ok());
  ASSERT_TRUE(registry.registerVertex<VertexVector<3>>("VERTEX_B").ok());
  ASSERT_TRUE(registry.registerEdge<EdgePoint2Prior>("EDGE_A").ok());
  ASSERT_TRUE(registry.registerVertex<VertexPoint2>("VERTEX_A").ok());
  ASSERT_TRUE(registry.registerEdge<EdgePoint2Range>("EDGE_M").ok());
  EXPECT_EQ(registry.tags(TypeRegistry::Kind::kEdge), (std::vector<std::string>{"EDGE_A", "EDGE_M", "EDGE_Z"}));
  EXPECT_EQ(registry.tags(TypeRegistry::Kind::kVertex), (std::vector<std::string>{"VERTEX_A", "VERTEX_B"}));
  EXPECT_TRUE(registry.tags(TypeRegistry::Kind::kParameter).empty());
}

TEST(TypeRegistry, TagsThatCannotBeReadBackAreRejected) {
  for (const std::string tag : {"", "VERTEX P2", "VERTEX\tP2", "VERTEX_P2\n", " VERTEX_P2", "VERTEX#P2", "#"}) {
    TypeRegistry registry;
    const Status status = registry.registerVertex<VertexPoint2>(tag);
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << "tag '" << tag << "'";
    EXPECT_TRUE(registry.tags(TypeRegistry::Kind::kVertex).empty());
    EXPECT_TRUE(registry.registerVertex<VertexPoint2>("VERTEX_P2").ok()) << "the type is still free";
  }
}

TEST(TypeRegistry, TagsWithPunctuationLikeG2osAreAccepted) {
  TypeRegistry registry;
  EXPECT_TRUE(registry.registerVertex<VertexPoint2>("VERTEX_SE3:QUAT").ok());
  EXPECT_TRUE(registry.registerEdge<EdgePoint2Prior>("EDGE_PRIOR-2D.v1").ok());
}

}  // namespace
}  // namespace dualgraph
