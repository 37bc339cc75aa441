// SPDX-License-Identifier: MIT
// PyGraph, behind Python's dualgraph.Graph: numpy batches, g2o I/O, optimisation, marginals.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/core/type_registry.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "custom_edge.h"

namespace dualgraph::python {

/// What `Graph.optimize` takes (Python keywords of the same names).
struct OptimizeOptions {
  int max_iterations = 100;
  std::string algorithm = "lm";          ///< "lm" | "gn"
  std::string linear_solver = "cholmod";  ///< "cholmod" | "eigen"
  double relative_decrease_stop = 1e-9;
  double time_budget_ms = 0.0;
  bool check = true;                      ///< raise OptimizationError when the result is not usable
  std::string damping = "diagonal";       ///< LM: "diagonal" (H + λ diag H, Ceres) | "identity" (H + λI, g2o)
  /// "none" (the graph's estimates: repeated calls continue) | "chordal" | "auto" (solvers/chordal_init.h)
  std::string init = "none";
};

/// The Python `dualgraph.Graph`: a Graph with the library's types registered, batch construction from numpy
/// arrays (all-or-nothing: every row is checked before the first is added), g2o I/O, LM/GN with a kept
/// Optimizer (its symbolic analysis is reused between calls), estimates and marginal covariances as numpy.
/// Vertex kinds: "se3" (VERTEX_SE3:QUAT, poses [x y z qx qy qz qw] or 4×4), "se2" (VERTEX_SE2, [x y θ]),
/// "point" (VERTEX_TRACKXYZ, [x y z]). Information matrices are in the edges' own (g2o) units.
class PyGraph {
 public:
  PyGraph();
  static std::unique_ptr<PyGraph> load(const std::string& path, bool skip_unknown_tags, bool repair_information);
  void save(const std::string& path) const;

  void addVertices(const std::string& kind, pybind11::handle ids, pybind11::handle estimates, bool fixed);
  /// `kind`: one of the binary edge kinds "se3", "se2", "se3_point".
  void addEdges(const std::string& kind, pybind11::handle pairs, pybind11::handle measurements,
                pybind11::handle information, std::optional<int> offset_id);
  /// `kind`: "se3_prior" or "point_prior".
  void addPriors(const std::string& kind, pybind11::handle ids, pybind11::handle measurements,
                 pybind11::handle information, std::optional<int> offset_id);
  /// A PARAMS_SE3OFFSET `body_T_sensor` for the se3_prior / se3_point edges that name `id`.
  void addSensorOffset(int id, pybind11::handle body_T_sensor);

  pybind11::array_t<long long> vertexIds(const std::optional<std::string>& kind) const;
  std::string vertexKind(int id) const;
  pybind11::array_t<double> estimates(const std::string& kind, pybind11::handle ids) const;
  void setEstimates(const std::string& kind, pybind11::handle ids, pybind11::handle estimates);
  void setFixed(pybind11::handle ids, bool fixed);
  std::optional<int> fixGauge(const std::string& choice);
  void setRobustKernel(const std::string& spec);

  /// An edge whose residual (and optionally Jacobians) are Python callables (custom_edge.h); returns its index
  /// among the custom edges. `information` None: the identity.
  long addCustomEdge(pybind11::handle ids, int dimension, pybind11::handle information, pybind11::object residual,
                     pybind11::object jacobians, bool as_matrix);
  long numCustomEdges() const { return custom_edges_; }

  SolverSummary optimize(const OptimizeOptions& options);
  pybind11::array_t<double> marginals(pybind11::handle ids, bool metric);
  /// Each vertex's own covariance block, (n, d, d) (MarginalCovariance::blocks: CHOLMOD's selected inverse);
  /// every id must have the same tangent dimension d (InvalidArgumentError naming two that differ).
  pybind11::array_t<double> marginalBlocks(pybind11::handle ids, bool metric);
  /// Σ eᵀΩe (robust: Σ ρ) at the current estimates; re-raises a custom edge's callback error.
  double chi2(bool robust) const;

  Graph& graph() { return graph_; }
  const Graph& graph() const { return graph_; }
  const TypeRegistry& registry() const { return registry_; }

 private:
  struct SensorOffset {
    int id = 0;
    Eigen::Isometry3d body_T_sensor = Eigen::Isometry3d::Identity();
    bool create = false;  ///< id 0 does not exist yet: add the identity offset with the edges
  };
  /// The offset `offset_id` names; without one, id 0 (created as the identity when absent).
  SensorOffset sensorOffset(std::optional<int> offset_id) const;
  /// Adds checked edges (cannot fail unless the graph changed in between).
  void commitEdges(std::vector<std::unique_ptr<EdgeBase>> edges, bool create_identity_offset);
  /// The kept optimiser, rebuilt when the linear solver changes.
  Optimizer& optimizer(LinearSolverKind kind);
  /// Vertex `id` of kind `kind` or raises NotFoundError / InvalidArgumentError naming it.
  const VertexBase* vertexOfKind(int id, const std::string& kind, const std::string& what) const;
  VertexBase* vertexOfKind(int id, const std::string& kind, const std::string& what) {
    return const_cast<VertexBase*>(static_cast<const PyGraph&>(*this).vertexOfKind(id, kind, what));
  }

  TypeRegistry registry_;
  Graph graph_;
  std::unique_ptr<Optimizer> optimizer_;
  LinearSolverKind optimizer_kind_ = LinearSolverKind::kCholmod;
  /// Shared with every custom edge: the first callback failure of the current call.
  std::shared_ptr<CallbackFailure> callback_failure_ = std::make_shared<CallbackFailure>();
  long custom_edges_ = 0;
};

/// "se3", "se2", "point", or "" for a vertex of another (user-registered) type.
std::string vertexKindName(const VertexBase& vertex);

}  // namespace dualgraph::python
