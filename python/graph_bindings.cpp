// SPDX-License-Identifier: MIT
// dualgraph.Graph and dualgraph.OptimizeSummary.
#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "errors.h"
#include "py_graph.h"
#include "types/se3_math.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace dualgraph::python {

void bindGraph(py::module_& m) {
  py::class_<SolverSummary>(m, "OptimizeSummary", "Outcome of Graph.optimize (chi2 is g2o's: sum of e^T Omega e).")
      .def_property_readonly("termination", [](const SolverSummary& s) { return terminationReasonName(s.termination); })
      .def_readonly("message", &SolverSummary::message)
      .def_readonly("iterations", &SolverSummary::iterations)
      .def_readonly("initial_chi2", &SolverSummary::initial_chi2)
      .def_readonly("final_chi2", &SolverSummary::final_chi2)
      .def_readonly("vertices", &SolverSummary::vertices, "free vertices in the system")
      .def_readonly("edges", &SolverSummary::edges)
      .def_readonly("dimension", &SolverSummary::dimension, "rows of H")
      .def_readonly("nonzeros", &SolverSummary::nonzeros)
      .def_readonly("factorizations", &SolverSummary::factorizations)
      .def_readonly("total_ms", &SolverSummary::total_ms)
      .def_readonly("linear_solver", &SolverSummary::linear_solver)
      .def_property_readonly("usable", &SolverSummary::usable, "converged, or stopped by the iteration/time budget")
      .def("__repr__", [](const SolverSummary& s) {
        return "OptimizeSummary(termination=" + std::string(terminationReasonName(s.termination)) +
               ", iterations=" + std::to_string(s.iterations) + ", initial_chi2=" + std::to_string(s.initial_chi2) +
               ", final_chi2=" + std::to_string(s.final_chi2) + ")";
      });

  py::class_<PyGraph>(m, "Graph", R"doc(A factor graph of the library's g2o types.

Vertex kinds: 'se3' (VERTEX_SE3:QUAT, world_T_body as [x y z qx qy qz qw] or a 4x4 matrix), 'se2'
(VERTEX_SE2, [x y theta]), 'point' (VERTEX_TRACKXYZ, [x y z]). Information matrices are in each edge's own
units, as in g2o files (EDGE_SE3:QUAT's rotation rows are q.vec ~ theta/2: convert metric ones with
information_metric_to_g2o). Batches are all-or-nothing: every row is checked before the first is added.)doc")
      .def(py::init<>())
      .def_static("load", &PyGraph::load, "path"_a, "skip_unknown_tags"_a = false, "repair_information"_a = false,
                  "Reads a g2o file (ParseError names file:line: field).")
      .def("save", &PyGraph::save, "path"_a, "Writes a g2o file (atomically).")
      .def_property_readonly("num_vertices", [](const PyGraph& g) { return g.graph().numVertices(); })
      .def_property_readonly("num_edges", [](const PyGraph& g) { return g.graph().numEdges(); })
      .def("add_se3_vertices", [](PyGraph& g, py::handle ids, py::handle poses, bool fixed) { g.addVertices("se3", ids, poses, fixed); },
           "ids"_a, "poses"_a, "fixed"_a = false, "ids (n,), poses (n, 7) or (n, 4, 4): world_T_body.")
      .def("add_se2_vertices", [](PyGraph& g, py::handle ids, py::handle poses, bool fixed) { g.addVertices("se2", ids, poses, fixed); },
           "ids"_a, "poses"_a, "fixed"_a = false, "ids (n,), poses (n, 3) [x y theta].")
      .def("add_point_vertices", [](PyGraph& g, py::handle ids, py::handle points, bool fixed) { g.addVertices("point", ids, points, fixed); },
           "ids"_a, "points"_a, "fixed"_a = false, "ids (n,), points (n, 3) p_world [m].")
      .def("add_se3_edges",
           [](PyGraph& g, py::handle pairs, py::handle z, py::handle omega) { g.addEdges("se3", pairs, z, omega, std::nullopt); },
           "pairs"_a, "measurements"_a, "information"_a,
           "EDGE_SE3:QUAT: pairs (m, 2) [i j], measurements i_T_j (m, 7) or (m, 4, 4), information (6, 6) or (m, 6, 6).")
      .def("add_se2_edges",
           [](PyGraph& g, py::handle pairs, py::handle z, py::handle omega) { g.addEdges("se2", pairs, z, omega, std::nullopt); },
           "pairs"_a, "measurements"_a, "information"_a,
           "EDGE_SE2: pairs (m, 2), measurements i_T_j (m, 3) [x y theta], information (3, 3) or (m, 3, 3).")
      .def("add_se3_point_edges",
           [](PyGraph& g, py::handle pairs, py::handle z, py::handle omega, std::optional<int> offset_id) {
             g.addEdges("se3_point", pairs, z, omega, offset_id);
           },
           "pairs"_a, "measurements"_a, "information"_a, "offset_id"_a = py::none(),
           "EDGE_SE3_TRACKXYZ: pairs (m, 2) [pose point], measurements p_sensor (m, 3), information (3, 3) or (m, 3, 3).")
      .def("add_se3_priors",
           [](PyGraph& g, py::handle ids, py::handle z, py::handle omega, std::optional<int> offset_id) {
             g.addPriors("se3_prior", ids, z, omega, offset_id);
           },
           "ids"_a, "measurements"_a, "information"_a, "offset_id"_a = py::none(),
           "EDGE_SE3_PRIOR: ids (m,), measurements world_T_sensor (m, 7) or (m, 4, 4), information (6, 6) or (m, 6, 6).")
      .def("add_point_priors",
           [](PyGraph& g, py::handle ids, py::handle z, py::handle omega) { g.addPriors("point_prior", ids, z, omega, std::nullopt); },
           "ids"_a, "measurements"_a, "information"_a, "EDGE_POINTXYZ_PRIOR: ids (m,), measurements (m, 3), information (3, 3) or (m, 3, 3).")
      .def("add_sensor_offset", &PyGraph::addSensorOffset, "id"_a, "body_T_sensor"_a,
           "PARAMS_SE3OFFSET for se3 priors / point edges (offset_id); without one they use id 0 = identity.")
      .def("vertex_ids", &PyGraph::vertexIds, "kind"_a = py::none(), "Ids in increasing order, of one kind or all.")
      .def("vertex_kind", &PyGraph::vertexKind, "id"_a)
      .def("se3_estimates", [](const PyGraph& g, py::handle ids) { return g.estimates("se3", ids); }, "ids"_a = py::none(),
           "(n, 7) [x y z qx qy qz qw] (w >= 0); all se3 vertices when ids is None.")
      .def("se2_estimates", [](const PyGraph& g, py::handle ids) { return g.estimates("se2", ids); }, "ids"_a = py::none())
      .def("point_estimates", [](const PyGraph& g, py::handle ids) { return g.estimates("point", ids); }, "ids"_a = py::none())
      .def("set_se3_estimates", [](PyGraph& g, py::handle ids, py::handle p) { g.setEstimates("se3", ids, p); }, "ids"_a, "poses"_a)
      .def("set_se2_estimates", [](PyGraph& g, py::handle ids, py::handle p) { g.setEstimates("se2", ids, p); }, "ids"_a, "poses"_a)
      .def("set_point_estimates", [](PyGraph& g, py::handle ids, py::handle p) { g.setEstimates("point", ids, p); }, "ids"_a, "points"_a)
      .def("set_fixed", &PyGraph::setFixed, "ids"_a, "fixed"_a = true)
      .def("fixed_ids", [](const PyGraph& g) {
        std::vector<long long> ids;
        for (const auto& [id, vertex] : g.graph().vertices()) if (vertex->fixed()) ids.push_back(id);
        return py::array_t<long long>(static_cast<py::ssize_t>(ids.size()), ids.data());
      })
      .def("fix_gauge", &PyGraph::fixGauge, "choice"_a = "highest",
           "Fixes the highest- (default, as `dualgraph optimize --gauge highest`) or lowest-id vertex of the largest "
           "dimension unless something is fixed; returns its id or None.")
      .def("set_robust_kernel", &PyGraph::setRobustKernel, "spec"_a, "'none', 'huber:1.0', 'cauchy:d', 'tukey:d', 'dcs:d' on every edge.")
      .def("chi2", [](const PyGraph& g, bool robust) { return g.graph().chi2(robust); }, "robust"_a = false)
      .def("optimize",
           [](PyGraph& g, int max_iterations, const std::string& algorithm, const std::string& linear_solver,
              double relative_decrease_stop, double time_budget_ms, bool check, const std::string& damping) {
             return g.optimize({max_iterations, algorithm, linear_solver, relative_decrease_stop, time_budget_ms, check,
                                damping});
           },
           "max_iterations"_a = 100, "algorithm"_a = "lm", "linear_solver"_a = "cholmod", "relative_decrease_stop"_a = 1e-9,
           "time_budget_ms"_a = 0.0, "check"_a = true, "damping"_a = "identity",
           "Levenberg-Marquardt ('lm') or Gauss-Newton ('gn') with CHOLMOD or Eigen; raises OptimizationError when the "
           "result is not usable (unless check=False).")
      .def("marginal", [](PyGraph& g, int id, bool metric) { return g.marginals(py::int_(id), metric); }, "id"_a,
           "metric"_a = false,
           "Marginal covariance of one vertex in its tangent space (se3: g2o's [dt; dq]; metric=True gives [dt; dtheta]).")
      .def("marginals", &PyGraph::marginals, "ids"_a, "metric"_a = false,
           "Joint marginal covariance of several vertices, blocks in the order of ids; fixed vertices are zero.");

  m.def("information_metric_to_g2o", [](py::handle omega) { return matrixArray(informationMetricToG2o(toMatrix(omega, "information", 6, 6))); },
        "information"_a, "Metric [t; theta] information (6, 6) -> EDGE_SE3:QUAT units (rotation rows/columns x2).");
  m.def("covariance_g2o_to_metric", [](py::handle sigma) { return matrixArray(covarianceG2oToMetric(toMatrix(sigma, "covariance", 6, 6))); },
        "covariance"_a, "VertexSE3 marginal in g2o's [dt; dq] -> metric [dt; dtheta].");
  m.def("pose_to_matrix", [](py::handle pose) { return poseMatrix(toPose(pose, "pose")); }, "pose"_a,
        "[x y z qx qy qz qw] (or 4x4) -> (4, 4).");
  m.def("matrix_to_pose", [](py::handle pose) { return poseArray(toPose(pose, "pose")); }, "pose"_a,
        "4x4 (or [x y z qx qy qz qw]) -> (7,) with w >= 0.");
}

}  // namespace dualgraph::python
