// SPDX-License-Identifier: MIT
// The `dualgraph` Python module: the graph engine (g2o files, numpy batches, LM/GN with CHOLMOD, marginal
// covariances), the Localizer, and the frontend's sequence run. No library call raises C++ exceptions into
// Python: every Status becomes a dualgraph.Error subclass carrying the library's message.
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "errors.h"

#ifndef DUALGRAPH_VERSION
#define DUALGRAPH_VERSION "unknown"
#endif

PYBIND11_MODULE(dualgraph, m) {
  m.doc() = "dualgraph: drift-corrected localisation with a dual pose graph, on a g2o-style graph engine.";
  m.attr("__version__") = DUALGRAPH_VERSION;
  dualgraph::python::registerExceptions(m);
  dualgraph::python::bindGraph(m);
  dualgraph::python::bindLocalizer(m);
  dualgraph::python::bindFrontend(m);
  dualgraph::python::bindPipeline(m);
  dualgraph::python::bindEvaluation(m);
}
