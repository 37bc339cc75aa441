// SPDX-License-Identifier: MIT
// writeG2o with a test-local registry: write→read→write identity, the line layout, FIX lines, and
// atomic file writes that never leave a half-written or temporary file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "dualgraph/core/g2o_io.h"
#include "test/core/g2o_io_fixtures.h"

namespace dualgraph {
namespace {

namespace fs = std::filesystem;
using namespace dualgraph::testing;

TEST(G2oIo, WriteReadWriteIsIdentical) {
  for (unsigned seed : {1u, 2u, 3u}) {
    Graph graph;
    buildGraphForWriting(graph, seed);
    const std::string first = writeText(graph);
    Graph reread;
    const auto report = readText(first, reread);
    ASSERT_TRUE(report.ok()) << report.status().toString() << "\n" << first;
    EXPECT_EQ(report->vertices, 5);
    EXPECT_EQ(report->edges, 4);
    EXPECT_EQ(report->parameters, 2);
    EXPECT_EQ(report->fixed, 2);
    EXPECT_EQ(writeText(reread), first);
    // Bit-identical values, not just identical text.
    for (const auto& [id, v] : graph.vertices()) {
      EXPECT_EQ(reread.vertexAs<VertexPoint2>(id)->estimate(), graph.vertexAs<VertexPoint2>(id)->estimate());
      EXPECT_EQ(reread.vertex(id)->fixed(), v->fixed());
    }
    EXPECT_EQ(reread.chi2(), graph.chi2());
  }
}

TEST(G2oIo, WrittenTextHasParametersVerticesEdgesThenFixLines) {
  Graph graph;
  addPoint(graph, 2, {1.5, -2});
  addPoint(graph, 1, {0, 0.25}, true);
  addEdge<EdgePoint2Range>(graph, {2, 1}, 2.0, Eigen::Matrix<double, 1, 1>(4.0));
  auto parameter = std::make_unique<ParameterScale>(7);
  parameter->setScale(0.5);
  ASSERT_TRUE(graph.parameters().add(std::move(parameter)).ok());
  EXPECT_EQ(writeText(graph),
            "PARAMS_SCALE 7 0.5\n"
            "VERTEX_P2 1 0 0.25\n"
            "VERTEX_P2 2 1.5 -2\n"
            "EDGE_P2_RANGE 2 1 2 4\n"
            "FIX 1\n");
}

TEST(G2oIo, FixLinesFixVerticesWhereverTheyAppear) {
  Graph graph;
  const auto report = readText(
      "FIX 2\n"
      "VERTEX_P2 0 0 0\n"
      "VERTEX_P2 1 1 0\n"
      "VERTEX_P2 2 2 0\n"
      "FIX 0 2   # several ids, one repeated\n"
      "EDGE_P2_REL 0 1 1 0 1 0 1\n",
      graph);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(report->fixed, 2);
  EXPECT_TRUE(graph.vertex(0)->fixed());
  EXPECT_FALSE(graph.vertex(1)->fixed());
  EXPECT_TRUE(graph.vertex(2)->fixed());
  const std::string written = writeText(graph);
  EXPECT_TRUE(contains(written, "FIX 0\nFIX 2\n"));
  EXPECT_FALSE(contains(written, "FIX 1"));
}

TEST(G2oIo, FileRoundTripWritesAtomicallyAndLeavesNoTemporary) {
  TempDir dir;
  const fs::path path = dir.path() / "graph.g2o";
  Graph graph;
  buildGraphForWriting(graph, 4);
  ASSERT_TRUE(writeG2o(path.string(), testRegistry(), graph).ok());
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"graph.g2o"});
  EXPECT_EQ(slurp(path), writeText(graph));
  Graph reread;
  const auto report = readG2o(path.string(), testRegistry(), reread);
  ASSERT_TRUE(report.ok()) << report.status().toString();
  EXPECT_EQ(writeText(reread), writeText(graph));

  // Overwriting replaces the old content completely.
  Graph small;
  addPoint(small, 0, {1, 2});
  ASSERT_TRUE(writeG2o(path.string(), testRegistry(), small).ok());
  EXPECT_EQ(slurp(path), "VERTEX_P2 0 1 2\n");
  EXPECT_EQ(dir.entries().size(), 1u);
}

TEST(G2oIo, WriteIntoAMissingDirectoryFailsCleanlyAndCreatesNothing) {
  TempDir dir;
  const fs::path missing = dir.path() / "no_such_dir";
  const fs::path path = missing / "out.g2o";
  Graph graph;
  buildGraphForWriting(graph, 5);
  const Status status = writeG2o(path.string(), testRegistry(), graph);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kIoError);
  EXPECT_TRUE(contains(status.message(), missing.string()));
  EXPECT_FALSE(fs::exists(missing));
  EXPECT_TRUE(dir.entries().empty());
}

TEST(G2oIo, WriteOfAnUnregisteredTypeFailsAndKeepsTheExistingFile) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  ASSERT_TRUE(graph.addVertex(std::make_unique<VertexVector<3>>(1)).ok());  // no tag
  std::ostringstream out;
  const Status to_stream = writeG2o(out, testRegistry(), graph);
  EXPECT_EQ(to_stream.code(), StatusCode::kNotFound);
  EXPECT_TRUE(contains(to_stream.message(), "vertex 1"));

  TempDir dir;
  const fs::path path = dir.path() / "keep.g2o";
  std::ofstream(path) << "old content\n";
  const Status to_file = writeG2o(path.string(), testRegistry(), graph);
  ASSERT_FALSE(to_file.ok());
  EXPECT_TRUE(contains(to_file.message(), "vertex 1"));
  EXPECT_EQ(slurp(path), "old content\n") << "a failed write never replaces the file";
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"keep.g2o"}) << "no temporary left behind";
}

TEST(G2oIo, WriteOntoADirectoryFailsAndLeavesNoTemporary) {
  TempDir dir;
  const fs::path target = dir.path() / "a_directory";
  fs::create_directory(target);
  Graph graph;
  addPoint(graph, 0, {0, 0});
  const Status status = writeG2o(target.string(), testRegistry(), graph);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kIoError);
  EXPECT_TRUE(contains(status.message(), target.string()));
  EXPECT_TRUE(fs::is_directory(target));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"a_directory"}) << "no temporary left behind";
}

TEST(G2oIo, WriteToAFailedStreamIsAnIoError) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  std::ostringstream out;
  out.setstate(std::ios::badbit);
  EXPECT_EQ(writeG2o(out, testRegistry(), graph).code(), StatusCode::kIoError);
}

TEST(G2oIo, WriteOfAnUnregisteredEdgeTypeFails) {
  Graph graph;
  addPoint(graph, 0, {0, 0});
  addPoint(graph, 1, {1, 0});
  addEdge<testing::EdgeLinear<2, VertexPoint2, VertexPoint2>>(graph, {0, 1}, {0, 0});
  std::ostringstream out;
  EXPECT_EQ(writeG2o(out, testRegistry(), graph).code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace dualgraph
