// SPDX-License-Identifier: MIT
// PyCustomEdge: an edge whose residual (and optionally Jacobians) are Python callables (Graph.add_custom_edge).
#pragma once

#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dualgraph/core/edge.h"

namespace dualgraph::python {

/// The first failure of a Python callback during one Graph call (optimize, chi2, marginals): the Python
/// exception it raised, or the binding's own error for a bad value (shape, NaN) naming the edge. Once set,
/// every custom edge returns NaN without calling Python, so the optimiser stops within a few evaluations
/// (a non-finite χ² or Jacobian ends it: core/optimizer.h); the Graph call then re-raises it.
class CallbackFailure {
 public:
  bool failed() const { return failed_; }
  /// Keeps the first failure only: the Python error currently being handled (`error`).
  void set(pybind11::error_already_set error);
  void clear();
  /// Raises the failure (the original Python exception, unchanged) and clears it; no-op when none.
  void raiseIfFailed();

 private:
  bool failed_ = false;
  std::optional<pybind11::error_already_set> error_;
};

/// An edge over 1+ se3 / se2 / point vertices with `dimension` residuals e = residual(estimates), χ² = eᵀΩe.
/// `estimates` is a list with one array per vertex: se3 (7,) [x y z qx qy qz qw] (w ≥ 0) or, with
/// `as_matrix`, (4, 4); se2 (3,) [x y θ]; point (3,). Jacobians are with respect to each vertex's increment δ in
/// the vertex's own chart (its `plus`): se3 x ← x · exp_g2o(δ), δ = [δt; δq] (body frame, δq the quaternion's
/// vector part ≈ δθ/2); se2 [x y θ] += δ; point p += δ. Without a Jacobian callback they are central differences
/// of `residual` through that chart (fixed vertices skipped). Must only be called with the GIL held.
class PyCustomEdge final : public EdgeBase {
 public:
  PyCustomEdge(long index, size_t num_vertices, const Eigen::MatrixXd& information, pybind11::object residual,
               pybind11::object jacobians, bool as_matrix, std::shared_ptr<CallbackFailure> failure);

  int errorDim() const override { return dimension_; }
  Status setVertex(size_t i, VertexBase* vertex) override;
  void computeError() override;
  void linearize() override;
  void computeJacobians() override;
  const double* errorData() const override { return error_.data(); }
  const double* jacobianData(size_t i) const override { return jacobians_.at(i).data(); }
  const double* informationData() const override { return information_.data(); }
  double* mutableInformationData() override { return information_.data(); }
  /// A Python-defined edge has no g2o form: read fails, write is never reached (Graph.save refuses first).
  Status read(TokenReader& in, const ParameterContainer& parameters) override;
  void write(std::ostream& out) const override;

  /// "custom edge 2 (vertices 0 1)": how errors name it.
  std::string name() const;

 private:
  pybind11::list estimates() const;
  /// Calls `callable(estimates)`; records a raised exception and returns a null object.
  pybind11::object call(const pybind11::object& callable);
  /// Converts and checks one returned array against `rows` × `cols`; records an error and returns false.
  bool take(pybind11::handle value, const std::string& what, int rows, int cols, double* out);

  long index_;
  int dimension_;
  Eigen::VectorXd error_;
  Eigen::MatrixXd information_;
  std::vector<Eigen::MatrixXd> jacobians_;
  pybind11::object residual_;
  pybind11::object jacobian_callback_;
  bool as_matrix_;
  std::shared_ptr<CallbackFailure> failure_;
};

}  // namespace dualgraph::python
