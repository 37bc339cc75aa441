// SPDX-License-Identifier: MIT
// Fuzzes readG2o (core/g2o_io.h) with every built-in type registered, under the default options and
// under skip_unknown_tags + repair_information. Beyond "no crash, no leak, no UB": an error names the
// source and leaves the graph empty; a graph that was read writes back and reads back with the same
// counts.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/graph.h"
#include "dualgraph/core/type_registry.h"
#include "test/fuzz/fuzz_input.h"
#include "dualgraph/types/register_types.h"

namespace {

const dualgraph::TypeRegistry& registry() {
  static const dualgraph::TypeRegistry* instance = [] {
    auto* r = new dualgraph::TypeRegistry();
    if (!dualgraph::registerBuiltinTypes(*r).ok()) dualgraph::fuzz::fuzzFail("registerBuiltinTypes failed");
    return r;
  }();
  return *instance;
}

size_t countFixed(const dualgraph::Graph& graph) {
  size_t fixed = 0;
  for (const auto& entry : graph.vertices()) fixed += entry.second->fixed() ? 1 : 0;
  return fixed;
}

void readOnce(const std::string& text, const dualgraph::G2oReadOptions& options) {
  using namespace dualgraph;
  const std::string source = "fuzz.g2o";
  Graph graph;
  std::istringstream in(text);
  const Result<G2oReadReport> report = readG2o(in, source, registry(), graph, options);
  if (!report.ok()) {
    fuzz::checkErrorNames(report.status(), source);
    if (graph.numVertices() != 0 || graph.numEdges() != 0) fuzz::fuzzFail("failed read left a graph behind");
    return;
  }
  std::ostringstream out;
  const Status written = writeG2o(out, registry(), graph);
  if (!written.ok()) fuzz::fuzzFail("a graph that was read does not write: " + written.toString());
  Graph again;
  std::istringstream back(out.str());
  const Result<G2oReadReport> reread = readG2o(back, "rewritten.g2o", registry(), again);
  if (!reread.ok()) fuzz::fuzzFail("written graph does not read back: " + reread.status().toString());
  if (again.numVertices() != graph.numVertices() || again.numEdges() != graph.numEdges() ||
      reread->parameters != report->parameters || countFixed(again) != countFixed(graph)) {
    fuzz::fuzzFail("written graph reads back with other counts");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = dualgraph::fuzz::asText(data, size);
  readOnce(text, dualgraph::G2oReadOptions{});
  dualgraph::G2oReadOptions lenient;
  lenient.skip_unknown_tags = true;
  lenient.repair_information = true;
  readOnce(text, lenient);
  return 0;
}
