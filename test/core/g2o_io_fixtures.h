// SPDX-License-Identifier: MIT
// Helpers of the g2o I/O tests: a registry with the user types, a second 2-D vertex type and a
// parameter type; text read/write shortcuts with the source name "test.g2o"; a temporary folder.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "dualgraph/core/g2o_io.h"
#include "test/core/test_fixtures.h"

namespace dualgraph::testing {

/// A parameter holding one number.
class ParameterScale : public ParameterBase {
 public:
  using ParameterBase::ParameterBase;
  Status read(TokenReader& in) override { return in.readDouble(scale_, "scale"); }
  void write(std::ostream& out) const override { out << std::setprecision(17) << scale_; }
  double scale() const { return scale_; }
  void setScale(double scale) { scale_ = scale; }

 private:
  double scale_ = 1.0;
};

/// The user types, a second 2-D vertex type under its own tag (same dimension as VERTEX_P2, so
/// only the type tells them apart) and a parameter type.
inline TypeRegistry testRegistry() {
  TypeRegistry registry;
  EXPECT_TRUE(testing::registerUserTypes(registry).ok());
  EXPECT_TRUE(registry.registerVertex<VertexVector<2>>("VERTEX_Q2").ok());
  EXPECT_TRUE(registry.registerParameter<ParameterScale>("PARAMS_SCALE").ok());
  return registry;
}

inline Result<G2oReadReport> readText(const std::string& text, Graph& graph, const G2oReadOptions& options = {}) {
  std::istringstream in(text);
  return readG2o(in, "test.g2o", testRegistry(), graph, options);
}

inline std::string writeText(const Graph& graph) {
  std::ostringstream out;
  const Status status = writeG2o(out, testRegistry(), graph);
  EXPECT_TRUE(status.ok()) << status.toString();
  return out.str();
}

inline void expectEmpty(const Graph& graph) {
  EXPECT_EQ(graph.numVertices(), 0u);
  EXPECT_EQ(graph.numEdges(), 0u);
  EXPECT_TRUE(graph.parameters().all().empty());
}

/// A temporary folder removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "dualgraph_core_test_XXXXXX").string();
    const char* made = mkdtemp(pattern.data());
    EXPECT_NE(made, nullptr);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(path_)) names.push_back(entry.path().filename().string());
    return names;
  }

 private:
  std::filesystem::path path_;
};

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

/// Points, relative, range and prior edges with full-precision random values, two fixed
/// vertices and two parameters.
inline void buildGraphForWriting(Graph& graph, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 10.0);
  for (int id : {0, 3, 4, 8, 11}) addPoint(graph, id, {normal(rng), normal(rng) * 1e-7}, id == 3 || id == 11);
  addEdge<EdgePoint2Relative>(graph, {0, 3}, {normal(rng), normal(rng)}, testing::randomInformation<2>(rng, 3.0));
  addEdge<EdgePoint2Relative>(graph, {8, 4}, {1.0 / 3.0, -2.0 / 7.0}, testing::randomInformation<2>(rng));
  addEdge<EdgePoint2Range>(graph, {11, 0}, std::abs(normal(rng)), Eigen::Matrix<double, 1, 1>(0.1));
  addEdge<EdgePoint2Prior>(graph, {4}, {normal(rng), 1e-300}, testing::randomInformation<2>(rng, 1e3));
  for (int id : {2, 0}) {
    auto parameter = std::make_unique<ParameterScale>(id);
    parameter->setScale(normal(rng));
    ASSERT_TRUE(graph.parameters().add(std::move(parameter)).ok());
  }
}

}  // namespace dualgraph::testing
