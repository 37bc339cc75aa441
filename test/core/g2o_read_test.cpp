// SPDX-License-Identifier: MIT
// readG2o with a test-local registry: comments, FIX, skipped tags, parameters, and every read error
// (naming source and line, leaving the graph empty), information checks and repair.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <utility>
#include <vector>

#include "dualgraph/core/g2o_io.h"
#include "test/core/g2o_io_fixtures.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;
using namespace dualgraph::testing;

TEST(G2oIo, CommentsBlankLinesAndWindowsLineEndsAreIgnored) {
  Graph graph;
  const auto report = readText(
      "# a full-line comment\n"
      "\n"
      "   \t \n"
      "VERTEX_P2 0 1 2 # trailing comment with numbers 3 4\n"
      "    # indented comment\r\n"
      "VERTEX_P2 1 3 4\r\n"
      "EDGE_P2_REL 0 1 2 2 1 0 1#no space before the comment\n"
      "#EDGE_P2_REL 1 0 0 0 1 0 1\n"
      "EDGE_P2_PRIOR\t1\t3 4 2 0 2",  // tabs, no final newline
      graph);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->vertices, 2);
  EXPECT_EQ(report->edges, 2);
  EXPECT_EQ(graph.vertexAs<VertexPoint2>(0)->estimate(), Eigen::Vector2d(1, 2));
  EXPECT_EQ(graph.vertexAs<VertexPoint2>(1)->estimate(), Eigen::Vector2d(3, 4));
  EXPECT_EQ(graph.edges()[0]->sourceLine(), 7);
  EXPECT_EQ(graph.edges()[1]->sourceLine(), 9);
  EXPECT_TRUE(report->warnings.empty());
}

TEST(G2oIo, UnknownTagsAreSkippedWithOneWarningPerTagWhenAsked) {
  Graph graph;
  G2oReadOptions options;
  options.skip_unknown_tags = true;
  const auto report = readText(
      "VERTEX_P2 0 0 0\n"
      "VERTEX_SE2 1 0 0 0\n"
      "VERTEX_P2 1 1 0\n"
      "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
      "VERTEX_SE2 2 0 0 0\n"
      "EDGE_P2_REL 0 1 1 0 1 0 1\n",
      graph, options);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->vertices, 2);
  EXPECT_EQ(report->edges, 1);
  EXPECT_EQ(report->skipped_lines, 3);
  ASSERT_EQ(report->warnings.size(), 2u);
  std::string all;
  for (const std::string& w : report->warnings) all += w + "\n";
  EXPECT_TRUE(contains(all, "test.g2o:4: skipped unknown tag 'EDGE_SE2'"));
  EXPECT_TRUE(contains(all, "test.g2o:2: skipped unknown tag 'VERTEX_SE2'")) << "first line of each tag";
}

TEST(G2oIo, EdgesRememberTheirSourceLine) {
  Graph graph;
  ASSERT_TRUE(readText("VERTEX_P2 0 0 0\nVERTEX_P2 1 0 0\n\nEDGE_P2_RANGE 0 1 1 1\n", graph).ok());
  EXPECT_EQ(graph.edges()[0]->sourceLine(), 4);
}

TEST(G2oIo, ParametersAreReadIntoTheGraph) {
  Graph graph;
  const auto report = readText("PARAMS_SCALE 3 2.5\nPARAMS_SCALE 1 -1\n", graph);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->parameters, 2);
  ASSERT_NE(graph.parameters().find(3), nullptr);
  EXPECT_EQ(static_cast<ParameterScale*>(graph.parameters().find(3))->scale(), 2.5);
}

/// A bad input, the code it must give and the `file:line` and text its message must contain.
struct BadInput {
  const char* name;
  std::string text;
  StatusCode code;
  std::string location;
  std::string fragment;
};

void PrintTo(const BadInput& input, std::ostream* out) { *out << input.name; }

class G2oReadRejects : public ::testing::TestWithParam<BadInput> {};

TEST_P(G2oReadRejects, WithAMessageNamingSourceAndLineAndLeavesTheGraphEmpty) {
  const BadInput& input = GetParam();
  Graph graph;
  const auto report = readText(input.text, graph);
  ASSERT_FALSE(report.ok()) << "accepted:\n" << input.text;
  EXPECT_EQ(report.status().code(), input.code) << report.status().toString();
  EXPECT_TRUE(contains(report.status().message(), input.location + ": "));
  EXPECT_TRUE(contains(report.status().message(), input.fragment));
  expectEmpty(graph);
}

const char kTwoPoints[] = "VERTEX_P2 0 0 0\nVERTEX_P2 1 1 0\n";

INSTANTIATE_TEST_SUITE_P(
    Catalogue, G2oReadRejects,
    ::testing::Values(
        BadInput{"UnknownTag", std::string(kTwoPoints) + "EDGE_NOPE 0 1 1 0\n", StatusCode::kParseError,
                 "test.g2o:3", "unknown tag 'EDGE_NOPE'"},
        BadInput{"UnprintableTag", "VERTEX_P2 0 0 0\n\x01\x7f\xfe 0 0\n", StatusCode::kParseError, "test.g2o:2",
                 "unknown tag '\\x01\\x7f\\xfe'"},
        BadInput{"EdgeToUnknownVertex", std::string(kTwoPoints) + "EDGE_P2_REL 0 7 1 0 1 0 1\n",
                 StatusCode::kParseError, "test.g2o:3", "unknown vertex id 7"},
        BadInput{"EdgeBeforeItsVertex", "VERTEX_P2 0 0 0\nEDGE_P2_REL 0 1 1 0 1 0 1\nVERTEX_P2 1 1 0\n",
                 StatusCode::kParseError, "test.g2o:2", "unknown vertex id 1"},
        BadInput{"DuplicateVertexId", "VERTEX_P2 0 0 0\nVERTEX_P2 1 0 0\nVERTEX_P2 0 1 1\n",
                 StatusCode::kParseError, "test.g2o:3", "duplicate vertex id 0"},
        BadInput{"SelfLoop", std::string(kTwoPoints) + "EDGE_P2_REL 1 1 1 0 1 0 1\n", StatusCode::kParseError,
                 "test.g2o:3", "self-loop"},
        BadInput{"WrongVertexTypeForSlot", "VERTEX_P2 0 0 0\nVERTEX_Q2 1 1 0\nEDGE_P2_REL 0 1 1 0 1 0 1\n",
                 StatusCode::kParseError, "test.g2o:3", "vertex 1 (VERTEX_Q2) has the wrong type for vertex slot 2"},
        BadInput{"WrongVertexTypeForUnarySlot", "VERTEX_Q2 4 1 0\nEDGE_P2_PRIOR 4 0 0 1 0 1\n",
                 StatusCode::kParseError, "test.g2o:2", "wrong type for vertex slot 1"},
        BadInput{"FixOfMissingVertex", "VERTEX_P2 0 0 0\nFIX 5\nVERTEX_P2 1 0 0\nEDGE_P2_RANGE 0 1 1 1\n",
                 StatusCode::kParseError, "test.g2o:2", "FIX of unknown vertex id 5"},
        BadInput{"FixWithoutId", std::string(kTwoPoints) + "FIX   # nothing\n", StatusCode::kParseError,
                 "test.g2o:3", "FIX without a vertex id"},
        BadInput{"FixOfNonInteger", std::string(kTwoPoints) + "FIX 0 one\n", StatusCode::kParseError,
                 "test.g2o:3", "field 'vertex id'"},
        BadInput{"TruncatedVertex", "VERTEX_P2 0 1\n", StatusCode::kParseError, "test.g2o:1",
                 "line ends before field 'xy[1]'"},
        BadInput{"VertexWithoutId", "VERTEX_P2\n", StatusCode::kParseError, "test.g2o:1",
                 "line ends before field 'id'"},
        BadInput{"TruncatedEdgeInformation", std::string(kTwoPoints) + "EDGE_P2_REL 0 1 1 0 1 0\n",
                 StatusCode::kParseError, "test.g2o:3", "line ends before field 'information[2]'"},
        BadInput{"TruncatedEdgeVertexIds", std::string(kTwoPoints) + "EDGE_P2_REL 0\n", StatusCode::kParseError,
                 "test.g2o:3", "line ends before field 'vertex id 2'"},
        BadInput{"NonNumericField", "VERTEX_P2 0 1 abc\n", StatusCode::kParseError, "test.g2o:1",
                 "field 'xy[1]' is not a number: 'abc'"},
        BadInput{"NanMeasurement", std::string(kTwoPoints) + "EDGE_P2_RANGE 0 1 nan 1\n", StatusCode::kParseError,
                 "test.g2o:3", "field 'range' is not finite"},
        BadInput{"OverflowingInformation", std::string(kTwoPoints) + "EDGE_P2_RANGE 0 1 1 1e999\n",
                 StatusCode::kParseError, "test.g2o:3", "field 'information' is not finite"},
        BadInput{"NonIntegerVertexId", "VERTEX_P2 0.5 1 1\n", StatusCode::kParseError, "test.g2o:1",
                 "field 'id' is not an integer"},
        BadInput{"NegativeVertexId", "VERTEX_P2 -1 0 0\n", StatusCode::kParseError, "test.g2o:1",
                 "negative vertex id -1"},
        BadInput{"TrailingGarbageOnVertex", "VERTEX_P2 0 1 1 extra\n", StatusCode::kParseError, "test.g2o:1",
                 "1 unexpected trailing field(s) starting with 'extra'"},
        BadInput{"TrailingGarbageOnEdge", std::string(kTwoPoints) + "EDGE_P2_RANGE 0 1 1 1 2 3\n",
                 StatusCode::kParseError, "test.g2o:3", "2 unexpected trailing field(s) starting with '2'"},
        BadInput{"TrailingGarbageOnParameter", "PARAMS_SCALE 0 1 1\n", StatusCode::kParseError, "test.g2o:1",
                 "trailing"},
        BadInput{"DuplicateParameterId", "PARAMS_SCALE 0 1\nPARAMS_SCALE 0 2\n", StatusCode::kParseError,
                 "test.g2o:2", "duplicate parameter id 0"},
        BadInput{"NonPositiveDefiniteInformation",
                 std::string(kTwoPoints) + "EDGE_P2_REL 0 1 1 0 1 0 1\nEDGE_P2_REL 0 1 1 0 1 2 1\n",
                 StatusCode::kNotPositiveDefinite, "test.g2o:4", "1 edge(s)"},
        BadInput{"ErrorAfterManyGoodLines",
                 std::string(kTwoPoints) + "VERTEX_P2 2 0 0\nVERTEX_P2 3 0 0\nEDGE_P2_REL 0 1 1 0 1 0 1\n"
                                            "EDGE_P2_REL 1 2 1 0 1 0 1\nEDGE_P2_REL 2 3 1 0 1 0 1 0\n",
                 StatusCode::kParseError, "test.g2o:7", "trailing"}),
    [](const ::testing::TestParamInfo<BadInput>& info) { return std::string(info.param.name); });

TEST(G2oIo, NonPositiveDefiniteInformationNamesTheCountAndTheFirstLine) {
  Graph graph;
  const auto report = readText(
      "VERTEX_P2 0 0 0\n"
      "VERTEX_P2 1 1 0\n"
      "EDGE_P2_REL 0 1 1 0 1 0 1\n"
      "EDGE_P2_REL 0 1 1 0 1 0 -1\n"   // indefinite
      "EDGE_P2_RANGE 0 1 1 0\n"        // zero
      "EDGE_P2_REL 1 0 1 0 1 5 1\n",   // indefinite, positive diagonal
      graph);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kNotPositiveDefinite);
  EXPECT_TRUE(contains(report.status().message(), "test.g2o:4: 3 edge(s)"));
  EXPECT_TRUE(contains(report.status().message(), "EDGE_P2_REL"));
  expectEmpty(graph);
}

TEST(G2oIo, RepairInformationLoadsCountsAndMakesEveryInformationValid) {
  const std::string text =
      "VERTEX_P2 0 0 0\n"
      "VERTEX_P2 1 1 0\n"
      "EDGE_P2_REL 0 1 1 0 2 0.5 3\n"
      "EDGE_P2_REL 0 1 1 0 1 0 -1\n"
      "EDGE_P2_RANGE 0 1 1 0\n"
      "EDGE_P2_REL 1 0 1 0 1 5 1\n";
  Graph graph;
  G2oReadOptions options;
  options.repair_information = true;
  const auto report = readText(text, graph, options);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->repaired_information, 3);
  EXPECT_EQ(report->edges, 4);
  for (const auto& edge : graph.edges()) EXPECT_TRUE(edge->informationIsValid()) << "line " << edge->sourceLine();
  Eigen::Matrix2d untouched;
  untouched << 2, 0.5, 0.5, 3;
  EXPECT_EQ(static_cast<EdgePoint2Relative*>(graph.edges()[0].get())->information(), untouched);
  EXPECT_TRUE(std::isfinite(graph.chi2()));
}

TEST(G2oIo, EmptyAndCommentOnlyFilesAreErrorsNamingTheSource) {
  for (const char* text : {"", "\n\n", "# only a comment\n   # and another\n", "FIX 0\n"}) {
    Graph graph;
    const auto report = readText(text, graph);
    ASSERT_FALSE(report.ok()) << "'" << text << "'";
    EXPECT_EQ(report.status().code(), StatusCode::kParseError);
    EXPECT_TRUE(contains(report.status().message(), "test.g2o"));
    expectEmpty(graph);
  }
  Graph graph;
  const auto report = readText("# nothing\n", graph);
  EXPECT_TRUE(contains(report.status().message(), "no vertices, edges or parameters"));
}

TEST(G2oIo, OnlyUnknownTagsSkippedIsStillAnEmptyFile) {
  Graph graph;
  G2oReadOptions options;
  options.skip_unknown_tags = true;
  const auto report = readText("VERTEX_SE2 0 0 0 0\n", graph, options);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kParseError);
}

TEST(G2oIo, ReadIntoANonEmptyGraphIsRefusedAndTheGraphIsKept) {
  Graph graph;
  addPoint(graph, 5, {1, 1});
  const auto report = readText("VERTEX_P2 0 0 0\n", graph);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(graph.numVertices(), 1u);
  EXPECT_NE(graph.vertex(5), nullptr);
}

TEST(G2oIo, ReadingAMissingFileIsAnIoErrorNamingThePath) {
  TempDir dir;
  const std::string path = (dir.path() / "absent.g2o").string();
  Graph graph;
  const auto report = readG2o(path, testRegistry(), graph);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kIoError);
  EXPECT_TRUE(contains(report.status().message(), path));
}


TEST(G2oIo, ReadErrorsFromAFileNameThePath) {
  TempDir dir;
  const fs::path path = dir.path() / "bad.g2o";
  std::ofstream(path) << "VERTEX_P2 0 0 0\nVERTEX_P2 0 1 1\n";
  Graph graph;
  const auto report = readG2o(path.string(), testRegistry(), graph);
  ASSERT_FALSE(report.ok());
  EXPECT_TRUE(contains(report.status().message(), path.string() + ":2: "));
  expectEmpty(graph);
}

TEST(G2oIo, ReadingADirectoryIsAnErrorNamingThePath) {
  TempDir dir;
  Graph graph;
  const auto report = readG2o(dir.path().string(), testRegistry(), graph);
  ASSERT_FALSE(report.ok());
  EXPECT_TRUE(contains(report.status().message(), dir.path().string()));
  expectEmpty(graph);
}

/// Serves `text`, then fails like a disk read error.
class FailingAfterTextBuffer : public std::streambuf {
 public:
  explicit FailingAfterTextBuffer(std::string text) : text_(std::move(text)) {
    setg(text_.data(), text_.data(), text_.data() + text_.size());
  }

 protected:
  int_type underflow() override { throw std::runtime_error("simulated read error"); }

 private:
  std::string text_;
};

TEST(G2oIo, StreamReadErrorIsAnIoErrorAndLeavesTheGraphEmpty) {
  FailingAfterTextBuffer buffer("VERTEX_P2 0 0 0\nVERTEX_P2 1 1 0\nEDGE_P2_REL 0 1 1 0 1 0 1\n");
  std::istream in(&buffer);
  Graph graph;
  const auto report = readG2o(in, "test.g2o", testRegistry(), graph);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kIoError);
  EXPECT_TRUE(contains(report.status().message(), "test.g2o"));
  expectEmpty(graph);
}

}  // namespace
}  // namespace dualgraph
