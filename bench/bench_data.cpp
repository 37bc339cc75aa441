// SPDX-License-Identifier: MIT
#include "bench/bench_data.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

#include "dualgraph/core/g2o_io.h"
#include "dualgraph/types/register_types.h"

namespace dualgraph::bench {

std::string datasetPath(const std::string& name) {
  const char* dir = std::getenv("DUALGRAPH_SHARED_DIR");
  return std::string(dir != nullptr ? dir : DUALGRAPH_DEFAULT_SHARED_DIR) + "/data/posegraph/" + name + ".g2o";
}

std::string repositoryDataPath(const std::string& relative) {
  const char* dir = std::getenv("DUALGRAPH_DATA_DIR");
  return std::string(dir != nullptr ? dir : DUALGRAPH_DEFAULT_DATA_DIR) + "/" + relative;
}

LoadedGraph& loadDataset(const std::string& name) {
  static std::map<std::string, std::unique_ptr<LoadedGraph>> cache;
  std::unique_ptr<LoadedGraph>& slot = cache[name];
  if (slot) return *slot;
  slot = std::make_unique<LoadedGraph>();
  LoadedGraph& loaded = *slot;
  (void)registerBuiltinTypes(loaded.registry);
  const auto report = readG2o(datasetPath(name), loaded.registry, loaded.graph);
  if (!report.ok()) {
    loaded.error = report.status().message();
    return loaded;
  }
  if (VertexBase* gauge = chooseGaugeVertex(loaded.graph, GaugeChoice::kHighestId)) {
    (void)loaded.graph.setFixed(gauge->id(), true);
  }
  loaded.ok = true;
  return loaded;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(p * static_cast<double>(values.size())) - 1.0;
  const size_t index = static_cast<size_t>(std::clamp(rank, 0.0, static_cast<double>(values.size() - 1)));
  return values[index];
}

void pushAll(Graph& graph) {
  for (auto& [id, vertex] : graph.vertices()) vertex->push();
}

void popAll(Graph& graph) {
  for (auto& [id, vertex] : graph.vertices()) vertex->pop();
}

}  // namespace dualgraph::bench
