// SPDX-License-Identifier: MIT
#include "bench/graph_clone.h"

#include <memory>
#include <random>
#include <sstream>

#include "dualgraph/core/robust_kernel.h"
#include "dualgraph/types/edge_point_xyz_prior.h"
#include "dualgraph/types/edge_se2.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/edge_se3_prior.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se2.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph::bench {
namespace {

template <typename V>
std::unique_ptr<VertexBase> copyVertex(const V& vertex) {
  auto copy = std::make_unique<V>(vertex.id());
  copy->setEstimate(vertex.estimate());
  copy->setFixed(vertex.fixed());
  return copy;
}

Result<std::unique_ptr<VertexBase>> cloneVertex(const VertexBase& vertex) {
  if (const auto* v = dynamic_cast<const VertexSE3*>(&vertex)) return copyVertex(*v);
  if (const auto* v = dynamic_cast<const VertexPointXYZ*>(&vertex)) return copyVertex(*v);
  if (const auto* v = dynamic_cast<const VertexSE2*>(&vertex)) return copyVertex(*v);
  return Status(StatusCode::kInvalidArgument, "cloneGraph: vertex " + std::to_string(vertex.id()) + " has an unsupported type");
}

/// The same measurement and information on a new edge of the same type; the offset where the type has one.
template <typename E>
std::unique_ptr<EdgeBase> copyMeasurement(const E& edge) {
  auto copy = std::make_unique<E>();
  if constexpr (std::is_same_v<E, EdgeSE3Prior> || std::is_same_v<E, EdgeSE3PointXYZ>) {
    copy->setOffset(edge.parameterId(), edge.offset());
  }
  copy->setMeasurement(edge.measurement());
  copy->setInformation(edge.information());
  return copy;
}

Result<std::unique_ptr<EdgeBase>> cloneEdge(const EdgeBase& edge) {
  if (const auto* e = dynamic_cast<const EdgeSE3*>(&edge)) return copyMeasurement(*e);
  if (const auto* e = dynamic_cast<const EdgeSE3Prior*>(&edge)) return copyMeasurement(*e);
  if (const auto* e = dynamic_cast<const EdgeSE3PointXYZ*>(&edge)) return copyMeasurement(*e);
  if (const auto* e = dynamic_cast<const EdgePointXYZPrior*>(&edge)) return copyMeasurement(*e);
  if (const auto* e = dynamic_cast<const EdgeSE2*>(&edge)) return copyMeasurement(*e);
  return Status(StatusCode::kInvalidArgument, "cloneGraph: the edge from vertex " + std::to_string(edge.vertex(0)->id()) +
                                                  " has an unsupported type (" + std::to_string(edge.errorDim()) +
                                                  "-dimensional error)");
}

}  // namespace

Status cloneGraph(const Graph& source, Graph& target) {
  for (const auto& [id, vertex] : source.vertices()) {
    Result<std::unique_ptr<VertexBase>> copy = cloneVertex(*vertex);
    if (!copy.ok()) return copy.status();
    DG_RETURN_IF_ERROR(target.addVertex(std::move(copy).value()));
  }
  for (const std::unique_ptr<EdgeBase>& edge : source.edges()) {
    Result<std::unique_ptr<EdgeBase>> copy = cloneEdge(*edge);
    if (!copy.ok()) return copy.status();
    for (size_t i = 0; i < edge->numVertices(); ++i) {
      DG_RETURN_IF_ERROR((*copy)->setVertex(i, target.vertex(edge->vertex(i)->id())));
    }
    if (const RobustKernel* kernel = edge->robustKernel()) {
      std::ostringstream spec;
      spec.precision(17);
      spec << kernel->name() << ':' << kernel->delta();
      Result<std::shared_ptr<const RobustKernel>> same = makeRobustKernel(spec.str());
      if (!same.ok()) return same.status();
      (*copy)->setRobustKernel(*same);
    }
    Result<EdgeBase*> added = target.addEdge(std::move(copy).value());
    if (!added.ok()) return added.status();
  }
  return Status();
}

void perturbGraph(Graph& graph, double sigma_t, double sigma_q, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (auto& [id, vertex] : graph.vertices()) {
    if (vertex->fixed()) continue;
    double delta[6];
    for (int k = 0; k < 6; ++k) delta[k] = (k < 3 ? sigma_t : sigma_q) * normal(rng);
    if (dynamic_cast<VertexSE3*>(vertex.get()) != nullptr || dynamic_cast<VertexPointXYZ*>(vertex.get()) != nullptr) {
      vertex->plus(delta);
    }
  }
}

}  // namespace dualgraph::bench
