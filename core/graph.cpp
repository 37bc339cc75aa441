// SPDX-License-Identifier: MIT
#include "dualgraph/core/graph.h"

#include <algorithm>
#include <string>
#include <unordered_set>

namespace dualgraph {

Status Graph::addVertex(std::unique_ptr<VertexBase> vertex) {
  if (!vertex) return Status(StatusCode::kInvalidArgument, "null vertex");
  const int id = vertex->id();
  if (id < 0) return Status(StatusCode::kInvalidArgument, "negative vertex id " + std::to_string(id));
  if (vertices_.count(id) != 0) {
    return Status(StatusCode::kAlreadyExists, "duplicate vertex id " + std::to_string(id));
  }
  vertices_.emplace(id, std::move(vertex));
  ++structure_version_;
  return Status();
}

Result<EdgeBase*> Graph::addEdge(std::unique_ptr<EdgeBase> edge) {
  if (!edge) return Status(StatusCode::kInvalidArgument, "null edge");
  const auto& slots = edge->vertices();
  for (size_t i = 0; i < slots.size(); ++i) {
    const VertexBase* v = slots[i];
    if (v == nullptr) {
      return Status(StatusCode::kInvalidArgument, "edge slot " + std::to_string(i) + " has no vertex");
    }
    if (vertex(v->id()) != v) {
      return Status(StatusCode::kNotFound,
                    "edge vertex " + std::to_string(v->id()) + " is not in this graph");
    }
    for (size_t j = 0; j < i; ++j) {
      if (slots[j] == v) {
        return Status(StatusCode::kInvalidArgument,
                      "edge connects vertex " + std::to_string(v->id()) + " to itself");
      }
    }
  }
  edges_.push_back(std::move(edge));
  ++structure_version_;
  return edges_.back().get();
}

Status Graph::removeVertex(int id) {
  const auto it = vertices_.find(id);
  if (it == vertices_.end()) {
    return Status(StatusCode::kNotFound, "unknown vertex id " + std::to_string(id));
  }
  const VertexBase* v = it->second.get();
  edges_.erase(std::remove_if(edges_.begin(), edges_.end(),
                              [v](const std::unique_ptr<EdgeBase>& e) {
                                const auto& s = e->vertices();
                                return std::find(s.begin(), s.end(), v) != s.end();
                              }),
               edges_.end());
  vertices_.erase(it);
  ++structure_version_;
  return Status();
}

Status Graph::removeEdge(const EdgeBase* edge) {
  const auto it = std::find_if(edges_.begin(), edges_.end(),
                               [edge](const std::unique_ptr<EdgeBase>& e) { return e.get() == edge; });
  if (it == edges_.end()) return Status(StatusCode::kNotFound, "edge is not in this graph");
  edges_.erase(it);
  ++structure_version_;
  return Status();
}

Status Graph::setFixed(int id, bool fixed) {
  VertexBase* v = vertex(id);
  if (v == nullptr) return Status(StatusCode::kNotFound, "unknown vertex id " + std::to_string(id));
  if (v->fixed() != fixed) {
    v->setFixed(fixed);
    ++structure_version_;
  }
  return Status();
}

void Graph::clear() {
  edges_.clear();
  vertices_.clear();
  parameters_.clear();
  ++structure_version_;
}

VertexBase* Graph::vertex(int id) {
  const auto it = vertices_.find(id);
  return it == vertices_.end() ? nullptr : it->second.get();
}

const VertexBase* Graph::vertex(int id) const {
  const auto it = vertices_.find(id);
  return it == vertices_.end() ? nullptr : it->second.get();
}

double Graph::chi2(bool robust) const {
  double sum = 0.0;
  for (const auto& e : edges_) {
    e->computeError();
    sum += robust ? e->robustChi2() : e->chi2();
  }
  return sum;
}

VertexBase* chooseGaugeVertex(const Graph& graph, GaugeChoice choice) {
  std::unordered_set<const VertexBase*> attached;
  for (const auto& edge : graph.edges()) attached.insert(edge->vertices().begin(), edge->vertices().end());
  VertexBase* best = nullptr;
  for (const auto& [id, vertex] : graph.vertices()) {
    if (vertex->fixed()) return nullptr;
    if (attached.count(vertex.get()) == 0) continue;
    const bool better = best == nullptr || vertex->tangentDim() > best->tangentDim() ||
                        (choice == GaugeChoice::kHighestId && vertex->tangentDim() == best->tangentDim());
    if (better) best = vertex.get();
  }
  return best;
}

Status cloneGraph(const Graph& source, Graph& target) {
  if (target.numVertices() != 0 || target.numEdges() != 0 || !target.parameters().all().empty()) {
    return Status(StatusCode::kInvalidArgument, "cloneGraph: the target graph is not empty");
  }
  const auto no_clone = [](const std::string& what) {
    return Status(StatusCode::kInvalidArgument, "cloneGraph: " + what + ": its type does not implement clone()");
  };
  Status status = [&]() -> Status {
    for (const auto& [id, parameter] : source.parameters().all()) {
      std::unique_ptr<ParameterBase> copy = parameter->clone();
      if (!copy) return no_clone("parameter " + std::to_string(id));
      DG_RETURN_IF_ERROR(target.parameters().add(std::move(copy)));
    }
    for (const auto& [id, vertex] : source.vertices()) {
      std::unique_ptr<VertexBase> copy = vertex->clone();
      if (!copy) return no_clone("vertex " + std::to_string(id));
      DG_RETURN_IF_ERROR(target.addVertex(std::move(copy)));
    }
    for (const std::unique_ptr<EdgeBase>& edge : source.edges()) {
      std::unique_ptr<EdgeBase> copy = edge->clone();
      if (!copy) return no_clone(describeEdge(*edge));
      for (size_t i = 0; i < edge->numVertices(); ++i) {
        DG_RETURN_IF_ERROR(copy->setVertex(i, target.vertex(edge->vertex(i)->id())));
      }
      DG_RETURN_IF_ERROR(target.addEdge(std::move(copy)).status());
    }
    return Status();
  }();
  if (!status.ok()) target.clear();  // parameters too
  return status;
}

}  // namespace dualgraph
