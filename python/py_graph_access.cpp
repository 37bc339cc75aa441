// SPDX-License-Identifier: MIT
// PyGraph: reading and writing estimates, fixing, optimising, marginal covariances.
#include <set>

#include "arrays.h"
#include "dualgraph/core/robust_kernel.h"
#include "errors.h"
#include "py_graph.h"
#include "dualgraph/solvers/chordal_init.h"
#include "dualgraph/solvers/marginal_covariance.h"
#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se2.h"
#include "dualgraph/types/vertex_se3.h"

namespace py = pybind11;

namespace dualgraph::python {
namespace {

using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

long widthOf(const std::string& kind) { return kind == "se3" ? 7 : 3; }

}  // namespace

const VertexBase* PyGraph::vertexOfKind(int id, const std::string& kind, const std::string& what) const {
  const VertexBase* vertex = graph_.vertex(id);
  if (!vertex) raise(Status(StatusCode::kNotFound, what + ": vertex " + std::to_string(id) + " not found"));
  if (vertexKindName(*vertex) != kind) {
    const std::string* tag = registry_.tagOf(*vertex);
    raiseInvalid(what + ": vertex " + std::to_string(id) + " is a " + (tag ? *tag : std::string("vertex of another type")) +
                 ", not a '" + kind + "' vertex");
  }
  return vertex;
}

py::array_t<long long> PyGraph::vertexIds(const std::optional<std::string>& kind) const {
  if (kind && *kind != "se3" && *kind != "se2" && *kind != "point") {
    raiseInvalid("kind must be 'se3', 'se2', 'point' or None, got '" + *kind + "'");
  }
  std::vector<long long> ids;
  for (const auto& [id, vertex] : graph_.vertices()) {
    if (!kind || vertexKindName(*vertex) == *kind) ids.push_back(id);
  }
  py::array_t<long long> out(static_cast<py::ssize_t>(ids.size()));
  std::copy(ids.begin(), ids.end(), out.mutable_data());
  return out;
}

std::string PyGraph::vertexKind(int id) const {
  const VertexBase* vertex = graph_.vertex(id);
  if (!vertex) raise(Status(StatusCode::kNotFound, "vertex " + std::to_string(id) + " not found"));
  return vertexKindName(*vertex);
}

py::array_t<double> PyGraph::estimates(const std::string& kind, py::handle ids_object) const {
  std::vector<int> ids;
  if (ids_object.is_none()) {
    for (const auto& [id, vertex] : graph_.vertices()) {
      if (vertexKindName(*vertex) == kind) ids.push_back(id);
    }
  } else {
    ids = toIds(ids_object, "ids");
  }
  const long width = widthOf(kind);
  py::array_t<double> out({static_cast<py::ssize_t>(ids.size()), static_cast<py::ssize_t>(width)});
  double* row = out.mutable_data();
  for (int id : ids) {
    const VertexBase* vertex = vertexOfKind(id, kind, "ids");
    if (kind == "se3") {
      Eigen::Map<Eigen::Matrix<double, 7, 1>> out_row(row);
      out_row = poseToVector(static_cast<const VertexSE3*>(vertex)->estimate());
    } else if (kind == "se2") {
      Eigen::Map<Eigen::Vector3d> out_row(row);
      out_row = static_cast<const VertexSE2*>(vertex)->estimate().toVector();
    } else {
      Eigen::Map<Eigen::Vector3d> out_row(row);
      out_row = static_cast<const VertexPointXYZ*>(vertex)->estimate();
    }
    row += width;
  }
  return out;
}

void PyGraph::setEstimates(const std::string& kind, py::handle ids_object, py::handle estimates) {
  const std::vector<int> ids = toIds(ids_object, "ids");
  const long n = static_cast<long>(ids.size());
  std::vector<VertexBase*> vertices;
  for (int id : ids) vertices.push_back(vertexOfKind(id, kind, "ids"));
  if (kind == "se3") {
    const IsometryList poses = toPoses(estimates, "poses", n);
    for (long i = 0; i < n; ++i) static_cast<VertexSE3*>(vertices[i])->setEstimate(poses[i]);
    return;
  }
  const Rows rows = toRows(estimates, kind == "se2" ? "poses" : "points", n, 3);
  for (long i = 0; i < n; ++i) {
    if (kind == "se2") {
      static_cast<VertexSE2*>(vertices[i])->setEstimate(SE2(rows(i, 0), rows(i, 1), rows(i, 2)));
    } else {
      static_cast<VertexPointXYZ*>(vertices[i])->setEstimate(rows.row(i).transpose());
    }
  }
}

void PyGraph::setFixed(py::handle ids_object, bool fixed) {
  const std::vector<int> ids = toIds(ids_object, "ids");
  for (int id : ids) {
    if (!graph_.vertex(id)) raise(Status(StatusCode::kNotFound, "ids: vertex " + std::to_string(id) + " not found"));
  }
  for (int id : ids) check(graph_.setFixed(id, fixed));
}

std::optional<int> PyGraph::fixGauge(const std::string& choice) {
  if (choice != "lowest" && choice != "highest") raiseInvalid("choice must be 'lowest' or 'highest', got '" + choice + "'");
  VertexBase* gauge = chooseGaugeVertex(graph_, choice == "lowest" ? GaugeChoice::kLowestId : GaugeChoice::kHighestId);
  if (!gauge) return std::nullopt;
  check(graph_.setFixed(gauge->id(), true));
  return gauge->id();
}

void PyGraph::setRobustKernel(const std::string& spec) {
  std::shared_ptr<const RobustKernel> kernel;
  if (spec != "none") kernel = unwrap(makeRobustKernel(spec));
  for (const auto& edge : graph_.edges()) edge->setRobustKernel(kernel);
}

Optimizer& PyGraph::optimizer(LinearSolverKind kind) {
  if (!optimizer_ || optimizer_kind_ != kind) {
    optimizer_ = std::make_unique<Optimizer>(graph_, makeLinearSolver(kind));
    optimizer_kind_ = kind;
  }
  return *optimizer_;
}

SolverSummary PyGraph::optimize(const OptimizeOptions& options) {
  if (options.algorithm != "lm" && options.algorithm != "gn") {
    raiseInvalid("algorithm must be 'lm' or 'gn', got '" + options.algorithm + "'");
  }
  if (options.max_iterations < 0) raiseInvalid("max_iterations must be >= 0");
  if (options.damping != "identity" && options.damping != "diagonal") {
    raiseInvalid("damping must be 'identity' or 'diagonal', got '" + options.damping + "'");
  }
  const PoseGraphInit init = unwrap(parsePoseGraphInit(options.init));
  OptimizerParams params;
  params.algorithm = options.algorithm == "gn" ? Algorithm::kGaussNewton : Algorithm::kLevenbergMarquardt;
  params.max_iterations = options.max_iterations;
  params.relative_decrease_stop = options.relative_decrease_stop;
  params.time_budget_ms = options.time_budget_ms;
  params.damping = options.damping == "diagonal" ? LmDamping::kDiagonal : LmDamping::kIdentity;
  const LinearSolverKind linear_kind = unwrap(parseLinearSolverKind(options.linear_solver));
  Optimizer& optimizer_ref = optimizer(linear_kind);
  unwrap(initializePoseGraph(graph_, init, linear_kind));  // before the solve; a failure changes nothing
  // The GIL stays held: a Graph is not thread-safe, and another thread must not change it mid-solve.
  callback_failure_->clear();
  const SolverSummary summary = optimizer_ref.optimize(params);
  callback_failure_->raiseIfFailed();  // a custom edge's callback raised (or returned a bad value): that error
  if (options.check && !summary.usable()) {
    const std::string name = terminationReasonName(summary.termination);
    raiseOptimizationError(name, summary.message.empty() ? name : name + ": " + summary.message);
  }
  return summary;
}

py::array_t<double> PyGraph::marginalBlocks(py::handle ids_object, bool metric) {
  const std::vector<int> ids = toIds(ids_object, "ids");
  long dim = -1;
  int first_id = -1;
  for (int id : ids) {  // unknown ids are the library's NotFound below
    const VertexBase* vertex = graph_.vertex(id);
    if (vertex == nullptr) continue;
    if (dim < 0) {
      dim = vertex->tangentDim();
      first_id = id;
    } else if (vertex->tangentDim() != dim) {
      raiseInvalid("marginal_blocks: the vertices' tangent dimensions differ (vertex " + std::to_string(first_id) + ": " +
                   std::to_string(dim) + ", vertex " + std::to_string(id) + ": " + std::to_string(vertex->tangentDim()) +
                   "); ask for each dimension separately, or use marginals(ids) for one joint matrix");
    }
  }
  MarginalCovariance marginal;
  callback_failure_->clear();
  const Status computed = marginal.compute(optimizer(optimizer_kind_), graph_);
  callback_failure_->raiseIfFailed();
  check(computed);
  const std::vector<Eigen::MatrixXd> blocks = unwrap(marginal.blocks(ids));
  const long d = dim < 0 ? 0 : dim;
  py::array_t<double> out({static_cast<long>(ids.size()), d, d});
  double* data = out.mutable_data();
  for (size_t k = 0; k < ids.size(); ++k) {
    Eigen::MatrixXd sigma = blocks[k];
    if (metric && vertexKindName(*graph_.vertex(ids[k])) == "se3") {  // g2o's [δt; δq] → metric [δt; δθ]
      sigma = covarianceG2oToMetric(sigma);
    }
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(data + k * d * d, d, d) = sigma;
  }
  return out;
}

py::array_t<double> PyGraph::marginals(py::handle ids_object, bool metric) {
  const std::vector<int> ids = toIds(ids_object, "ids");
  MarginalCovariance marginal;
  callback_failure_->clear();
  const Status computed = marginal.compute(optimizer(optimizer_kind_), graph_);
  callback_failure_->raiseIfFailed();
  check(computed);
  Eigen::MatrixXd covariance = unwrap(marginal.jointBlock(ids));
  if (metric) {  // g2o's [δt; δq] chart of VertexSE3 → metric [δt; δθ]: Σ_metric = D Σ D, D = diag(1,1,1,2,2,2)
    Eigen::VectorXd scale = Eigen::VectorXd::Ones(covariance.rows());
    long offset = 0;
    for (int id : ids) {
      const VertexBase* vertex = graph_.vertex(id);
      if (vertexKindName(*vertex) == "se3") scale.segment<3>(offset + 3).setConstant(2.0);
      offset += vertex->tangentDim();
    }
    covariance = scale.asDiagonal() * covariance * scale.asDiagonal();
  }
  return matrixArray(covariance);
}

}  // namespace dualgraph::python
