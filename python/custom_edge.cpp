// SPDX-License-Identifier: MIT
// PyCustomEdge: residuals and Jacobians from Python callables, failures kept for the Graph call to re-raise.
#include "custom_edge.h"

#include <limits>

#include "arrays.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se2.h"
#include "dualgraph/types/vertex_se3.h"
#include "errors.h"
#include "py_graph.h"

namespace py = pybind11;

namespace dualgraph::python {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

void CallbackFailure::set(py::error_already_set error) {
  if (failed_) return;
  failed_ = true;
  error_.emplace(std::move(error));
}

void CallbackFailure::clear() {
  failed_ = false;
  error_.reset();
}

void CallbackFailure::raiseIfFailed() {
  if (!failed_) return;
  py::error_already_set error = std::move(*error_);
  clear();
  throw error;  // pybind11 restores the original exception (type, value, traceback)
}

PyCustomEdge::PyCustomEdge(long index, size_t num_vertices, const Eigen::MatrixXd& information, py::object residual,
                           py::object jacobians, bool as_matrix, std::shared_ptr<CallbackFailure> failure)
    : EdgeBase(num_vertices),
      index_(index),
      dimension_(static_cast<int>(information.rows())),
      error_(Eigen::VectorXd::Zero(information.rows())),
      information_(information),
      jacobians_(num_vertices),
      residual_(std::move(residual)),
      jacobian_callback_(std::move(jacobians)),
      as_matrix_(as_matrix),
      failure_(std::move(failure)) {}

Status PyCustomEdge::setVertex(size_t i, VertexBase* vertex) {
  if (i >= vertices_.size()) return Status(StatusCode::kInvalidArgument, name() + " has no vertex slot " + std::to_string(i));
  if (vertex != nullptr && vertexKindName(*vertex).empty()) {
    return Status(StatusCode::kInvalidArgument, name() + ": vertex " + std::to_string(vertex->id()) +
                                                    " is not an 'se3', 'se2' or 'point' vertex");
  }
  vertices_[i] = vertex;
  if (vertex != nullptr) jacobians_[i] = Eigen::MatrixXd::Zero(dimension_, vertex->tangentDim());
  return Status();
}

std::string PyCustomEdge::name() const {
  std::string text = "custom edge " + std::to_string(index_) + " (vertices";
  for (const VertexBase* vertex : vertices_) text += vertex ? " " + std::to_string(vertex->id()) : std::string(" ?");
  return text + ")";
}

py::list PyCustomEdge::estimates() const {
  py::list out;
  for (const VertexBase* vertex : vertices_) {
    if (const auto* se3 = dynamic_cast<const VertexSE3*>(vertex)) {
      out.append(as_matrix_ ? poseMatrix(se3->estimate()) : poseArray(se3->estimate()));
    } else if (const auto* se2 = dynamic_cast<const VertexSE2*>(vertex)) {
      out.append(matrixArray(se2->estimate().toVector().transpose()).attr("reshape")(3));
    } else {
      const auto* point = static_cast<const VertexPointXYZ*>(vertex);
      out.append(matrixArray(point->estimate().transpose()).attr("reshape")(3));
    }
  }
  return out;
}

py::object PyCustomEdge::call(const py::object& callable) {
  try {
    return callable(estimates());
  } catch (py::error_already_set& error) {
    failure_->set(std::move(error));
    return py::object();
  }
}

bool PyCustomEdge::take(py::handle value, const std::string& what, int rows, int cols, double* out) {
  try {
    const DoubleArray array = toDoubles(value, name() + ": " + what);
    const bool as_vector = array.ndim() == 1 && (cols == 1 || rows == 1) && array.size() == rows * cols;
    const bool as_matrix = array.ndim() == 2 && array.shape(0) == rows && array.shape(1) == cols;
    const bool as_scalar = array.ndim() == 0 && rows * cols == 1;
    if (!as_vector && !as_matrix && !as_scalar) {
      raiseInvalid(name() + ": " + what + " has shape " + shapeString(array) + ", expected (" + std::to_string(rows) +
                   (cols == 1 ? ",)" : ", " + std::to_string(cols) + ")"));
    }
    requireFinite(array, name() + ": " + what);
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    Eigen::Map<Eigen::MatrixXd>(out, rows, cols) = Eigen::Map<const RowMajor>(array.data(), rows, cols);
    return true;
  } catch (py::error_already_set& error) {
    failure_->set(std::move(error));
    return false;
  }
}

void PyCustomEdge::computeError() {
  if (!failure_->failed()) {
    const py::object value = call(residual_);
    if (value && take(value, "residual", dimension_, 1, error_.data())) return;
  }
  error_.setConstant(kNaN);
}

void PyCustomEdge::linearize() {
  computeError();
  computeJacobians();
}

void PyCustomEdge::computeJacobians() {
  for (size_t i = 0; i < vertices_.size(); ++i) {
    if (failure_->failed()) break;
    if (jacobian_callback_.is_none()) {  // central differences, as BaseEdge's default
      if (vertices_[i]->fixed()) {
        jacobians_[i].setZero();  // never read: a fixed vertex has no block in the system
      } else {
        numericJacobian(i, jacobians_[i].data());
      }
      continue;
    }
    const py::object value = call(jacobian_callback_);
    if (!value) break;
    try {
      const py::sequence list = py::reinterpret_borrow<py::sequence>(value);
      if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value) || py::len(list) != vertices_.size()) {
        raiseInvalid(name() + ": jacobians must return a list of " + std::to_string(vertices_.size()) +
                     " arrays (one per vertex), got " + std::string(py::str(py::repr(value))).substr(0, 80));
      }
      for (size_t k = 0; k < vertices_.size(); ++k) {
        if (!take(list[k], "jacobians[" + std::to_string(k) + "]", dimension_, vertices_[k]->tangentDim(),
                  jacobians_[k].data())) {
          break;
        }
      }
    } catch (py::error_already_set& error) {
      failure_->set(std::move(error));
    }
    break;  // one call gives every vertex's Jacobian
  }
  if (failure_->failed()) {
    for (Eigen::MatrixXd& jacobian : jacobians_) jacobian.setConstant(kNaN);
  }
}

Status PyCustomEdge::read(TokenReader& /*in*/, const ParameterContainer& /*parameters*/) {
  return Status(StatusCode::kFailedPrecondition, "a Python-defined edge cannot be read from a g2o file");
}

void PyCustomEdge::write(std::ostream& /*out*/) const {}

long PyGraph::addCustomEdge(py::handle ids_object, int dimension, py::handle information, py::object residual,
                            py::object jacobians, bool as_matrix) {
  const std::vector<int> ids = toIds(ids_object, "vertex_ids");
  if (ids.empty()) raiseInvalid("vertex_ids: a custom edge needs at least one vertex");
  if (dimension < 1) raiseInvalid("dimension must be >= 1, got " + std::to_string(dimension));
  if (!PyCallable_Check(residual.ptr())) raiseInvalid("residual must be callable, got " + std::string(py::str(py::type::of(residual))));
  if (!jacobians.is_none() && !PyCallable_Check(jacobians.ptr())) {
    raiseInvalid("jacobians must be callable or None, got " + std::string(py::str(py::type::of(jacobians))));
  }
  const Eigen::MatrixXd omega = information.is_none() ? Eigen::MatrixXd::Identity(dimension, dimension)
                                                      : toMatrix(information, "information", dimension, dimension);
  auto edge = std::make_unique<PyCustomEdge>(custom_edges_, ids.size(), omega, std::move(residual), std::move(jacobians),
                                             as_matrix, callback_failure_);
  for (size_t k = 0; k < ids.size(); ++k) {
    for (size_t j = 0; j < k; ++j) {
      if (ids[j] == ids[k]) raiseInvalid("vertex_ids: vertex " + std::to_string(ids[k]) + " appears twice");
    }
    VertexBase* vertex = graph_.vertex(ids[k]);
    if (!vertex) raise(Status(StatusCode::kNotFound, "vertex_ids: vertex " + std::to_string(ids[k]) + " not found"));
    check(edge->setVertex(k, vertex));
  }
  if (!edge->informationIsValid()) raiseInvalid("information is not symmetric positive definite");
  check(graph_.addEdge(std::move(edge)).status());
  return custom_edges_++;
}

double PyGraph::chi2(bool robust) const {
  callback_failure_->clear();
  const double value = graph_.chi2(robust);
  callback_failure_->raiseIfFailed();
  return value;
}

}  // namespace dualgraph::python
