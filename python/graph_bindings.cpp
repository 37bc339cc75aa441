// SPDX-License-Identifier: MIT
// dualgraph.Graph (with edges defined in Python) and dualgraph.OptimizeSummary.
#include <pybind11/stl.h>

#include <cstdio>

#include "arrays.h"
#include "bindings.h"
#include "errors.h"
#include "py_graph.h"
#include "typed_args.h"
#include "dualgraph/types/se3_math.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace dualgraph::python {

namespace {

std::string graphRepr(const PyGraph& g) {
  size_t fixed = 0;
  for (const auto& [id, vertex] : g.graph().vertices()) fixed += vertex->fixed() ? 1 : 0;
  return "Graph(vertices=" + std::to_string(g.graph().numVertices()) + ", edges=" + std::to_string(g.graph().numEdges()) +
         ", fixed=" + std::to_string(fixed) + ", custom_edges=" + std::to_string(g.numCustomEdges()) + ")";
}

std::string summaryRepr(const SolverSummary& s) {
  char chi2[96];
  std::snprintf(chi2, sizeof(chi2), "initial_chi2=%.9g, final_chi2=%.9g", s.initial_chi2, s.final_chi2);
  return "OptimizeSummary(termination=" + std::string(terminationReasonName(s.termination)) +
         ", iterations=" + std::to_string(s.iterations) + ", " + chi2 + ", linear_solver=" + s.linear_solver + ")";
}

void bindSummary(py::module_& m) {
  py::class_<SolverSummary>(m, "OptimizeSummary", "Outcome of Graph.optimize (chi2 is g2o's: sum of rho(e^T Omega e)).")
      .def_property_readonly("termination", [](const SolverSummary& s) { return terminationReasonName(s.termination); },
                             "why it stopped: 'converged', 'max_iterations', 'no_decrease', 'time_budget', ... (core/optimizer.h)")
      .def_readonly("message", &SolverSummary::message, "detail: which edge was NaN, the solver's error, ... ('' when none)")
      .def_readonly("iterations", &SolverSummary::iterations, "iterations performed, accepted or not [count]")
      .def_readonly("initial_chi2", &SolverSummary::initial_chi2, "robust chi2 at the start [dimensionless, whitened]")
      .def_readonly("final_chi2", &SolverSummary::final_chi2, "robust chi2 at the end [dimensionless, whitened]")
      .def_readonly("vertices", &SolverSummary::vertices, "free vertices in the system [count]")
      .def_readonly("edges", &SolverSummary::edges, "edges in the system [count]")
      .def_readonly("dimension", &SolverSummary::dimension, "rows of H [count]")
      .def_readonly("nonzeros", &SolverSummary::nonzeros, "stored entries of H's upper triangle [count]")
      .def_readonly("factorizations", &SolverSummary::factorizations, "numeric factorisations [count]")
      .def_readonly("total_ms", &SolverSummary::total_ms, "wall time of the call [ms]")
      .def_readonly("linear_solver", &SolverSummary::linear_solver, "the linear solver's name")
      .def_property_readonly("usable", &SolverSummary::usable, "converged, or stopped by the iteration/time budget")
      .def("__repr__", &summaryRepr);
}

}  // namespace

void bindGraph(py::module_& m) {
  bindSummary(m);
  py::class_<PyGraph>(m, "Graph", R"doc(A factor graph of the library's g2o types.

Vertex kinds: 'se3' (VERTEX_SE3:QUAT, world_T_body as [x y z qx qy qz qw] [m, unit quaternion] or a 4x4
matrix), 'se2' (VERTEX_SE2, [x y theta] [m, m, rad]), 'point' (VERTEX_TRACKXYZ, [x y z] [m]). Information
matrices are in each edge's own units, as in g2o files (EDGE_SE3:QUAT's rotation rows are q.vec ~ theta/2:
convert metric ones with information_metric_to_g2o). Batches are all-or-nothing: every row is checked before
the first is added. Edges defined in Python: add_custom_edge.)doc")
      .def(py::init<>(), "An empty graph, the library's vertex and edge types registered.")
      .def_static("load", &PyGraph::load, "path"_a, "skip_unknown_tags"_a = false, "repair_information"_a = false,
                  "Reads a g2o file. skip_unknown_tags: ignore lines of unknown types instead of raising; "
                  "repair_information: replace information matrices that are not positive definite by the nearest "
                  "ones that are. ParseError names file:line: field.")
      .def("save", &PyGraph::save, "path"_a,
           "Writes a g2o file (atomically). Raises FailedPreconditionError when the graph holds Python-defined "
           "edges (add_custom_edge): they have no g2o form, and a file without them would be another problem.")
      .def_property_readonly("num_vertices", [](const PyGraph& g) { return g.graph().numVertices(); }, "vertices [count]")
      .def_property_readonly("num_edges", [](const PyGraph& g) { return g.graph().numEdges(); }, "edges, custom ones included [count]")
      .def("add_se3_vertices", [](PyGraph& g, IdsLike ids, ArrayLike poses, bool fixed) { g.addVertices("se3", ids, poses, fixed); },
           "ids"_a, "poses"_a, "fixed"_a = false,
           "ids (n,) [int >= 0]; poses world_T_body (n, 7) [x y z qx qy qz qw] (m, quaternion normalised here) or "
           "(n, 4, 4); fixed: held constant by optimize.")
      .def("add_se2_vertices", [](PyGraph& g, IdsLike ids, ArrayLike poses, bool fixed) { g.addVertices("se2", ids, poses, fixed); },
           "ids"_a, "poses"_a, "fixed"_a = false, "ids (n,); poses (n, 3) [x y theta] [m, m, rad]; fixed: held constant.")
      .def("add_point_vertices", [](PyGraph& g, IdsLike ids, ArrayLike points, bool fixed) { g.addVertices("point", ids, points, fixed); },
           "ids"_a, "points"_a, "fixed"_a = false, "ids (n,); points p_world (n, 3) [m]; fixed: held constant.")
      .def("add_se3_edges",
           [](PyGraph& g, ArrayLike pairs, ArrayLike z, ArrayLike omega) { g.addEdges("se3", pairs, z, omega, std::nullopt); },
           "pairs"_a, "measurements"_a, "information"_a,
           "EDGE_SE3:QUAT: pairs (m, 2) [i j] vertex ids; measurements i_T_j (m, 7) [m, quaternion] or (m, 4, 4); "
           "information (6, 6) or (m, 6, 6) in g2o units [1/m^2 on t, 1/q.vec^2 on the rotation].")
      .def("add_se2_edges",
           [](PyGraph& g, ArrayLike pairs, ArrayLike z, ArrayLike omega) { g.addEdges("se2", pairs, z, omega, std::nullopt); },
           "pairs"_a, "measurements"_a, "information"_a,
           "EDGE_SE2: pairs (m, 2); measurements i_T_j (m, 3) [x y theta] [m, m, rad]; information (3, 3) or "
           "(m, 3, 3) [1/m^2, 1/rad^2].")
      .def("add_se3_point_edges",
           [](PyGraph& g, ArrayLike pairs, ArrayLike z, ArrayLike omega, std::optional<int> offset_id) {
             g.addEdges("se3_point", pairs, z, omega, offset_id);
           },
           "pairs"_a, "measurements"_a, "information"_a, "offset_id"_a = py::none(),
           "EDGE_SE3_TRACKXYZ: pairs (m, 2) [pose point]; measurements p_sensor (m, 3) [m]; information (3, 3) or "
           "(m, 3, 3) [1/m^2]; offset_id: the sensor offset (add_sensor_offset), None = id 0 (identity).")
      .def("add_se3_priors",
           [](PyGraph& g, IdsLike ids, ArrayLike z, ArrayLike omega, std::optional<int> offset_id) {
             g.addPriors("se3_prior", ids, z, omega, offset_id);
           },
           "ids"_a, "measurements"_a, "information"_a, "offset_id"_a = py::none(),
           "EDGE_SE3_PRIOR: ids (m,); measurements world_T_sensor (m, 7) or (m, 4, 4) [m, quaternion]; information "
           "(6, 6) or (m, 6, 6) in g2o units; offset_id: as add_se3_point_edges.")
      .def("add_point_priors",
           [](PyGraph& g, IdsLike ids, ArrayLike z, ArrayLike omega) { g.addPriors("point_prior", ids, z, omega, std::nullopt); },
           "ids"_a, "measurements"_a, "information"_a,
           "EDGE_POINTXYZ_PRIOR: ids (m,); measurements p_world (m, 3) [m]; information (3, 3) or (m, 3, 3) [1/m^2].")
      .def("add_custom_edge",
           [](PyGraph& g, IdsLike ids, int dimension, OptionalArrayLike information, ResidualCallback residual,
              JacobianCallback jacobians, bool as_matrix) {
             return g.addCustomEdge(ids, dimension, information, residual.object, jacobians.object, as_matrix);
           },
           "vertex_ids"_a, "dimension"_a, "information"_a, "residual"_a, "jacobians"_a = py::none(), "as_matrix"_a = false,
           R"doc(An edge defined in Python (as GTSAM's CustomFactor); returns its index among the custom edges.

vertex_ids: the vertices it connects, in the order the callbacks see them (se3, se2 or point, distinct).
dimension: d, the residual's length. information: Omega (d, d), symmetric positive definite, in the inverse
squared units of the residual (None: identity); chi2 = e^T Omega e. residual(estimates) -> e (d,): estimates
is a list with one array per vertex, se3 (7,) [x y z qx qy qz qw] [m] (w >= 0; (4, 4) when as_matrix), se2 (3,)
[x y theta] [m, m, rad], point (3,) [m]. jacobians(estimates) -> a list of (d, dof_i) arrays, de/d(delta_i) at
delta_i = 0 in each vertex's own increment chart: se3 x <- x * Exp(delta), delta = [dt; dq] (6,) in the body
frame, dt [m], dq the increment quaternion's vector part (~ dtheta / 2 [rad]); se2 [x y theta] += delta;
point p += delta. Without it: central differences of residual (step 1e-6) in that chart. Callbacks run with the
GIL held, inside optimize / chi2 / marginal(s). An exception raised by a callback stops the optimisation and is
re-raised unchanged by that call; a wrong shape or a NaN/Inf in what a callback returns raises
InvalidArgumentError naming the edge ('custom edge 0 (vertices 1 2): residual ...'). The estimates are left at
the last accepted step. Graph.save refuses graphs with custom edges.)doc")
      .def("add_sensor_offset", [](PyGraph& g, int id, ArrayLike pose) { g.addSensorOffset(id, pose); }, "id"_a, "body_T_sensor"_a,
           "PARAMS_SE3OFFSET body_T_sensor (7,) or (4, 4) [m] for se3 priors / point edges (offset_id); without one "
           "they use id 0 = identity.")
      .def("vertex_ids", &PyGraph::vertexIds, "kind"_a = py::none(), "Ids in increasing order, of one kind ('se3', 'se2', 'point') or all (None).")
      .def("vertex_kind", &PyGraph::vertexKind, "id"_a, "'se3', 'se2', 'point', or '' for a vertex of another type.")
      .def("se3_estimates", [](const PyGraph& g, OptionalIdsLike ids) { return g.estimates("se3", ids); }, "ids"_a = py::none(),
           "(n, 7) [x y z qx qy qz qw] [m] (w >= 0) of ids; all se3 vertices when ids is None.")
      .def("se2_estimates", [](const PyGraph& g, OptionalIdsLike ids) { return g.estimates("se2", ids); }, "ids"_a = py::none(),
           "(n, 3) [x y theta] [m, m, rad] of ids; all se2 vertices when ids is None.")
      .def("point_estimates", [](const PyGraph& g, OptionalIdsLike ids) { return g.estimates("point", ids); }, "ids"_a = py::none(),
           "(n, 3) [x y z] [m] of ids; all point vertices when ids is None.")
      .def("set_se3_estimates", [](PyGraph& g, IdsLike ids, ArrayLike p) { g.setEstimates("se3", ids, p); }, "ids"_a, "poses"_a,
           "poses (n, 7) [m, quaternion] or (n, 4, 4) for ids (n,).")
      .def("set_se2_estimates", [](PyGraph& g, IdsLike ids, ArrayLike p) { g.setEstimates("se2", ids, p); }, "ids"_a, "poses"_a,
           "poses (n, 3) [x y theta] [m, m, rad] for ids (n,).")
      .def("set_point_estimates", [](PyGraph& g, IdsLike ids, ArrayLike p) { g.setEstimates("point", ids, p); }, "ids"_a, "points"_a,
           "points (n, 3) [m] for ids (n,).")
      .def("set_fixed", [](PyGraph& g, IdsLike ids, bool fixed) { g.setFixed(ids, fixed); }, "ids"_a, "fixed"_a = true,
           "Fixes (or frees) the vertices ids (an id or (n,)).")
      .def("fixed_ids", [](const PyGraph& g) {
        std::vector<long long> ids;
        for (const auto& [id, vertex] : g.graph().vertices()) if (vertex->fixed()) ids.push_back(id);
        return py::array_t<long long>(static_cast<py::ssize_t>(ids.size()), ids.data());
      }, "(n,) ids of the fixed vertices, increasing.")
      .def("fix_gauge", &PyGraph::fixGauge, "choice"_a = "highest",
           "Fixes the highest- (default, as `dualgraph optimize --gauge highest`) or lowest-id ('lowest') vertex of the "
           "largest dimension unless something is fixed; returns its id or None.")
      .def("set_robust_kernel", &PyGraph::setRobustKernel, "spec"_a,
           "'none', 'huber:1.0', 'cauchy:d', 'tukey:d', 'dcs:d' on every edge (d in whitened-error units, i.e. sigmas).")
      .def("chi2", &PyGraph::chi2, "robust"_a = false,
           "sum of e^T Omega e over the edges at the current estimates [dimensionless]; robust: with the kernels' rho.")
      .def("optimize",
           [](PyGraph& g, int max_iterations, const std::string& algorithm, const std::string& linear_solver,
              double relative_decrease_stop, double time_budget_ms, bool check, const std::string& damping,
              const std::string& init) {
             return g.optimize({max_iterations, algorithm, linear_solver, relative_decrease_stop, time_budget_ms, check,
                                damping, init});
           },
           "max_iterations"_a = 100, "algorithm"_a = "lm", "linear_solver"_a = "cholmod", "relative_decrease_stop"_a = 1e-9,
           "time_budget_ms"_a = 0.0, "check"_a = true, "damping"_a = "diagonal", "init"_a = "none",
           "Levenberg-Marquardt ('lm') or Gauss-Newton ('gn') with 'cholmod' or 'eigen'. max_iterations [count]; "
           "relative_decrease_stop: stop when a step lowers chi2 by less than this fraction [1]; time_budget_ms: wall "
           "time [ms], 0 = none; damping (LM): 'diagonal' (H + lambda diag H, Ceres; the default) or 'identity' "
           "(H + lambda I, g2o's, iteration for iteration). init: 'none' (the graph's estimates, so repeated calls "
           "continue), 'chordal' (rotations by chordal relaxation, then translations, in place before the solve; a "
           "graph of only se2 or only se3 vertices and edges, else FailedPreconditionError) or 'auto' (chordal on such "
           "a graph without robust kernels, none otherwise: `dualgraph optimize`'s default); initial_chi2 is then "
           "after the initialisation. "
           "Raises OptimizationError when the result is not usable (unless check=False), and a custom edge's callback "
           "error unchanged.")
      .def("marginal", [](PyGraph& g, int id, bool metric) { return g.marginals(py::int_(id), metric); }, "id"_a,
           "metric"_a = false,
           "Marginal covariance of one vertex in its tangent space (se3: g2o's [dt; dq] [m^2, 1]; metric=True gives "
           "[dt; dtheta] [m^2, rad^2]; se2 [m^2, rad^2]; point [m^2]).")
      .def("marginals", [](PyGraph& g, IdsLike ids, bool metric) { return g.marginals(ids, metric); }, "ids"_a, "metric"_a = false,
           "Joint marginal covariance of several vertices, blocks in the order of ids (units as marginal); fixed "
           "vertices are zero.")
      .def("marginal_blocks", [](PyGraph& g, IdsLike ids, bool metric) { return g.marginalBlocks(ids, metric); }, "ids"_a,
           "metric"_a = false,
           "Each vertex's own marginal covariance, shape (n, d, d) in the order of ids (repeats allowed), in its tangent "
           "space (se3: g2o's [dt; dq] [m^2, 1], metric=True gives [dt; dtheta] [m^2, rad^2]; se2 [dx dy dtheta] "
           "[m^2, rad^2]; point [m^2]); fixed vertices are zero. All blocks come from one pass over CHOLMOD's factor "
           "(its selected inverse): all of a graph's vertices cost about one factorisation. The ids must share one tangent "
           "dimension d (InvalidArgumentError otherwise). A free gauge (nothing fixed, no prior) is "
           "FailedPreconditionError.")
      .def("__repr__", &graphRepr);

  m.def("information_metric_to_g2o", [](ArrayLike omega) { return matrixArray(informationMetricToG2o(toMatrix(omega, "information", 6, 6))); },
        "information"_a, "Metric [t; theta] information (6, 6) [1/m^2, 1/rad^2] -> EDGE_SE3:QUAT units (rotation rows/columns x2).");
  m.def("covariance_g2o_to_metric", [](ArrayLike sigma) { return matrixArray(covarianceG2oToMetric(toMatrix(sigma, "covariance", 6, 6))); },
        "covariance"_a, "VertexSE3 marginal (6, 6) in g2o's [dt; dq] -> metric [dt; dtheta] [m^2, rad^2].");
  m.def("pose_to_matrix", [](ArrayLike pose) { return poseMatrix(toPose(pose, "pose")); }, "pose"_a,
        "[x y z qx qy qz qw] [m] (or 4x4) -> (4, 4).");
  m.def("matrix_to_pose", [](ArrayLike pose) { return poseArray(toPose(pose, "pose")); }, "pose"_a,
        "4x4 (or [x y z qx qy qz qw]) [m] -> (7,) with w >= 0.");
}

}  // namespace dualgraph::python
