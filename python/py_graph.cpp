// SPDX-License-Identifier: MIT
#include "py_graph.h"

#include <set>

#include "arrays.h"
#include "dualgraph/core/g2o_io.h"
#include "errors.h"
#include "dualgraph/solvers/marginal_covariance.h"
#include "dualgraph/types/edge_point_xyz_prior.h"
#include "dualgraph/types/edge_se2.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/edge_se3_prior.h"
#include "dualgraph/types/parameter_se3_offset.h"
#include "dualgraph/types/register_types.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se2.h"
#include "dualgraph/types/vertex_se3.h"

namespace py = pybind11;

namespace dualgraph::python {
namespace {

using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

void requireKind(const std::string& kind) {
  if (kind != "se3" && kind != "se2" && kind != "point") {
    raiseInvalid("kind must be 'se3', 'se2' or 'point', got '" + kind + "'");
  }
}

// The (m, 2) integer vertex pairs of a batch of binary edges.
std::vector<std::pair<int, int>> toPairs(py::handle object) {
  py::array array = py::array::ensure(object);
  if (!array || array.ndim() != 2 || array.shape(1) != 2) {
    raiseInvalid("pairs: expected shape (m, 2) of vertex ids" + (array ? ", got " + shapeString(array) : std::string()));
  }
  const std::vector<int> flat = toIds(array.attr("reshape")(-1), "pairs");
  std::vector<std::pair<int, int>> pairs;
  for (size_t k = 0; k + 1 < flat.size(); k += 2) pairs.emplace_back(flat[k], flat[k + 1]);
  return pairs;
}

// Connects slot `slot` of `edge` (the k-th of a batch) to vertex `id`, or raises naming both.
void connect(Graph& graph, EdgeBase& edge, size_t slot, int id, size_t k) {
  VertexBase* vertex = graph.vertex(id);
  if (!vertex) raise(Status(StatusCode::kNotFound, "edge " + std::to_string(k) + ": vertex " + std::to_string(id) + " not found"));
  const Status connected = edge.setVertex(slot, vertex);
  if (!connected.ok()) raise(Status(connected.code(), "edge " + std::to_string(k) + ": " + connected.message()));
}

// Ω of every edge must be symmetric positive definite, as the g2o reader demands.
void requireValidInformation(const std::vector<std::unique_ptr<EdgeBase>>& edges) {
  for (size_t k = 0; k < edges.size(); ++k) {
    if (!edges[k]->informationIsValid()) {
      raiseInvalid("information[" + std::to_string(k) + "] is not symmetric positive definite");
    }
  }
}

}  // namespace

std::string vertexKindName(const VertexBase& vertex) {
  if (dynamic_cast<const VertexSE3*>(&vertex)) return "se3";
  if (dynamic_cast<const VertexSE2*>(&vertex)) return "se2";
  if (dynamic_cast<const VertexPointXYZ*>(&vertex)) return "point";
  return "";
}

PyGraph::PyGraph() { check(registerBuiltinTypes(registry_)); }

std::unique_ptr<PyGraph> PyGraph::load(const std::string& path, bool skip_unknown_tags, bool repair_information) {
  auto loaded = std::make_unique<PyGraph>();
  G2oReadOptions options;
  options.skip_unknown_tags = skip_unknown_tags;
  options.repair_information = repair_information;
  Result<G2oReadReport> report = [&] {
    py::gil_scoped_release release;
    return readG2o(path, loaded->registry_, loaded->graph_, options);
  }();
  check(report.status());
  return loaded;
}

void PyGraph::save(const std::string& path) const {
  if (custom_edges_ > 0) {  // refused, not skipped: a file without them would describe another problem
    raise(Status(StatusCode::kFailedPrecondition,
                 path + ": not written: the graph has " + std::to_string(custom_edges_) +
                     " Python-defined edge(s) (add_custom_edge), which have no g2o form"));
  }
  check(writeG2o(path, registry_, graph_));
}

void PyGraph::addVertices(const std::string& kind, py::handle ids_object, py::handle estimates, bool fixed) {
  requireKind(kind);
  const std::vector<int> ids = toIds(ids_object, "ids");
  std::set<int> seen;
  for (int id : ids) {
    if (!seen.insert(id).second) raise(Status(StatusCode::kAlreadyExists, "ids: vertex " + std::to_string(id) + " appears twice"));
    if (graph_.vertex(id)) raise(Status(StatusCode::kAlreadyExists, "vertex " + std::to_string(id) + " exists already"));
  }
  const long n = static_cast<long>(ids.size());
  std::vector<std::unique_ptr<VertexBase>> vertices;
  if (kind == "se3") {
    const IsometryList poses = toPoses(estimates, "poses", n);
    for (long i = 0; i < n; ++i) {
      auto v = std::make_unique<VertexSE3>(ids[i]);
      v->setEstimate(poses[i]);
      vertices.push_back(std::move(v));
    }
  } else {
    const Rows rows = toRows(estimates, kind == "se2" ? "poses" : "points", n, 3);
    for (long i = 0; i < n; ++i) {
      if (kind == "se2") {
        auto v = std::make_unique<VertexSE2>(ids[i]);
        v->setEstimate(SE2(rows(i, 0), rows(i, 1), rows(i, 2)));
        vertices.push_back(std::move(v));
      } else {
        auto v = std::make_unique<VertexPointXYZ>(ids[i]);
        v->setEstimate(rows.row(i).transpose());
        vertices.push_back(std::move(v));
      }
    }
  }
  for (auto& vertex : vertices) {
    vertex->setFixed(fixed);
    check(graph_.addVertex(std::move(vertex)));
  }
}

void PyGraph::addEdges(const std::string& kind, py::handle pairs_object, py::handle measurements, py::handle information,
                       std::optional<int> offset_id) {
  const auto pairs = toPairs(pairs_object);
  const long m = static_cast<long>(pairs.size());
  std::vector<std::unique_ptr<EdgeBase>> edges;
  SensorOffset offset;
  if (kind == "se3") {
    const IsometryList z = toPoses(measurements, "measurements", m);
    const MatrixList omega = toMatrices(information, "information", m, 6, 6);
    for (long k = 0; k < m; ++k) {
      auto e = std::make_unique<EdgeSE3>();
      e->setMeasurement(z[k]);
      e->setInformation(omega[k]);
      edges.push_back(std::move(e));
    }
  } else if (kind == "se2") {
    const Rows z = toRows(measurements, "measurements", m, 3);
    const MatrixList omega = toMatrices(information, "information", m, 3, 3);
    for (long k = 0; k < m; ++k) {
      auto e = std::make_unique<EdgeSE2>();
      e->setMeasurement(SE2(z(k, 0), z(k, 1), z(k, 2)));
      e->setInformation(omega[k]);
      edges.push_back(std::move(e));
    }
  } else {  // se3_point
    const Rows z = toRows(measurements, "measurements", m, 3);
    const MatrixList omega = toMatrices(information, "information", m, 3, 3);
    offset = sensorOffset(offset_id);
    for (long k = 0; k < m; ++k) {
      auto e = std::make_unique<EdgeSE3PointXYZ>();
      e->setMeasurement(z.row(k).transpose());
      e->setInformation(omega[k]);
      e->setOffset(offset.id, offset.body_T_sensor);
      edges.push_back(std::move(e));
    }
  }
  for (long k = 0; k < m; ++k) {
    if (pairs[k].first == pairs[k].second) {
      raiseInvalid("edge " + std::to_string(k) + ": both ends are vertex " + std::to_string(pairs[k].first));
    }
    connect(graph_, *edges[k], 0, pairs[k].first, static_cast<size_t>(k));
    connect(graph_, *edges[k], 1, pairs[k].second, static_cast<size_t>(k));
  }
  requireValidInformation(edges);
  commitEdges(std::move(edges), offset.create);
}

void PyGraph::addPriors(const std::string& kind, py::handle ids_object, py::handle measurements, py::handle information,
                        std::optional<int> offset_id) {
  const std::vector<int> ids = toIds(ids_object, "ids");
  const long m = static_cast<long>(ids.size());
  std::vector<std::unique_ptr<EdgeBase>> edges;
  SensorOffset offset;
  if (kind == "se3_prior") {
    const IsometryList z = toPoses(measurements, "measurements", m);
    const MatrixList omega = toMatrices(information, "information", m, 6, 6);
    offset = sensorOffset(offset_id);
    for (long k = 0; k < m; ++k) {
      auto e = std::make_unique<EdgeSE3Prior>();
      e->setMeasurement(z[k]);
      e->setInformation(omega[k]);
      e->setOffset(offset.id, offset.body_T_sensor);
      edges.push_back(std::move(e));
    }
  } else {  // point_prior
    const Rows z = toRows(measurements, "measurements", m, 3);
    const MatrixList omega = toMatrices(information, "information", m, 3, 3);
    for (long k = 0; k < m; ++k) {
      auto e = std::make_unique<EdgePointXYZPrior>();
      e->setMeasurement(z.row(k).transpose());
      e->setInformation(omega[k]);
      edges.push_back(std::move(e));
    }
  }
  for (long k = 0; k < m; ++k) connect(graph_, *edges[k], 0, ids[k], static_cast<size_t>(k));
  requireValidInformation(edges);
  commitEdges(std::move(edges), offset.create);
}

void PyGraph::addSensorOffset(int id, py::handle pose) {
  const Eigen::Isometry3d body_T_sensor = toPose(pose, "body_T_sensor");
  check(graph_.parameters().add(std::make_unique<ParameterSE3Offset>(id, body_T_sensor)));
}

PyGraph::SensorOffset PyGraph::sensorOffset(std::optional<int> offset_id) const {
  SensorOffset offset;
  offset.id = offset_id.value_or(0);
  const ParameterBase* parameter = graph_.parameters().find(offset.id);
  if (const auto* se3_offset = dynamic_cast<const ParameterSE3Offset*>(parameter)) {
    offset.body_T_sensor = se3_offset->offset();
  } else if (parameter || offset_id) {
    raise(Status(StatusCode::kNotFound,
                 "no PARAMS_SE3OFFSET with id " + std::to_string(offset.id) + " (add_sensor_offset adds one)"));
  } else {
    offset.create = true;  // id 0, identity: added with the edges, so `save` writes a file that reads back
  }
  return offset;
}

void PyGraph::commitEdges(std::vector<std::unique_ptr<EdgeBase>> edges, bool create_identity_offset) {
  if (create_identity_offset) check(graph_.parameters().add(std::make_unique<ParameterSE3Offset>(0)));
  for (auto& edge : edges) check(graph_.addEdge(std::move(edge)).status());
}

}  // namespace dualgraph::python
