// SPDX-License-Identifier: MIT
// Graph, the owner of one factor graph's vertices, edges and parameters, and the choice of gauge vertex.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "dualgraph/core/edge.h"
#include "dualgraph/core/parameter.h"
#include "dualgraph/core/status.h"
#include "dualgraph/core/vertex.h"

namespace dualgraph {

/// Owns the vertices (keyed by id, iterated in increasing id order), the edges (in insertion
/// order) and the parameters of one factor graph. Every mutation that changes the structure of
/// the linear system (vertices, edges, fixed flags) bumps `structureVersion()`, so an optimiser
/// knows when to rebuild its sparsity pattern.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class Graph {
 public:
  Graph() = default;
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;

  /// AlreadyExists on a duplicate id, InvalidArgument on a null vertex or a negative id.
  Status addVertex(std::unique_ptr<VertexBase> vertex);
  /// Every slot must hold a vertex of this graph, and no vertex may appear twice (self-loop).
  /// Returns the stored edge.
  Result<EdgeBase*> addEdge(std::unique_ptr<EdgeBase> edge);
  /// Removes the vertex and every edge attached to it. NotFound for an unknown id.
  Status removeVertex(int id);
  /// NotFound when the edge is not in this graph.
  Status removeEdge(const EdgeBase* edge);
  /// NotFound for an unknown id.
  Status setFixed(int id, bool fixed);
  void clear();

  /// nullptr when the id is unknown. Through a const Graph the vertex is const too.
  VertexBase* vertex(int id);
  const VertexBase* vertex(int id) const;
  /// nullptr when the id is unknown or the vertex is not a `V`.
  template <typename V>
  V* vertexAs(int id) { return dynamic_cast<V*>(vertex(id)); }
  template <typename V>
  const V* vertexAs(int id) const { return dynamic_cast<const V*>(vertex(id)); }

  const std::map<int, std::unique_ptr<VertexBase>>& vertices() const { return vertices_; }
  const std::vector<std::unique_ptr<EdgeBase>>& edges() const { return edges_; }
  size_t numVertices() const { return vertices_.size(); }
  size_t numEdges() const { return edges_.size(); }
  ParameterContainer& parameters() { return parameters_; }
  const ParameterContainer& parameters() const { return parameters_; }

  /// Recomputes every edge's error and returns Σ eᵀΩe (robust ρ applied when `robust`).
  double chi2(bool robust = false) const;

  uint64_t structureVersion() const { return structure_version_; }

 private:
  std::map<int, std::unique_ptr<VertexBase>> vertices_;
  std::vector<std::unique_ptr<EdgeBase>> edges_;
  ParameterContainer parameters_;
  uint64_t structure_version_ = 0;
};

/// Copies `source` into the empty `target`: every parameter, vertex and edge by its clone(), each edge connected to
/// target's copies of its vertices (estimates, fixed flags, measurements, information and robust kernels as in
/// `source`; no undo stacks). kInvalidArgument when `target` is not empty, or naming the first parameter, vertex or
/// edge whose type does not implement clone() (`target` is then left empty).
Status cloneGraph(const Graph& source, Graph& target);

/// Which vertex `chooseGaugeVertex` fixes among those of the largest tangent dimension.
enum class GaugeChoice {
  kLowestId,   ///< the conventional first pose
  kHighestId,  ///< what g2o's command-line tool ends up fixing on the public datasets (see README)
};

/// The vertex to fix when nothing is fixed (the gauge): among the vertices attached to an edge and
/// of the largest tangent dimension, the lowest or highest id. nullptr when some vertex is fixed
/// already or the graph has no edges.
VertexBase* chooseGaugeVertex(const Graph& graph, GaugeChoice choice = GaugeChoice::kLowestId);

}  // namespace dualgraph
