// SPDX-License-Identifier: MIT
// Shared helpers of the benchmark executables: where the data lives, loading a pose-graph dataset
// with its gauge fixed, percentiles, and saving/restoring every estimate around a timed solve.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/type_registry.h"

namespace dualgraph::bench {

// Pitfall: Debian's Google Benchmark 1.7.1 binds a non-const lvalue in DoNotOptimize(T&) with GCC's
// "+m,r" constraint, and a double can come back as garbage (a register holding a pointer: 6.9e-310
// was read back as a final χ²). Pass the address instead: DoNotOptimize(&summary).

/// ../shared/data/posegraph/<name>.g2o, or $DUALGRAPH_SHARED_DIR/data/posegraph/<name>.g2o.
std::string datasetPath(const std::string& name);
/// A file of the repository's data/ folder, e.g. "tracks/ratm_ellipse.yaml" ($DUALGRAPH_DATA_DIR overrides).
std::string repositoryDataPath(const std::string& relative);

/// A g2o dataset read with the built-in types, the highest-id vertex fixed (what `dualgraph optimize` and
/// g2o's tool fix), as the engine benchmarks use it.
struct LoadedGraph {
  TypeRegistry registry;
  Graph graph;
  bool ok = false;
  std::string error;
};
/// Reads the dataset once per process and per name; later calls return the same object.
LoadedGraph& loadDataset(const std::string& name);

/// The p-quantile (0..1, nearest rank) of `values`; 0 when empty.
double percentile(std::vector<double> values, double p);

/// push()/pop() on every vertex: saves and restores all estimates around a timed solve.
void pushAll(Graph& graph);
void popAll(Graph& graph);

}  // namespace dualgraph::bench
