// SPDX-License-Identifier: MIT
// The parts of the `dualgraph` Python module (module.cpp calls them in this order).
#pragma once

#include <pybind11/pybind11.h>

namespace dualgraph::python {

/// Graph, OptimizeSummary, the SE(3) unit helpers (graph_bindings.cpp).
void bindGraph(pybind11::module_& m);
/// LocalizerParams, GateObservation, Localizer (localizer_bindings.cpp).
void bindLocalizer(pybind11::module_& m);
/// RunConfig, Sequence, GateFrontend, run_sequence (frontend_bindings.cpp).
void bindFrontend(pybind11::module_& m);
/// dualgraph.StreamingLocalizer (pipeline_bindings.cpp).
void bindPipeline(pybind11::module_& m);
/// TrajectoryMetrics, evaluate_trajectory, read_trajectory (evaluation_bindings.cpp).
void bindEvaluation(pybind11::module_& m);

}  // namespace dualgraph::python
